#!/usr/bin/env bash
# Interleaved A/B speed comparison of two riffle builds on one machine (a code reorganisation's acceptance: same or
# better speed on the seed scene and the dry DEM benchmark). On the 2-vCPU machines, 2-thread timings of one binary vary
# between runs by up to 1.8x, so one run proves nothing: every benchmark runs A, B, A, B, ... and the report gives per
# build the median, min, max and spread ((max - min) / median) of the repetitions, and the ratio of the medians B / A.
#
#   tools/ab.sh <build-dir-A> <build-dir-B> [reps]          reps defaults to 5
#
# Benchmarks, each at $THREADS (default 2) threads:
#   seed    scenes/oscillating_tank_quick.toml --until $SEED_UNTIL (default 0.3 s: 300 coupled steps)
#   dem     scenes/dry_shaken_tank.toml --until $DEM_UNTIL (default 0.05 s: 50 engine steps x 100 DEM sub-steps of the
#           settled seed bed, shaken dry; what tools/bench_dem.sh times)
#   engine  riffle_bench_engine --side 40 --steps 100 (64,000 free-flying grains; what tools/bench.sh times)
# The time reported for seed and dem is riffle's "stepping (wall)" (the time loop, without reading the scene and the
# checkpoint); for engine it is the benchmark's own wall time. The binaries are copied to the work folder first, so
# a rebuild during the runs changes nothing. Both builds' seed and dem runs are checked to end in byte-identical
# checkpoints ("same" in the report); a "no" there means the builds differ in physics, not only in speed. Each run
# prints the 1-minute load average after it: runs beside other jobs (load above the 2 cores) are slower and noisier.
# The seed and dem scenes start from the settled seed bed: $SETTLED, else out/dry_bed_settle/checkpoints/final.ckpt
# of this source tree, else it is settled once with build A (about 3 minutes). OWN_BEDS=1 settles one bed with each
# build instead and runs each build from its own (a change of the grains' slot order at the rebuilds, or of the
# checkpoint format, shows only in a bed the build settled itself, as a user's fresh clone does; the beds are then
# different packings of the same scene and "same" is not judged). Work folder: $WORK (default a new
# temporary folder, removed at the end unless KEEP=1). Nothing is written into the source tree.
set -euo pipefail
# The whole script is one function, read before it runs: editing the file during a run cannot change that run.
main() {
if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  sed -n '2,24p' "$0" >&2
  exit 1
fi
SRC=$(cd "$(dirname "$0")/.." && pwd)
reps=${3:-5}
threads=${THREADS:-2}
seed_until=${SEED_UNTIL:-0.3}
dem_until=${DEM_UNTIL:-0.05}
work=${WORK:-$(mktemp -d /tmp/riffle_ab.XXXXXX)}
mkdir -p "$work/scenes" "$work/out/dry_bed_settle/checkpoints" "$work/A" "$work/B"
work=$(cd "$work" && pwd)
for side in A B; do
  dir=$1
  [ "$side" = B ] && dir=$2
  for exe in riffle riffle_bench_engine; do
    [ -x "$dir/$exe" ] || { echo "ab: $dir/$exe not found (build it: cmake --build $dir --target $exe)" >&2; exit 1; }
    cp "$dir/$exe" "$work/$side/$exe"
  done
done
cp "$SRC/scenes/oscillating_tank_quick.toml" "$SRC/scenes/dry_shaken_tank.toml" "$SRC/scenes/dry_bed_settle.toml" \
  "$work/scenes/"
cd "$work"
settled=out/dry_bed_settle/checkpoints/final.ckpt
own_beds=${OWN_BEDS:-0}
# The folder a side's seed and dem runs start in (their scenes read the settled bed by a relative path).
bed_dir() { if [ "$own_beds" = 1 ]; then echo "$work/bed_$1"; else echo "$work"; fi; }
if [ "$own_beds" = 1 ]; then
  for side in A B; do
    mkdir -p "bed_$side/out/dry_bed_settle"
    cp -r scenes "bed_$side/"
    echo "ab: settling the seed bed with build $side (scenes/dry_bed_settle.toml, about 3 minutes)" >&2
    (cd "bed_$side" && "$work/$side/riffle" run scenes/dry_bed_settle.toml --out out/dry_bed_settle --threads "$threads" \
      --log-level warn >"$work/settle_$side.log" 2>&1)
  done
elif [ -n "${SETTLED:-}" ]; then
  cp "$SETTLED" "$settled"
elif [ -f "$SRC/$settled" ]; then
  cp "$SRC/$settled" "$settled"
else
  echo "ab: settling the seed bed with build A (scenes/dry_bed_settle.toml, about 3 minutes)" >&2
  A/riffle run scenes/dry_bed_settle.toml --out out/dry_bed_settle --threads "$threads" --log-level warn >settle.log 2>&1
fi

stepping_wall() { awk '$1 == "stepping" && $2 == "(wall)" { print $3 }' "$1"; }

# One timed run: run_one <side> <bench> <rep>; appends "bench side rep seconds same" to results.txt.
run_one() {
  local side=$1 bench=$2 rep=$3 out=$work/run_$2_$1_$3 seconds same=-
  case $bench in
    seed | dem)
      local scene=scenes/oscillating_tank_quick.toml until=$seed_until
      [ "$bench" = dem ] && scene=scenes/dry_shaken_tank.toml && until=$dem_until
      (cd "$(bed_dir "$side")" && "$work/$side/riffle" run "$scene" --until "$until" --threads "$threads" --out "$out") \
        >"$out.log" 2>&1 || { echo "ab: $side/riffle run $scene failed, see $out.log" >&2; exit 1; }
      seconds=$(stepping_wall "$out.log")
      if [ "$side" = B ] && [ "$own_beds" != 1 ]; then
        cmp -s "$out/checkpoints/final.ckpt" "$work/run_${bench}_A_$rep/checkpoints/final.ckpt" && same=yes || same=no
      fi
      ;;
    engine)
      "$side/riffle_bench_engine" --side 40 --steps 100 --threads "$threads" >"$out.log" 2>&1 ||
        { echo "ab: $side/riffle_bench_engine failed, see $out.log" >&2; exit 1; }
      seconds=$(awk 'NR == 1 { for (k = 1; k < NF; ++k) if ($k == "wall") print $(k + 1) }' "$out.log")
      ;;
  esac
  [ -n "$seconds" ] || { echo "ab: no timing in $out.log" >&2; exit 1; }
  echo "$bench $side $rep $seconds $same" >>results.txt
  printf '  %-6s %s rep %-2s %9.3f s  same as A: %-3s  load %s\n' "$bench" "$side" "$rep" "$seconds" "$same" \
    "$(cut -d' ' -f1 /proc/loadavg)"
}

