#!/usr/bin/env bash
# A/B timing of fluid changes in the sloshing tank's violent stage (docs/BENCHMARKS.md, fifth pass): resumes the
# same checkpoint with each binary in turn, interleaved, and prints per step the time of the main fluid systems, the
# stepping wall time, the mean PCG iterations and whether the final states are byte-identical to the first binary's.
#   tools/bench_fluid_ab.sh BINARY_A [BINARY_B ...]
# Environment: UNTIL (default 2.05: 50 steps from t = 2.0 s), THREADS (default 1: the quietest on a shared machine;
# 2 threads vary by about 10 % from run to run), REPEATS (default 2), WORK (default /tmp/riffle_bench_ab: the
# t = 2.0 s checkpoint is made there once, with the first binary, in about 90 s on 2 threads).
# Copy the binaries out of the build directory first (cp build/riffle /tmp/riffle_a): they must not change between
# runs. Compare two builds only when the gap is larger than the code-placement effect that BENCHMARKS describes.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || { sed -n '2,11p' "$0"; exit 1; }
work=${WORK:-/tmp/riffle_bench_ab}
until=${UNTIL:-2.05}
threads=${THREADS:-1}
repeats=${REPEATS:-2}
base=$work/base/checkpoints/final.ckpt
mkdir -p "$work"
if [ ! -f "$base" ]; then
  echo "bench_fluid_ab: making the t = 2.0 s checkpoint with $1"
  "$1" run scenes/sloshing_tank.toml --until 2.0 --threads 2 --out "$work/base" > "$work/base.log" 2>&1
fi
echo "# $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); resume t = 2.0 -> $until s, $threads thread(s); $(uptime)"
printf '%-28s %6s %8s %8s %8s %8s %8s %8s %8s %s\n' binary run predict search free_surf pressure correct step_ms pcg_it same
for repeat in $(seq "$repeats"); do
  index=0
  for binary in "$@"; do
    out=$work/run_${index}_$repeat
    rm -rf "$out"
    "$binary" resume "$base" --until "$until" --threads "$threads" --out "$out" > "$out.log" 2>&1 ||
      { echo "bench_fluid_ab: $binary failed, see $out.log" >&2; exit 1; }
    same=-
    if [ "$index" -gt 0 ]; then
      cmp -s "$out/checkpoints/final.ckpt" "$work/run_0_$repeat/checkpoints/final.ckpt" && same=yes || same=no
    fi
    # mean [ms] of a system from the timer table; stepping [s] over the steps taken
    read -r predict search free_surface pressure correct step_ms < <(awk '
      $1 == "fluid_predict" { p = $5 } $1 == "fluid_neighbours_predicted" { n = $5 } $1 == "fluid_free_surface" { f = $5 }
      $1 == "fluid_pressure" { q = $5 } $1 == "fluid_correct" { c = $5 } $1 == "fluid" && $2 == "step" && $3 == "graph" { calls = $5 }
      $1 == "stepping" { s = $3 } END { printf "%s %s %s %s %s %.3f\n", p, n, f, q, c, 1000 * s / calls }' "$out.log")
    iterations=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "ppe_iterations") k = i; next }
      $2 > 2.0 { sum += $k; ++rows } END { printf "%.2f", rows ? sum / rows : 0 }' "$out/diagnostics.csv")
    printf '%-28s %6s %8s %8s %8s %8s %8s %8s %8s %s\n' "$(basename "$binary")" "$repeat" "$predict" "$search" \
      "$free_surface" "$pressure" "$correct" "$step_ms" "$iterations" "$same"
    index=$((index + 1))
  done
done
