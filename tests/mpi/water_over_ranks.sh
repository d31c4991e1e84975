#!/usr/bin/env bash
# `mpirun -np N riffle run|resume` for scenes of water alone (the MPS particles spread over the ranks: fluid_ranks.hpp,
# fluid_rank_migration, the searches' rank ghosts, the pressure solved by hypre over all the ranks): each run on 2 and
# 4 ranks against 1 rank, particle by particle (matched by id) in its ParaView frames, a checkpoint of 2 ranks resumed
# on 1 and 3, a lid with SPS and a bulk-velocity controller on 2 ranks against 1, a splash's escaped particles named
# in the log, and riffle check's answer.
#
# Tolerances: one rank solves the same pressure equation with hypre alone (the scenes ask for "boomeramg"), the ranks
# with hypre over all of them; both stop at |r| <= 1e-8 |b| (fluid.solver_tolerance), at other iterates, so each
# step's pressures differ by about that fraction and the flows by its accumulation over the steps. The bounds
# (1e-8 m = 4e-6 l0 in position, 1e-6 of the largest speed, 1e-5 of the largest pressure) are far above rounding and
# that accumulation over these runs' 80-200 steps, and far below anything a flow of these sizes shows (a wrong ghost
# or a missed neighbour moves a particle by a fraction of l0 within a few steps).
#   tests/mpi/water_over_ranks.sh RIFFLE MPIEXEC SOURCE_DIR WORK_DIR
set -u
RIFFLE=$1 MPIEXEC=$2 SRC=$3 WORK=$4
RANKS_TIMEOUT=300
source "$SRC/tests/mpi/over_ranks_common.sh"
compare() { /usr/bin/python3 "$SRC/tests/mpi/compare_fluid_frames.py" "$@"; }

# Periodic water over a block (periodic along x and y, a free surface, shifting): 0.06 s, 120 steps.
block="$SRC/tests/data/periodic_water_over_block.toml"
for n in 1 2 4; do
  ranks "$n" run "$block" --out "block$n" --until 0.06 --threads 1 >"block$n.out" 2>&1
  check "the periodic water over a block runs on $n rank(s)" [ $? = 0 ]
done
check "... rank 0 wrote the outputs once and reported each rank's particles" \
  bash -c "[ -s block2/diagnostics.csv ] && [ -s block2/checkpoints/final.ckpt ] &&
           [ \$(grep -c 'finished at' block2/riffle.log) = 1 ] && grep -qF 'MPS particles, stepping' block2/riffle.log"
check "... and each system's time on each rank (timings_ranks.csv, the table over the ranks)" \
  bash -c "grep -qF 'per-system timings over the 4 ranks' block4/riffle.log &&
           [ \$(grep -c '^3,fluid_pressure,' block4/timings_ranks.csv) = 1 ] &&
           [ \$(grep -c '^3,fluid_rank_migration,' block4/timings_ranks.csv) = 1 ]"
for n in 2 4; do
  check "... on $n ranks as on one, particle by particle, at t = 0.02, 0.04, 0.06 s" compare block1 "block$n" 1 2 3
done
check "... the water's totals in diagnostics.csv: the same particle count and volume to 1e-9" \
  /usr/bin/python3 -c "
import csv
rows = [list(csv.DictReader(open(f'block{n}/diagnostics.csv')))[-1] for n in (1, 2, 4)]
for row in rows[1:]:
    assert row['fluid_particles'] == rows[0]['fluid_particles'], row['fluid_particles']
    assert row['ppe_unknowns'] == rows[0]['ppe_unknowns'] or abs(int(row['ppe_unknowns']) - int(rows[0]['ppe_unknowns'])) <= 2
    assert abs(float(row['fluid_volume_m3']) / float(rows[0]['fluid_volume_m3']) - 1) < 1e-9
"

# A checkpoint of 2 ranks (t = 0.05 s) resumed on 1 and 3 ranks goes on as the 2-rank run did.
for n in 1 3; do
  ranks "$n" resume block2/checkpoints/step_0000000100.ckpt --out "resumed$n" --until 0.06 --threads 1 \
    >"resumed$n.out" 2>&1
  check "the 2-rank checkpoint at t = 0.05 s resumes on $n rank(s)" [ $? = 0 ]
  check "... and reaches t = 0.06 s as the 2-rank run did" compare block2 "resumed$n" 3
