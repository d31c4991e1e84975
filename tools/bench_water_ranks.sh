#!/usr/bin/env bash
# MPS water on one rank against two (docs/SCALING.md, "Water over ranks"): a scene run, interleaved, as
#   one rank of 2 threads with the in-house two-level PCG, one rank of 2 threads with hypre's BoomerAMG-PCG,
#   2 ranks of 1 thread with the in-house PCG over both (the default), the same with hypre over both, and 2 ranks of
#   2 threads (in-house),
# REPS times; prints each run's wall and user seconds, steps, stepping seconds and rank 0's pressure solve a step.
#   tools/bench_water_ranks.sh SCENE UNTIL [REPS] [--set KEY=VALUE ...]
#   tools/bench_water_ranks.sh scenes/dam_break.toml 0.1 3
#   tools/bench_water_ranks.sh scenes/dam_break.toml 0.03 2 --set fluid.spacing=0.0025
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1 until=$2 reps=${3:-3}
shift $(($# < 3 ? $# : 3))
riffle=${RIFFLE:-build/riffle}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_mpi_yield_when_idle=1
grep -m1 "model name" /proc/cpuinfo || true
for rep in $(seq "$reps"); do
  for variant in two_level boomeramg ranks2 ranks2_hypre ranks2x2; do
    out=$work/$variant
    rm -rf "$out"
    case $variant in
      two_level | boomeramg)
        command=("$riffle" run "$scene" --out "$out" --until "$until" --threads 2 "$@"
                 --set "fluid.preconditioner=\"$variant\"") ;;
      ranks2) command=(mpirun -n 2 "$riffle" run "$scene" --out "$out" --until "$until" --threads 1 "$@") ;;
      ranks2_hypre)
        command=(mpirun -n 2 "$riffle" run "$scene" --out "$out" --until "$until" --threads 1 "$@"
                 --set 'fluid.preconditioner="boomeramg"') ;;
      ranks2x2) command=(mpirun -n 2 "$riffle" run "$scene" --out "$out" --until "$until" --threads 2 "$@") ;;
    esac
    /usr/bin/time -f "%e %U" -o "$work/time" "${command[@]}" >/dev/null 2>&1
    stepping=$(grep -o -m1 "stepping (wall) *[0-9.]*" "$out/riffle.log" | awk '{print $NF}')
    steps=$(tail -1 "$out/diagnostics.csv" | cut -d, -f1)
    pressure=$(grep "^fluid_pressure " "$out/riffle.log" | head -1 | awk '{print $5}')
    echo "rep $rep $variant: wall, user $(cat "$work/time") s; $steps steps; stepping $stepping s; pressure $pressure ms a step"
  done
done
