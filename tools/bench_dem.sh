#!/usr/bin/env bash
# The DEM benchmark: the settled seed bed (8,162 grains) shaken dry, E = 1e8 Pa, nu = 0.3, e = 0.5,
# mu = 0.4, sub-step 1e-5 s, for a fixed number of sub-steps, at 1 and 2 threads. Prints riffle's timing table
# (particle-steps per second per system) for each. Results go to docs/BENCHMARKS.md with this command.
#   tools/bench_dem.sh [build-dir] [engine-steps]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
steps=${2:-50}   # engine steps of 1 ms = 100 sub-steps each
settled=out/dry_bed_settle/checkpoints/final.ckpt
if [ ! -f "$settled" ]; then
  echo "bench_dem: settling the seed bed first (scenes/dry_bed_settle.toml, a few minutes)"
  "$build/riffle" run scenes/dry_bed_settle.toml --log-level warn
fi
until=$(awk -v n="$steps" 'BEGIN { printf "%.6f", n * 1e-3 }')
echo "# machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); $steps engine steps x 100 sub-steps"
for threads in 1 2; do
  out=$(mktemp -d)
  "$build/riffle" run scenes/dry_shaken_tank.toml --until "$until" --threads "$threads" --out "$out" \
    --log-level warn
  echo "## threads $threads"
  column -s, -t < "$out/timings.csv"
  rm -rf "$out"
done
