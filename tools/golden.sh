#!/usr/bin/env bash
# The bit-identity check of a code reorganisation: run the quick seed scene for its 5 periods and the dam break to its
# end, and print the sha256 of the outputs that must not change when the code is reorganised. Run it with the binary
# before and after a change and compare the two listings (`diff`): any differing line is a physics change.
#
#   tools/golden.sh <riffle-binary> <work-dir>          prints "sha256  name" lines on stdout
#
#   (a) scenes/oscillating_tank_quick.toml, 5 periods (its end_time, 2.94118 s), --threads 2, into <work-dir>/quick:
#       class_centroids.csv, bed_profile.csv, probe_fluid_totals.csv, diagnostics.csv, checkpoints/final.ckpt
#   (b) scenes/dam_break.toml --until 0.45 (its end_time, 0.6 s, is not reached: see DAM_UNTIL), --threads 2,
#       into <work-dir>/dam:
#       diagnostics.csv, checkpoints/final.ckpt
#
# Wall-clock columns (step_wall_s, wall_<system>_s) are removed from diagnostics.csv by header name before hashing:
# they differ between any two runs. The other CSVs carry no timing. timings.csv and riffle.log are not hashed.
# GOLDEN_DROP="name ..." leaves out further diagnostics and fluid-totals columns by name (for a documented change of
# one column, e.g. solid_dt_s once it prints the sub-step actually used): state it beside the hashes. Against a build
# that kept escaped particles (no escaped-particle columns): GOLDEN_DROP="fluid_removed_particles fluid_removed_mass_kg
# removed_particles removed_mass_kg removed_volume_m3"; against one without the removals by reason:
# GOLDEN_DROP="fluid_removed_left_domain fluid_removed_lone_droplets removed_left_domain removed_lone_droplets".
# Against a build before the drag's step limit
# (the drag_rate_1_s column): GOLDEN_DROP="drag_rate_1_s".
# final.ckpt holds no timestamp (scene file name and text, world, output schedule), so it is hashed whole; the file
# name stored in it is the relative one given on the command line, which is why every run starts in <work-dir> with
# the scenes copied there. A change of the checkpoint format changes its hash without any physics change: compare
# the CSVs first.
#
# The quick scene starts from the settled seed bed, ../out/dry_bed_settle/checkpoints/final.ckpt relative to the
# scene. It is taken, in this order, from $GOLDEN_SETTLED (a path to a final.ckpt), from out/dry_bed_settle/ of the
# source tree this script belongs to, or else settled here with the binary under test (scenes/dry_bed_settle.toml,
# about 3 minutes on 2 threads; then its final.ckpt is hashed too). Its sha256 is printed as "settled_input.ckpt",
# so that two listings made from different beds are seen to differ at their input. Nothing is written into the
# source tree.
#
# Measured (2 vCPU AMD EPYC, 2 threads, base 7c2e891): see docs/BENCHMARKS.md ("Golden check").
set -u
# The whole script is one function, read before it runs: editing the file during a run cannot change that run.
main() {
if [ $# -ne 2 ]; then
  echo "usage: $0 <riffle-binary> <work-dir>" >&2
  exit 1
fi
RIFFLE=$(realpath "$1") || exit 1
WORK=$2
SRC=$(cd "$(dirname "$0")/.." && pwd)
PY=/usr/bin/python3
THREADS=2
# The dam break's end_time is 0.6 s, but at 7c2e891 the run stops at t = 0.495 s (exit 3): a spray particle leaves the
# domain's top (0.6 m, domain_margin 0.3 m above the 0.3 m tank). 0.45 s covers the collapse, the impact on the far
# wall and the run-up (the front reaches the wall at T = 3.6, t = 0.26 s) and ends before that.
DAM_UNTIL=0.45

rm -rf "$WORK" && mkdir -p "$WORK/scenes" "$WORK/out/dry_bed_settle/checkpoints" || exit 1
WORK=$(cd "$WORK" && pwd)
cp "$SRC/scenes/oscillating_tank_quick.toml" "$SRC/scenes/dam_break.toml" "$SRC/scenes/dry_bed_settle.toml" \
  "$WORK/scenes/" || exit 1
settled="$WORK/out/dry_bed_settle/checkpoints/final.ckpt"
cd "$WORK" || exit 1

run() {  # run <name> <riffle run arguments...>: fail loudly with the log's tail
  local name=$1
  shift
  local rc=0
  "$RIFFLE" run "$@" --threads "$THREADS" >"$WORK/$name.log" 2>&1 || rc=$?
  if [ "$rc" -ne 0 ]; then
    echo "golden: riffle run $* failed (exit $rc); last lines of $WORK/$name.log:" >&2
    tail -n 5 "$WORK/$name.log" >&2
    exit 1
  fi
}

# Hash a CSV without its wall-clock columns (chosen by header name, so a reordering of columns cannot hide one).
hash_csv_without_timing() {
  "$PY" - "$1" <<'EOF' | sha256sum | cut -d' ' -f1
import csv, os, re, sys
timing = re.compile(r"^(step_wall_s|wall_.*_s)$")
extra = os.environ.get("GOLDEN_DROP", "").split()
with open(sys.argv[1], newline="") as f:
    rows = csv.reader(f)
    header = next(rows)
    dropped = [name for name in header if timing.match(name) or name in extra]
    keep = [k for k, name in enumerate(header) if name not in dropped]
    print(f"golden: {sys.argv[1]}: left out {len(dropped)} columns"
          f" ({len([d for d in dropped if d in extra])} named in GOLDEN_DROP)", file=sys.stderr)
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow([header[k] for k in keep])
    for row in rows:
        out.writerow([row[k] for k in keep])
EOF
}

print_hash() {  # print_hash <file> <name>
  [ -f "$1" ] || { echo "golden: missing $1" >&2; exit 1; }
  echo "$(sha256sum "$1" | cut -d' ' -f1)  $2"
}

# (0) The settled bed the quick scene starts from.
if [ -n "${GOLDEN_SETTLED:-}" ]; then
  cp "$GOLDEN_SETTLED" "$settled" || exit 1
elif [ -f "$SRC/out/dry_bed_settle/checkpoints/final.ckpt" ]; then
  cp "$SRC/out/dry_bed_settle/checkpoints/final.ckpt" "$settled" || exit 1
else
  echo "golden: no settled bed in $SRC/out; settling it with $RIFFLE" >&2
  run settle scenes/dry_bed_settle.toml --out out/dry_bed_settle
fi
print_hash "$settled" settled_input.ckpt

# (a) The quick seed scene, 5 periods.
start=$(date +%s)
run quick scenes/oscillating_tank_quick.toml --out quick
echo "golden: quick seed scene took $(($(date +%s) - start)) s" >&2
for f in class_centroids.csv bed_profile.csv; do print_hash "quick/$f" "quick/$f"; done
# Through the column filter, so that GOLDEN_DROP can leave out columns a change appended (escaped particles' removed_*).
echo "$(hash_csv_without_timing quick/probe_fluid_totals.csv)  quick/probe_fluid_totals.csv (filtered)"
echo "$(hash_csv_without_timing quick/diagnostics.csv)  quick/diagnostics.csv (without wall-clock columns)"
print_hash quick/checkpoints/final.ckpt quick/checkpoints/final.ckpt

# (b) The dam break to t = 0.45 s.
start=$(date +%s)
run dam scenes/dam_break.toml --out dam --until "$DAM_UNTIL"
echo "golden: dam break took $(($(date +%s) - start)) s" >&2
echo "$(hash_csv_without_timing dam/diagnostics.csv)  dam/diagnostics.csv (without wall-clock columns)"
print_hash dam/checkpoints/final.ckpt dam/checkpoints/final.ckpt
}
main "$@"
exit $?
