#!/usr/bin/env bash
# `riffle check` and `riffle graph` answer from the scene's model alone: they read and validate the scene, build its
# systems and step graph on an unlaid World and estimate its budget, but lay out no grain, particle or grid array and
# generate no bed (the model keeps a bed's classes; a run generates it when it starts).
# So a scene that needs more memory than the process may have is still checked (a run would refuse or die at set-up),
# and the counts check prints are the ones a run lays out.
#   tests/cli/test_check_model_only.sh <riffle-binary> <source-dir> <work-dir>
# Prints one "ok - ..." / "not ok - ..." line per check, then "N passed, M failed"; exits 1 if any failed.
set -u
RIFFLE=$(realpath "$1") SRC=$(realpath "$2") WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 2
passed=0 failed=0
report() {  # report DESCRIPTION STATUS
  if [ "$2" -eq 0 ]; then echo "ok - $1"; passed=$((passed + 1)); else echo "not ok - $1"; failed=$((failed + 1)); fi
}

# 12.5 million water particles (33.8 GiB estimated for a run): laid out, they need about 2 GB before the first
# neighbour list; check and graph run under a 1.5 GB address-space limit.
cat > big_water.toml <<'TOML'
[run]
name = "big_water"
end_time = 0.01
dt = 0.001

[materials.grain]
density = 2500.0
young_modulus = 1.0e7
poisson_ratio = 0.3

[tank]
size = [1.0, 1.0, 1.0]
wall_material = "grain"

[fluid]
spacing = 0.004

[[fluid.boxes]]
low = [0.0, 0.0, 0.0]
high = [1.0, 1.0, 0.8]
TOML
(ulimit -v 1500000; "$RIFFLE" check big_water.toml --memory-limit 100 > big_check.out 2> big_check.err)
report "check answers on a scene too large to lay out in 1.5 GB (exit $?)" $?
grep -q "fluid: 13652216 MPS particles, 12500000 of them fluid" big_check.out
report "... and prints the particle counts of its boxes and tank walls" $?
(ulimit -v 1500000; "$RIFFLE" graph big_water.toml --memory-limit 100 > big_graph.out 2> big_graph.err)
report "graph answers on the same scene (exit $?)" $?
grep -q "^digraph" big_graph.out
report "... with the step graph as DOT" $?
"$RIFFLE" run big_water.toml > big_run.out 2> big_run.err
[ $? -eq 2 ] && grep -q "memory" big_run.err
report "a run of it is refused by the memory budget (exit 2), before anything is laid out" $?

# A layered bed of 1,958,880 grains (tests/data/check_big_bed.toml): check counts it from its classes and does not
# generate it (generating it, which check did while reading the scene, took 231 s and 416 MB on a loaded 2-core
# machine; answering from the classes takes 0.06 s and 15 MB). Allowed 2 s here, for a machine busy with other work.
start_ns=$(date +%s%N)
timeout 60 "$RIFFLE" check "$SRC/tests/data/check_big_bed.toml" > bed_check.out 2> bed_check.err
rc=$?
elapsed_ms=$(( ($(date +%s%N) - start_ns) / 1000000 ))
report "check answers on a 2e6-grain layered bed (exit $rc)" $rc
[ "$elapsed_ms" -lt 2000 ]
report "... in well under the time generating it takes (${elapsed_ms} ms)" $?
grep -q "valid scene 'check_big_bed': 1958880 grains" bed_check.out &&
  grep -q "1958880 in layered beds and fills" bed_check.out && grep -q "grains 1.95888e+06" bed_check.out
report "... and prints the bed's grain count, from its classes, in the summary and the budget" $?

# A bed whose random grains jam passes check (only generating it shows a jam) and is refused when a run generates
# it, at the key, as the scene reader names its problems, before anything is written.
jam=(--set 'solids.layered_beds[0].loose_factor=1.2')
"$RIFFLE" check "$SRC/scenes/dry_bed_settle.toml" "${jam[@]}" > jam_check.out 2> jam_check.err
report "check passes the seed bed loosened too little to generate (exit $?)" $?
"$RIFFLE" run "$SRC/scenes/dry_bed_settle.toml" "${jam[@]}" --out jam_run > jam_run.out 2> jam_run.err
rc=$?
[ "$rc" -eq 2 ] && [ ! -e jam_run ] &&
  grep -q "dry_bed_settle.toml:[0-9]*:[0-9]*: solids.layered_beds\[0\].classes\[2\].count: random sequential addition placed only" jam_run.err
report "a run of it is refused when it generates the bed (exit $rc), naming the class's count, writing nothing" $?

# The counts check prints are those a run lays out: a periodic box of water under a lid (no walls on the periodic
# faces).
"$RIFFLE" check "$SRC/scenes/sheared_water_block.toml" > block_check.out 2> block_check.err
report "check on the sheared water block (exit $?)" $?
check_fluid=$(sed -n 's/.*fluid: [0-9]* MPS particles, \([0-9]*\) of them fluid.*/\1/p' block_check.out)
"$RIFFLE" run "$SRC/scenes/sheared_water_block.toml" --until 0.0005 --threads 1 --out block_run > /dev/null 2>&1
run_fluid=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "fluid_particles") c = i } NR == 2 { print $c }' \
  block_run/diagnostics.csv)
[ -n "$check_fluid" ] && [ "$check_fluid" = "$run_fluid" ]
report "check's fluid count ($check_fluid) is the run's ($run_fluid)" $?

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
