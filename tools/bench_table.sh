#!/usr/bin/env bash
# The figures of docs/BENCHMARKS.md's table, measured at one commit: the dry DEM (the settled seed bed shaken, 50
# engine steps x 100 sub-steps), the quick seed scene and the full seed scene (300 steps each from the settled bed)
# and the dam break (to t = 0.3 s), each at 1 and 2 threads, REPS repetitions interleaved (rep 1 of every case, then
# rep 2, ...). Prints a markdown table: the median of riffle's "stepping" wall time converted to the row's unit, and
# the range over the repetitions, headed by the commit, the date, the CPU and the load.
#   tools/bench_table.sh [build-dir] [reps]          defaults: build, 3
# Needs out/dry_bed_settle/checkpoints/final.ckpt (build/riffle run scenes/dry_bed_settle.toml). Run it on an
# otherwise idle machine: each repetition prints the 1-minute load average to stderr.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath "${1:-build}")
reps=${2:-3}
[ -f out/dry_bed_settle/checkpoints/final.ckpt ] ||
  { echo "bench_table: no settled bed: run $build/riffle run scenes/dry_bed_settle.toml first" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$build/riffle" "$work/riffle"  # a rebuild during the runs changes nothing
# name|scene|until|factor|unit: value = factor / stepping_s (a rate) when factor > 0, else stepping_s * -factor
cases=(
  "dem|scenes/dry_shaken_tank.toml|0.05|40810000|particle-steps/s (8,162 grains x 5,000 sub-steps)"
  "quick|scenes/oscillating_tank_quick.toml|0.3|-3.3333333|ms a step (300 steps)"
  "full|scenes/oscillating_tank.toml|0.3|-3.3333333|ms a step (300 steps)"
  "dam|scenes/dam_break.toml|0.3|-1|s of stepping to t = 0.3 s"
)
for rep in $(seq 1 "$reps"); do
  for entry in "${cases[@]}"; do
    IFS='|' read -r name scene until factor unit <<<"$entry"
    for threads in 1 2; do
      out="$work/$name-$threads-$rep"
      "$work/riffle" run "$scene" --until "$until" --threads "$threads" --out "$out" --log-level warn >/dev/null
      stepping=$(awk -F, '$1 == "stepping" { print $4 }' "$out/timings.csv")
      echo "$name $threads $stepping" >>"$work/times"
      echo "bench_table: rep $rep $name $threads threads: stepping $stepping s, load $(cut -d' ' -f1 /proc/loadavg)" >&2
      rm -rf "$out"
    done
  done
done
echo "Commit $(git rev-parse --short HEAD), $(date -u +%Y-%m-%d), $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) CPUs, $reps repetitions interleaved: median [min-max]."
echo
echo "| benchmark | 1 thread | 2 threads | unit |"
echo "|---|---|---|---|"
for entry in "${cases[@]}"; do
  IFS='|' read -r name scene until factor unit <<<"$entry"
  cells=()
  for threads in 1 2; do
    cells+=("$(/usr/bin/python3 -c '
import statistics, sys
name, threads, factor = sys.argv[1], sys.argv[2], float(sys.argv[3])
values = sorted(factor / float(s) if factor > 0 else float(s) * -factor
                for n, t, s in (line.split() for line in open(sys.argv[4])) if n == name and t == threads)
print("%.3g [%.3g-%.3g]" % (statistics.median(values), values[0], values[-1]))' "$name" "$threads" "$factor" "$work/times")")
  done
  echo "| $name: \`$scene --until $until\` | ${cells[0]} | ${cells[1]} | $unit |"
done
