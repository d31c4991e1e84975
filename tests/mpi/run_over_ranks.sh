#!/usr/bin/env bash
# `mpirun -np N riffle run|resume` for a scene of grains (Simulation::split_over_ranks): a dry bed dropped into a
# shaken tank run on 2 ranks against 1, its checkpoint resumed on 1, 2 and 3 ranks against the run that went on (water
# over ranks, and a scene riffle cannot spread yet refused: water_over_ranks.sh). Tolerances: the ranks add each
# grain's contact forces in another order,
# so the runs agree to rounding until the granular flow amplifies it (tests/mpi/grain_ranks.cpp measures the
# growth); the rows compared here are before that, at 1e-9 relative.
#   tests/mpi/run_over_ranks.sh RIFFLE MPIEXEC SOURCE_DIR WORK_DIR
set -u
RIFFLE=$1 MPIEXEC=$2 SRC=$3 WORK=$4
source "$SRC/tests/mpi/over_ranks_common.sh"

cp "$SRC/tests/data/shaken_bed.toml" shaken.toml

ranks 1 run shaken.toml --out one --threads 1 >one.out 2>&1
check "one rank runs the shaken bed" [ $? = 0 ]
ranks 2 run shaken.toml --out two --threads 1 >two.out 2>&1
check "two ranks run it (exit 0)" [ $? = 0 ]
check "... rank 0 wrote the outputs once: log, diagnostics, the probe, frames, checkpoints" \
  bash -c "[ -s two/diagnostics.csv ] && [ -s two/probe_wall_forces.csv ] && [ -s two/vtk/solids_000004.pvtp ] &&
           [ -s two/vtk/walls_000004.vtp ] && [ -s two/checkpoints/final.ckpt ] &&
           [ \$(grep -c 'finished at' two/riffle.log) = 1 ]"
# Each frame in pieces (output.vtk_pieces = "per_rank", the default): each rank's grains in its own .vtp, a .pvtp
# naming the two, the .pvd listing the .pvtp; joined, the same grains and values as rank 0 writes after gathering them.
check "... each frame in two pieces, one a rank, named by a .pvtp that solids.pvd lists" \
  bash -c "[ -s two/vtk/solids_000004_0.vtp ] && [ -s two/vtk/solids_000004_1.vtp ] && [ ! -e two/vtk/solids_000004.vtp ] &&
           grep -qF 'Source=\"solids_000004_1.vtp\"' two/vtk/solids_000004.pvtp &&
           grep -qF 'file=\"vtk/solids_000004.pvtp\"' two/solids.pvd"
ranks 2 run shaken.toml --out two_gathered --threads 1 --set 'output.vtk_pieces="gathered"' >two_gathered.out 2>&1
check "... the pieces joined are the frames rank 0 writes with output.vtk_pieces = \"gathered\", value for value" \
  /usr/bin/python3 "$SRC/tests/mpi/compare_fluid_frames.py" two_gathered two 0 1 2 3 4 --grains --position 0 \
  --velocity 0 --pressure 0
# A piece one rank cannot write (a folder in its place): every rank stops, rank 0 names that rank and the file, and the
# series lists the frames written whole.
mkdir -p unwritable/vtk/solids_000002_1.vtp/in_the_way
ranks 2 run shaken.toml --out unwritable --threads 1 >unwritable.out 2>&1
rc=$?
check "a frame's piece rank 1 cannot write stops both ranks (exit 4)" [ $rc = 4 ]
check "... rank 0 naming rank 1's file; the series lists the two frames written whole" \
  bash -c "grep -qF 'output failed: rank 1: unwritable/vtk/solids_000002_1.vtp' unwritable/riffle.log &&
           [ \$(grep -c '<DataSet' unwritable/solids.pvd) = 2 ]"
check "... and reported each rank's grains and stepping time" grep -qF "rank 1:" two/riffle.log
# Each system's time on every rank: a row per system and rank, the same systems on both, and their table in the log.
check "... and each system's time on each rank (timings_ranks.csv, the table over the ranks)" \
  bash -c "grep -qF 'per-system timings over the 2 ranks' two/riffle.log &&
           [ \$(grep -c '^0,solid_contact_forces,' two/timings_ranks.csv) = 1 ] &&
           [ \$(grep -c '^1,solid_contact_forces,' two/timings_ranks.csv) = 1 ] &&
           [ \$(grep -c '^0,' two/timings_ranks.csv) = \$(grep -c '^1,' two/timings_ranks.csv) ] &&
           ! grep -q '^2,' two/timings_ranks.csv"
ranks 2 run shaken.toml --out two_threads --threads 2 >two_threads.out 2>&1
check "two ranks of two threads each end in the same checkpoint as of one thread, byte for byte" \
  cmp -s two/checkpoints/final.ckpt two_threads/checkpoints/final.ckpt

