#!/usr/bin/env bash
# Engine benchmarks at 1 and 2 threads. Results go to docs/BENCHMARKS.md by hand, with this command beside them.
#   tools/bench.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
echo "# machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p')"
echo "## throughput: 64,000 free-flying grains, 100 engine steps x 10 sub-steps"
for threads in 1 2; do "$build/riffle_bench_engine" --side 40 --steps 100 --threads "$threads"; done
echo "## per-step overhead of the three flow graphs: 8 grains, 2000 engine steps x 10 sub-steps"
for threads in 1 2; do "$build/riffle_bench_engine" --side 2 --steps 2000 --threads "$threads" | head -1; done