done

# The dam break (3,200 fluid particles in a column at one end of a 0.5 m tank of 42,800 wall and dummy particles):
# over 4 ranks the boxes cut the column itself (over 2 the one cut lies beyond the water until the front reaches
# it, at about 0.1 s). 0.04 s, 40 steps: by 0.04 s particles have drifted out of their boxes enough that ghosts
# chosen by the boxes alone, without fluid_box_overflow's widening, miss neighbours and the check fails.
sed 's/^spacing = 0.005 .*/spacing = 0.005\npreconditioner = "boomeramg"/' "$SRC/scenes/dam_break.toml" >dam.toml
for n in 1 4; do
  ranks "$n" run dam.toml --out "dam$n" --until 0.04 --threads 1 >"dam$n.out" 2>&1
  check "the dam break runs on $n rank(s)" [ $? = 0 ]
done
check "... on 4 ranks as on one, particle by particle, at t = 0.02 and 0.04 s" compare dam1 dam4 1 2

# The same dam break as shipped (l0 = 10 mm, the in-house CG: over ranks its coarse level spanning the ranks, the
# products reading the ghosts' entries, the sums over the ranks in rank order) on 4 ranks against 1.
for n in 1 4; do
  ranks "$n" run "$SRC/scenes/dam_break.toml" --out "dam_cg$n" --until 0.04 --threads 1 >"dam_cg$n.out" 2>&1
  check "the dam break with the in-house pressure solve runs on $n rank(s)" [ $? = 0 ]
done
check "... on 4 ranks as on one, particle by particle, at t = 0.02 and 0.04 s" compare dam_cg1 dam_cg4 1 2

# The seed's tank of water alone shaken at 1 cm and 1.7 Hz (55,548 MPS particles): the walls move with the tank
# through the ranks' boxes, which stay in the lab frame. 0.02 s, 20 steps.
for n in 1 2; do
  ranks "$n" run "$SRC/scenes/sloshing_tank.toml" --out "sloshing$n" --until 0.02 --threads 1 \
    --set 'fluid.preconditioner="boomeramg"' --set output.vtk_interval=0.02 >"sloshing$n.out" 2>&1
  check "the shaken tank of water runs on $n rank(s)" [ $? = 0 ]
done
check "... on 2 ranks as on one, particle by particle, at t = 0.02 s" compare sloshing1 sloshing2 1

# The sheared water block (periodic along x and y, a no-slip lid at 1 m/s, SPS eddy viscosity; 4,352 particles): the
# lid's particles and the eddy viscosity seen across the ranks, the lid's force summed over them. 0.02 s, 40 steps.
for n in 1 2; do
  ranks "$n" run "$SRC/scenes/sheared_water_block.toml" --out "sheared$n" --until 0.02 --threads 1 \
    --set 'fluid.preconditioner="boomeramg"' --set output.vtk_interval=0.01 >"sheared$n.out" 2>&1
  check "the sheared water block (a lid, SPS) runs on $n rank(s)" [ $? = 0 ]
done
check "... on 2 ranks as on one, particle by particle, at t = 0.01 and 0.02 s" compare sheared1 sheared2 1 2
# columns: time, step, body force, bulk velocity, then the lid's force and shear stress
compare_columns() {  # compare_columns A B FIRST_COLUMN: each row's values from FIRST_COLUMN on, to 1e-6 of the row's largest
  /usr/bin/python3 - "$@" <<'PY'
import csv, sys
a, b, first = list(csv.reader(open(sys.argv[1])))[1:], list(csv.reader(open(sys.argv[2])))[1:], int(sys.argv[3])
assert len(a) == len(b) >= 2, (len(a), len(b))
worst = 0.0
for ra, rb in zip(a, b):
    pairs = [(float(x), float(y)) for x, y in zip(ra[first:], rb[first:]) if x != "" or y != ""]
    scale = max([abs(x) for x, _ in pairs] + [1e-300])
    worst = max([worst] + [abs(x - y) / scale for x, y in pairs])
print(f"{sys.argv[1]} against {sys.argv[2]}: largest difference {worst:.3g} of the row's largest value")
sys.exit(0 if worst < 1e-6 else 1)
PY
}
check "... the lid's force on the water the same to 1e-6" \
  compare_columns sheared1/probe_driven_flow.csv sheared2/probe_driven_flow.csv 4