# compare A B STEPS...: the bed's energies in diagnostics.csv at STEPS agree to 1e-9 relative.
compare() {
  /usr/bin/python3 - "$@" <<'PY'
import csv, sys
a, b, steps = sys.argv[1], sys.argv[2], sys.argv[3:]
def rows(path):
    lines = list(csv.reader(open(path)))
    header = lines[0]
    return header, {row[0]: dict(zip(header, row)) for row in lines[1:]}
_, ra = rows(a)
_, rb = rows(b)
worst = 0.0
for step in steps:
    for key in ("solid_translational_energy_J", "solid_rotational_energy_J", "solid_potential_energy_J"):
        x, y = float(ra[step][key]), float(rb[step][key])
        worst = max(worst, abs(x - y) / max(abs(x), 1e-300))
print(f"{a} against {b} at steps {' '.join(steps)}: largest relative difference {worst:.3g}")
sys.exit(0 if worst < 1e-9 else 1)
PY
}
check "two ranks against one: the bed's energies to 1e-9 over the first 80 steps" \
  compare one/diagnostics.csv two/diagnostics.csv 10 20 40 60 80
# The outputs rank 0 writes from the gathered grains: the walls' forces (wall contacts only) and the bed profile's
# layers with their contact counts (the pair list rebuilt over the gathered bed), the same as one rank's while the
# two runs are the same (to t = 0.05 s and 0.04 s: 6 and 3 output times). A wall's force sums its grains' in the
# gathered order (by id), one rank's in its slot order: the rows agree to 1e-8 of their largest force.
check "... the wall-force probe the same to 1e-8 to t = 0.05 s" \
  /usr/bin/python3 -c "
import csv
a = list(csv.reader(open('one/probe_wall_forces.csv')))[1:7]
b = list(csv.reader(open('two/probe_wall_forces.csv')))[1:7]
assert len(a) == len(b) == 6
for ra, rb in zip(a, b):
    x, y = [float(v) for v in ra], [float(v) for v in rb]
    scale = max(abs(v) for v in x[2:]) or 1.0
    assert max(abs(p - q) for p, q in zip(x, y)) <= 1e-8 * scale, (ra[0], ra, rb)
"
check "... and the bed profile with its contact counts, to t = 0.04 s" \
  bash -c "[ \$(grep -c '^0.04' one/bed_profile.csv) -gt 0 ] &&
           cmp -s <(awk -F, '\$1 <= 0.041' one/bed_profile.csv) <(awk -F, '\$1 <= 0.041' two/bed_profile.csv)"
for n in 1 2 3; do
  ranks "$n" resume two/checkpoints/step_0000000100.ckpt --out "resumed$n" --threads 1 >"resumed$n.out" 2>&1
  check "the two ranks' checkpoint at t = 0.1 s resumes on $n rank(s)" [ $? = 0 ]
  check "... and goes on as the run that wrote it did, to 1e-9 over 20 steps" \
    compare two/diagnostics.csv "resumed$n/diagnostics.csv" 105 110 115 120
done
# Resumed on one rank in the folder of the two ranks' run: the frames up to the checkpoint stay in pieces, the later ones
# are rewritten whole (their .pvtp removed), and the series names each frame's file.
cp -r two mixed
ranks 1 resume mixed/checkpoints/step_0000000100.ckpt --out mixed --threads 1 >mixed.out 2>&1
check "the two ranks' run resumed on one rank in its own folder: its series lists frames 0-2 in pieces, 3-4 whole" \
  bash -c "grep -qF 'file=\"vtk/solids_000002.pvtp\"' mixed/solids.pvd && grep -qF 'file=\"vtk/solids_000003.vtp\"' mixed/solids.pvd &&
           grep -qF 'file=\"vtk/solids_000004.vtp\"' mixed/solids.pvd && [ ! -e mixed/vtk/solids_000004.pvtp ] &&
           [ \$(grep -c '<DataSet' mixed/solids.pvd) = 5 ]"
check "... and its diagnostics keep the two ranks' rows (the file as it was kept beside it where the columns differ)" \
  bash -c "if [ \"\$(head -1 two/diagnostics.csv)\" = \"\$(head -1 mixed/diagnostics.csv)\" ]; then
             [ ! -e mixed/diagnostics.before_resume.csv ] && [ \$(awk -F, 'NR > 1 && \$1 <= 100' mixed/diagnostics.csv | wc -l) -gt 0 ]
           else
             cmp -s two/diagnostics.csv mixed/diagnostics.before_resume.csv && grep -qF 'its rows up to the resume' mixed/riffle.log &&
             [ \$(awk -F, 'NR > 1 && \$1 <= 100' mixed/diagnostics.csv | wc -l) -gt 0 ]
           fi"

# A periodic bed (the bed-load channel's, 1,150 grains of 2 mm falling into a box periodic along x and y), then the
# channel's mean-flow water driving it at Theta = 0.2 over 40 steps: the images across the periodic faces and the
# column's sums over the ranks.
ranks 1 run "$SRC/scenes/bedload_channel_settle.toml" --out settle1 --until 0.1 --threads 1 >settle1.out 2>&1
check "the periodic bed settles on one rank" [ $? = 0 ]
ranks 2 run "$SRC/scenes/bedload_channel_settle.toml" --out settle2 --until 0.1 --threads 1 >settle2.out 2>&1
check "... and on two" [ $? = 0 ]
check "... the same to 1e-9 over its first 100 steps (falling, first impacts)" \
  compare settle1/diagnostics.csv settle2/diagnostics.csv 20 40 60 80 100
