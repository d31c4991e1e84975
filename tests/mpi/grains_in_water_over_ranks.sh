#!/usr/bin/env bash
# `mpirun -np N riffle run|resume` for grains in MPS water (the grains spread by grain_ranks, the water by
# fluid_ranks, each over its own boxes, and the coupling reading across the ranks' edges: coupling_ranks.hpp, the
# water the grains sample, their voidage, the drag handed back to the water): tests/data/shaken_bed_in_water.toml
# (520 grains of 4 and 6 mm sinking into 5 cm of water, l0 = 5 mm, a tank shaken at 5 mm and 4 Hz) on 2 and 4 ranks
# against 1, particle by particle and grain by grain (matched by id) in its ParaView frames; a checkpoint of 2 ranks
# resumed on 1 and 3; `riffle check` saying it can be spread; lubrication across the ranks' edges on 2 ranks
# against 1 (hypre's solve); a periodic bed under a lid (seed 003's options) on 2 and 4 ranks; a scene of grains
# without contacts refused with its reason.
#
# Tolerances: as tests/mpi/water_over_ranks.sh says, one rank and the ranks both solve the pressure (the in-house CG
# or hypre) to |r| <= 1e-8 |b| at other iterates, so each step's pressures differ by about that fraction; the
# grains' drag and buoyancy follow, and a dense bed amplifies any difference about tenfold every 10 ms
# (docs/SCALING.md). The bounds (positions 1e-7 m = 2e-5 l0, velocities and drag 1e-4 of the largest, pressures 1e-5
# of the largest) are far above that over these 0.1 s and far below what a coupling that misses a grain or a fluid
# particle across an edge gives (a grain whose voidage or sampled water is wrong feels a drag off by a tenth or more
# at once).
#   tests/mpi/grains_in_water_over_ranks.sh RIFFLE MPIEXEC SOURCE_DIR WORK_DIR
set -u
RIFFLE=$1 MPIEXEC=$2 SRC=$3 WORK=$4
RANKS_TIMEOUT=240
source "$SRC/tests/mpi/over_ranks_common.sh"
compare() { /usr/bin/python3 "$SRC/tests/mpi/compare_fluid_frames.py" "$@"; }
compare_both() {  # compare_both RUN_A RUN_B FRAME...: the water, then the grains, within the bounds above
  compare "$@" --position 1e-7 --velocity 1e-4 && compare "$@" --grains --position 1e-7 --velocity 1e-4 --pressure 1e-4
}
bed="$SRC/tests/data/shaken_bed_in_water.toml"

# The pressure as a user gets it: the in-house CG over the ranks (its two-level preconditioner's coarse level spanning
# the ranks, the products reading the ghosts' entries, the sums over the ranks in rank order) against its one-rank
# solve.
for n in 1 2 4; do
  ranks "$n" run "$bed" --out "bed$n" --until 0.1 --threads 1 --set output.checkpoint_interval=0.05 \
    --set 'fluid.preconditioner="two_level"' >"bed$n.out" 2>&1
  check "the shaken bed in water runs on $n rank(s)" [ $? = 0 ]
done
check "... rank 0 reported each rank's grains and the systems' times over the ranks" \
  bash -c "grep -qF 'per-system timings over the 2 ranks' bed2/riffle.log &&
           [ \$(grep -c '^1,fluid_drag_reaction,' bed2/timings_ranks.csv) = 1 ]"