echo "# A = $1"
echo "# B = $2"
cpu="$(lscpu | sed -n 's/^Model name: *//p') (family $(lscpu | sed -n 's/^CPU family: *//p'), model $(lscpu | sed -n 's/^Model: *//p'))"
echo "# machine: $(nproc) cores, $cpu; $threads threads; $reps repetitions A,B,A,B,..."
echo "# seed: oscillating_tank_quick --until $seed_until; dem: dry_shaken_tank --until $dem_until;" \
  "engine: riffle_bench_engine --side 40 --steps 100"
echo "# load at start:$(uptime | sed 's/.*load average://')"
: >results.txt
for rep in $(seq "$reps"); do
  for bench in seed dem engine; do
    run_one A "$bench" "$rep"
    run_one B "$bench" "$rep"
  done
done
echo "# load at end:$(uptime | sed 's/.*load average://')"
/usr/bin/python3 - results.txt <<'EOF'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
print(f"{'bench':<7} {'build':<5} {'median [s]':>10} {'min [s]':>9} {'max [s]':>9} {'spread':>7}   B/A median")
for bench in ("seed", "dem", "engine"):
    medians = {}
    for side in ("A", "B"):
        times = [float(r[3]) for r in rows if r[0] == bench and r[1] == side]
        median = statistics.median(times)
        medians[side] = median
        spread = (max(times) - min(times)) / median
        ratio = f"{medians['B'] / medians['A']:.3f}" if side == "B" else ""
        print(f"{bench:<7} {side:<5} {median:>10.3f} {min(times):>9.3f} {max(times):>9.3f} {100 * spread:>6.1f}%   {ratio}")
    same = {r[4] for r in rows if r[0] == bench and r[1] == "B"}
    if same - {"-"}:
        print(f"{'':<7} final checkpoints byte-identical A vs B: {'yes' if same == {'yes'} else 'NO'}")
EOF
cd /
[ "${KEEP:-0}" = 1 ] || [ -n "${WORK:-}" ] || rm -rf "$work"
}
main "$@"
exit $?