for n in 1 2; do
  ranks "$n" run "$SRC/scenes/bedload_channel.toml" --out "channel$n" --until 0.04 --threads 1 \
    --set "solids.initial_state=\"$WORK/settle1/checkpoints/final.ckpt\"" --set mean_flow.shields_number=0.2 \
    >"channel$n.out" 2>&1
  check "the bed-load channel (mean-flow water, periodic) runs on $n rank(s)" [ $? = 0 ]
done
ranks 2 run "$SRC/scenes/bedload_channel.toml" --out channel2_threads --until 0.04 --threads 2 \
  --set "solids.initial_state=\"$WORK/settle1/checkpoints/final.ckpt\"" --set mean_flow.shields_number=0.2 \
  >channel2_threads.out 2>&1
# The checkpoint holds the gathered pair list, with the image pairs across the periodic faces: byte for byte the same
# again (another run, other threads) only if nothing in it is read from beyond the grains.
check "... its checkpoint the same byte for byte when run again on 2 ranks of 2 threads" \
  cmp -s channel2/checkpoints/final.ckpt channel2_threads/checkpoints/final.ckpt
check "... its bed-load probe the same on 2 ranks as on 1 over 40 steps (Theta, u*, bed surface, q*)" \
  bash -c "cut -d, -f1-8 channel1/probe_bedload_transport.csv > c1 && cut -d, -f1-8 channel2/probe_bedload_transport.csv > c2 &&
           [ \$(wc -l < c1) -ge 4 ] && cmp -s c1 c2"

# A grain thrown out through the open top on the second rank: every rank stops, rank 0 reports that rank's diagnosis.
cat >lost.toml <<'SCENE'
[run]
name = "lost_over_ranks"
end_time = 0.5
dt = 1.0e-3

[materials.grain]
density = 1318.0
young_modulus = 1.0e7
poisson_ratio = 0.3

[contact]
law = "hertz_mindlin"
restitution = 0.5
friction = 0.4

[tank]
size = [0.10, 0.08, 0.10]
open_faces = ["z_max"]
wall_material = "grain"

[solids]
[[solids.spheres]]
position = [0.02, 0.04, 0.01]
radius = 0.004
material = "grain"

[[solids.spheres]]
position = [0.08, 0.04, 0.01]
velocity = [0.0, 0.0, 3.0]
radius = 0.004
material = "grain"

[output]
checkpoint_interval = 0.01
SCENE
ranks 2 run lost.toml --out lost --threads 1 >lost.out 2>&1
rc=$?
check "a grain lost on rank 1 of 2 stops the run (exit 3)" [ $rc = 3 ]
check "... rank 0 naming rank 1's grain and the last good checkpoint, with the gathered grains written" \
  bash -c "grep -qF 'rank 1: run stopped at step 51' lost/riffle.log &&
           grep -qF 'last good checkpoint: lost/checkpoints/step_0000000050.ckpt' lost/riffle.log &&
           [ -s lost/vtk/solids_failed.vtp ]"

# A rank killed mid-run (a node lost): mpirun ends the other rank with SIGTERM while it waits for the dead one; rank 0
# names the last checkpoint written whole, on stderr and in riffle.log, and that checkpoint resumes.
( ranks 2 run "$SRC/tests/data/column_collapse.toml" --out "$WORK/killed" --until 5 --threads 1 \
    --set output.checkpoint_interval=0.05 >killed.out 2>&1
  echo $? >killed.rc ) &
for _ in $(seq 600); do
  [ "$(ls killed/checkpoints/step_*.ckpt 2>/dev/null | wc -l)" -ge 2 ] && break
  sleep 0.1
done
for pid in $(pgrep -f -- "--out $WORK/killed"); do
  grep -qz '^OMPI_COMM_WORLD_RANK=1$' "/proc/$pid/environ" 2>/dev/null && kill -9 "$pid"
done
wait
check "a rank killed mid-run ends the run (exit not 0)" [ "$(cat killed.rc)" != 0 ]
named=$(grep -o 'the last checkpoint written whole is [^ ]*' killed.out | head -1 | awk '{print $NF}')
named_time=$(grep -o 'written whole is [^ ]* (t = [0-9.e+-]*' killed.out | head -1 | awk '{print $NF}')
check "... rank 0 names the last checkpoint written whole on stderr ($named) and in riffle.log" \
  bash -c "[ -n '$named' ] && [ -s '$named' ] && grep -qF 'last checkpoint written whole is $named' killed/riffle.log"
check "... and the log kept its lines up to then" grep -qF "starting 'column_collapse'" killed/riffle.log
ranks 1 resume "$named" --out after_kill --threads 1 \
  --until "$(awk -v t="$named_time" 'BEGIN { print t + 0.01 }')" >after_kill.out 2>&1
check "... which resumes" [ $? = 0 ]

echo "$failures check(s) failed"
[ "$failures" = 0 ]