# The preconditioner over 2 and 4 ranks is the one-rank one over the whole domain (only the aggregates the ranks'
# boundaries cut differ), so the mean iteration count stays within 5 % of one rank's. A coarse level per rank's
# block alone took 7 % more on 2 ranks and 17 % more on 4 (35.1, 37.7, 41.0 iterations).
mean_iterations() {  # mean_iterations RUN: the mean of diagnostics.csv's ppe_iterations column
  awk -F, 'NR == 1 { for (k = 1; k <= NF; ++k) if ($k == "ppe_iterations") c = k; next }
           c { s += $c; n++ } END { if (n) printf "%.3f", s / n }' "$1/diagnostics.csv"
}
for n in 2 4; do
  check "... the pressure solve's mean iterations on $n ranks within 5 % of one rank's ($(mean_iterations bed1) on 1)" \
    awk -v one="$(mean_iterations bed1)" -v many="$(mean_iterations "bed$n")" \
      'BEGIN { print "#   " many " iterations"; exit !(one > 0 && many > 0 && many < 1.05 * one && many > 0.95 * one) }'
done
for n in 2 4; do
  check "... the water and grains on $n ranks as on one, particle by particle and grain by grain, at t = 0.05, 0.1 s" \
    compare_both bed1 "bed$n" 1 2
done

# Across periodic seams, with the options seed 003's sheared beds use (tests/data/periodic_bed_in_water.toml: 1,000
# grains of 1 mm falling through water periodic along x and y under a lid at 1 m/s, SPS; the grains' volume over the
# tank's, the drag given back with the sampling kernel, ellipsoidal kernels, the water's viscous stress on the
# grains): 2 and 4 ranks against 1 over 24 steps.
periodic="$SRC/tests/data/periodic_bed_in_water.toml"
for n in 1 2 4; do
  ranks "$n" run "$periodic" --out "periodic$n" --threads 1 --set 'fluid.preconditioner="boomeramg"' \
    >"periodic$n.out" 2>&1
  check "the periodic bed in water under a lid runs on $n rank(s)" [ $? = 0 ]
done
for n in 2 4; do
  check "... its water and grains on $n ranks as on one at t = 0.005 and 0.01 s" compare_both periodic1 "periodic$n" 1 2
done

# The 2 ranks' checkpoint at t = 0.05 s resumed on 1 and 3 ranks goes on as the 2-rank run did.
for n in 1 3; do
  ranks "$n" resume bed2/checkpoints/step_0000000050.ckpt --out "resumed$n" --until 0.1 --threads 1 \
    >"resumed$n.out" 2>&1
  check "the 2-rank checkpoint at t = 0.05 s resumes on $n rank(s)" [ $? = 0 ]
  check "... and its water and grains reach t = 0.1 s as the 2-rank run did" compare_both bed2 "resumed$n" 2
done

check "riffle check: grains in water can be spread over ranks" \
  bash -c "'$RIFFLE' check '$bed' | grep -qF 'over MPI ranks: can be spread'"
# Lubrication between grains across the ranks' edges (the other rank's grain read as a ghost with its owner's
# sampling weight, the reaction sent home): on 2 ranks as on one.
for n in 1 2; do
  ranks "$n" run "$bed" --out "lubricated$n" --until 0.1 --threads 1 --set coupling.lubrication=true \
    >"lubricated$n.out" 2>&1  # hypre, on one rank as over both (the scene's preconditioner)
  check "the shaken bed in water with lubrication runs on $n rank(s)" [ $? = 0 ]
done
check "... its grains and water on 2 ranks as on one at t = 0.05 and 0.1 s" compare_both lubricated1 lubricated2 1 2

# What cannot be spread is refused before anything is written, and riffle check says so beforehand.
ranks 2 run "$SRC/scenes/free_fall_box.toml" --out refused --until 0.01 >refused.out 2>&1
rc=$?
check "grains without contacts on two ranks exit 1, naming why, with nothing written" \
  bash -c "[ $rc = 1 ] && grep -qF 'cannot spread this scene over 2 MPI ranks: a scene without grains in contact' \
             refused.out && [ ! -e refused ] &&
           '$RIFFLE' check '$SRC/scenes/free_fall_box.toml' | grep -qF 'over MPI ranks: one rank only: a scene without'"

echo "$failures check(s) failed"
[ "$failures" = 0 ]