# The periodic block driven to a bulk velocity of 0.1 m/s (a controller on the mean u_x of all the water).
sed 's/^kind = "constant"/kind = "bulk_velocity"/; s/^acceleration = 2.0 .*/target_velocity = 0.1\nresponse_time = 0.01/' \
  "$block" >bulk.toml
printf '\n[[output.probes]]\nkind = "driven_flow"\ninterval = 0.01\n' >>bulk.toml
for n in 1 2; do
  ranks "$n" run bulk.toml --out "bulk$n" --until 0.03 --threads 1 >"bulk$n.out" 2>&1
  check "the block driven to a bulk velocity runs on $n rank(s)" [ $? = 0 ]
done
check "... its body force and bulk velocity the same on 2 ranks as on one, to 1e-6" \
  compare_columns bulk1/probe_driven_flow.csv bulk2/probe_driven_flow.csv 2
check "... diagnostics.csv has its body force column on 2 ranks as on one" \
  bash -c "head -1 bulk1/diagnostics.csv | grep -qF body_force_m_s2 && head -1 bulk2/diagnostics.csv | grep -qF body_force_m_s2"
# Resumed on one rank in its own folder: the series go on; one whose columns differ from what one rank writes (a
# system timer only ranks have) goes on under one rank's columns, and the file as it was is kept beside it.
cp -r bulk2 bulk_resumed
ranks 1 resume bulk_resumed/checkpoints/final.ckpt --out bulk_resumed --until 0.04 --threads 1 >bulk_resumed.out 2>&1
check "the 2 ranks' driven block resumes on one rank in its own folder" [ $? = 0 ]
check "... its diagnostics go on from the 2 ranks' rows (their columns matched by name), the earlier file kept whole" \
  /usr/bin/python3 - bulk2/diagnostics.csv bulk_resumed <<'PY'
import csv, os, sys
earlier = list(csv.DictReader(open(sys.argv[1])))
now = list(csv.DictReader(open(os.path.join(sys.argv[2], "diagnostics.csv"))))
aside = os.path.join(sys.argv[2], "diagnostics.before_resume.csv")
if os.path.exists(aside):
    assert open(aside).read() == open(sys.argv[1]).read(), "the earlier file is not kept whole"
    assert "its rows up to the resume" in open(os.path.join(sys.argv[2], "riffle.log")).read(), "no warning in the log"
assert len(now) > len(earlier), (len(now), len(earlier))
for a, b in zip(earlier, now):  # every earlier value under its column's name, in order
    assert all(b[k] == v for k, v in a.items() if k in b), (a, b)
assert float(now[-1]["time_s"]) > float(earlier[-1]["time_s"])
PY
# A splash out of a low open tank (tests/data/splash_escape.toml: 288 particles, droplets over the walls and out of
# the domain): each rank removes its own escaped particles, the counts are the water's, and rank 0's log names every
# removed particle once, as one rank's does.
ranks 2 run "$SRC/tests/data/splash_escape.toml" --out splash2 --threads 1 >splash2.out 2>&1
check "a splash out of an open tank runs on 2 ranks" [ $? = 0 ]
check "... its log names each removed particle once (past 20 a step, counts them), as diagnostics.csv counts" \
  /usr/bin/python3 -c "
import csv, re
removed = int(list(csv.DictReader(open('splash2/diagnostics.csv')))[-1]['fluid_removed_particles'])
log = open('splash2/riffle.log').read()
ids = re.findall(r'fluid particle id (\d+) removed', log)
more = sum(int(n) for n in re.findall(r'(\d+) more fluid particles removed as escaped', log))  # past 20 a step
assert removed > 0 and len(ids) + more == removed and len(set(ids)) == len(ids), (removed, len(ids), more)
"

# riffle check says beforehand whether a scene can be spread (grains in water: grains_in_water_over_ranks.sh).
check "riffle check: the dam break can be spread over ranks" \
  bash -c "'$RIFFLE' check dam.toml | grep -qF 'over MPI ranks: can be spread'"

echo "$failures check(s) failed"
[ "$failures" = 0 ]
