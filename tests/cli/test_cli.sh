#!/usr/bin/env bash
# End-to-end test of the riffle command line: help and usage errors, scene validation, run outputs, resume and
# thread-count determinism (byte-identical checkpoints), damaged checkpoints, SIGINT/SIGTERM, and an unstable run.
#
#   bash tests/cli/test_cli.sh <riffle-binary> <source-dir> <work-dir>
#
# Prints one "ok - ..." / "not ok - ..." line per check (details of a failure follow as "#" lines), then
# "N passed, M failed". Exits 1 if any check failed, 2 on bad usage. The work dir is wiped first (see below).
set -u

if [ $# -ne 3 ]; then
  echo "usage: bash $0 <riffle-binary> <source-dir> <work-dir>" >&2
  exit 2
fi
abs_path() { (cd "$(dirname "$1")" && printf '%s/%s\n' "$(pwd -P)" "$(basename "$1")"); }
RIFFLE=$(abs_path "$1") || exit 2
SRC=$(cd "$2" && pwd -P) || exit 2
# The work dir is wiped, but only if it is new, empty or one this script made (it holds the marker file).
if [ -d "$3" ] && [ -n "$(ls -A "$3")" ] && [ ! -f "$3/.riffle_cli_work" ]; then
  echo "$3: not empty and not a riffle CLI test work dir; refusing to wipe it" >&2
  exit 2
fi
rm -rf "$3" && mkdir -p "$3" && touch "$3/.riffle_cli_work" || exit 2
WORK=$(cd "$3" && pwd -P) || exit 2
if [ ! -x "$RIFFLE" ]; then
  echo "$RIFFLE: not an executable" >&2
  exit 2
fi
cd "$WORK" || exit 2
export LC_ALL=C
# A background run of check 6 must not outlive the script (e.g. when a test driver's timeout stops it).
background_pid=
trap '[ -z "$background_pid" ] || kill -s KILL "$background_pid" 2>/dev/null' EXIT

passed=0
failed=0
ok() { echo "ok - $1"; passed=$((passed + 1)); }
not_ok() {
  echo "not ok - $1"
  shift
  local line
  for line in "$@"; do printf '#   %s\n' "$line"; done
  failed=$((failed + 1))
}
# check DESCRIPTION COMMAND...: ok if the command succeeds.
check() {
  local description=$1 output command
  shift
  if output=$("$@" 2>&1); then
    ok "$description"
  else
    command="$*"
    command=${command//$'\n'/ }
    [ ${#command} -le 160 ] || command="${command:0:160}..."
    not_ok "$description" "failed: $command"
    [ -z "$output" ] || printf '%s\n' "$output" | sed 's/^\(#   \)\{0,1\}/#   /'
  fi
}
# Shows the tail of a file under a failing check.
show() { [ -f "$1" ] && tail -n 6 "$1" | sed "s|^|#   $(basename "$1"): |"; return 0; }

# riffle_as NAME ARGS...: runs riffle with stdout/stderr in NAME.out / NAME.err and its exit code in NAME.rc
# (and in $rc). A hard 60 s limit keeps a hang from stalling the test.
riffle_as() {
  local name=$1
  shift
  timeout -k 5 60 "$RIFFLE" "$@" >"$WORK/$name.out" 2>"$WORK/$name.err"
  rc=$?
  echo "$rc" >"$WORK/$name.rc"
}
# expect_rc DESCRIPTION NAME CODE: the run NAME exited with CODE.
expect_rc() {
  local got
  got=$(cat "$WORK/$2.rc")
  if [ "$got" = "$3" ]; then
    ok "$1"
  else
    not_ok "$1" "expected exit $3, got $got"
    tail -n 6 "$WORK/$2.err" | sed 's/^/#   stderr: /'
  fi
}
# contains FILE STRING...: every string occurs in FILE (fixed strings).
contains() {
  local file=$1 needle
  shift
  for needle in "$@"; do grep -qF -- "$needle" "$file" || { echo "#   '$needle' not found in $(basename "$file")"; return 1; }; done
}
# same_text A B: the two strings are equal; on a difference, shows its first lines.
same_text() {
  [ "$1" = "$2" ] && return 0
  diff <(printf '%s\n' "$1") <(printf '%s\n' "$2") | head -n 5
  return 1
}
ckpt_name() { printf 'step_%010d.ckpt' "$1"; }
data_rows() { if [ -f "$1" ]; then tail -n +2 "$1" | grep -c . || true; else echo 0; fi; }

# ---------------------------------------------------------------------------------------------------------------
# Scenes. Line numbers in typo.toml matter (check 2).

# small: ~3700 grains thrown upwards in a shaken tank (tank motion, rotation, cell sorting every 7 steps).
# 50 steps; a VTK frame and an interval checkpoint every 10 steps.
cat >small.toml <<'EOF'
[run]
name = "cli_small"
end_time = 0.05
dt = 1.0e-3
solid_substeps = 5

[materials.grain]
density = 1318.0

[materials.glass]
density = 2500.0

[tank]
size = [0.10, 0.08, 0.10]
open_faces = ["z_max"]
wall_material = "glass"

[tank.motion]
kind = "sinusoidal"
amplitude = 0.01
frequency = 1.7
ramp_time = 0.02

[solids]
sort_every = 7

[[solids.spheres]]
position = [0.05, 0.04, 0.08]
velocity = [0.05, 0.0, 0.4]
angular_velocity = [0.0, 10.0, 3.0]
radius = 0.004
material = "grain"

[[solids.blocks]]
min = [0.01, 0.01, 0.01]
max = [0.09, 0.07, 0.05]
spacing = 0.004
radius = 0.0015
material = "grain"
velocity = [0.0, 0.0, 0.5]

[output]
vtk_interval = 0.01
checkpoint_interval = 0.01
checkpoint_keep = 10
EOF

# typo: "end_tme" on line 4, column 1.
cat >typo.toml <<'EOF'
[run]
name = "cli_typo"
dt = 1.0e-3
end_tme = 0.05

[materials.grain]
density = 1318.0

[tank]
size = [0.10, 0.08, 0.10]
wall_material = "grain"
EOF

# long: ~2900 grains at rest without gravity, so it runs for as long as --until says (minutes for --until 1000)
# and never fails.
cat >long.toml <<'EOF'
[run]
name = "cli_long"
end_time = 0.01
dt = 1.0e-3
solid_substeps = 4
gravity = [0.0, 0.0, 0.0]

[materials.grain]
density = 1318.0

[tank]
size = [0.10, 0.10, 0.10]
wall_material = "grain"

[tank.motion]
kind = "sinusoidal"
amplitude = 0.005
frequency = 2.0

[solids]
sort_every = 50

[[solids.blocks]]
min = [0.005, 0.005, 0.005]
max = [0.095, 0.095, 0.04]
spacing = 0.005
radius = 0.002
material = "grain"

[output]
diagnostics_every = 20
EOF

# unstable: particle id 1 (the second sphere) sits near the x_max wall moving outwards at 4.5 m/s. Nothing stops it
# yet (no grain-wall contact), and it passes the domain (tank + 0.05 m margin: x <= 0.15) in step 14.
cat >unstable.toml <<'EOF'
[run]
name = "cli_unstable"
end_time = 0.05
dt = 1.0e-3
solid_substeps = 4

[materials.grain]
density = 1318.0

[tank]
size = [0.10, 0.10, 0.10]
wall_material = "grain"

[solids]
sort_every = 1

[[solids.spheres]]
position = [0.05, 0.05, 0.05]
radius = 0.003
material = "grain"

[[solids.spheres]]
position = [0.09, 0.05, 0.05]
velocity = [4.5, 0.0, 0.0]
radius = 0.003
material = "grain"

[[solids.blocks]]
min = [0.01, 0.01, 0.01]
max = [0.03, 0.03, 0.03]
spacing = 0.01
radius = 0.003
material = "grain"

[output]
checkpoint_interval = 0.005
EOF

# ---------------------------------------------------------------------------------------------------------------
# 1. Help and usage errors.
exit_code_lines=("  0    success" "  1    bad command line" "  2    invalid scene or checkpoint" "  3    the run stopped"
                 "  4    output could not be written" "  130  interrupted by SIGINT" "  143  terminated by SIGTERM")
riffle_as help --help
expect_rc "riffle --help exits 0" help 0
check "riffle --help lists the subcommands, --log-level and the exit codes" \
  contains help.out "run" "check" "resume" "--log-level" "Exit codes:" "${exit_code_lines[@]}"
for sub in run resume check; do
  riffle_as "help_$sub" "$sub" --help
  expect_rc "riffle $sub --help exits 0" "help_$sub" 0
  options=(--log-level)
  [ "$sub" != check ] && options+=(--out --threads --until)
  check "riffle $sub --help mentions ${options[*]} and the exit codes" \
    contains "help_$sub.out" "Usage: riffle $sub" "${options[@]}" "Exit codes:" "${exit_code_lines[@]}"
done
riffle_as usage_sub frobnicate
expect_rc "an unknown subcommand exits 1" usage_sub 1
riffle_as usage_none
expect_rc "no subcommand exits 1" usage_none 1
riffle_as usage_opt run small.toml --bogus
expect_rc "an unknown option exits 1" usage_opt 1
riffle_as usage_threads run small.toml --threads 0 --out usage_threads
expect_rc "--threads 0 exits 1" usage_threads 1
riffle_as usage_level run small.toml --log-level loud --out usage_level
expect_rc "an unknown --log-level exits 1" usage_level 1
# Runs over several ranks are tested under a real mpiexec (tests/mpi/run_over_ranks.sh); a build without MPI must
# refuse to be one of several ranks rather than run the whole scene N times into one folder.
if "$RIFFLE" --version | grep -qF "(no MPI)"; then
  OMPI_COMM_WORLD_SIZE=2 riffle_as two_ranks run small.toml --out two_ranks
  expect_rc "a build without MPI started as one of several ranks (mpirun -np 2) exits 1 before it reads the scene" \
    two_ranks 1
  check "... saying it was built without MPI, with nothing written" \
    bash -c "grep -qF 'built without MPI' '$WORK/two_ranks.err' && [ ! -e '$WORK/two_ranks' ]"
fi
OMPI_COMM_WORLD_SIZE=1 riffle_as one_rank check small.toml
expect_rc "mpirun -np 1 runs as without mpirun" one_rank 0
riffle_as level_after check small.toml --log-level warn
expect_rc "--log-level is accepted after the subcommand" level_after 0

# ---------------------------------------------------------------------------------------------------------------
# 2. Scene validation.
riffle_as check_seed check "$SRC/scenes/free_fall_box.toml"
expect_rc "riffle check scenes/free_fall_box.toml exits 0" check_seed 0
check "riffle check reports the valid scene on stdout" contains check_seed.out "valid scene 'free_fall_box'"
check "riffle check writes no output directory" test ! -e out
riffle_as graph_seed graph "$SRC/scenes/free_fall_box.toml"
expect_rc "riffle graph scenes/free_fall_box.toml exits 0" graph_seed 0
check "riffle graph prints the step graph as DOT, the sub-step loop as a cluster" \
  contains graph_seed.out 'digraph "step" {' '"solid_substeps"' 'subgraph "cluster_substep"' '"solid_kick_drift"'
check "riffle graph writes no output directory" test ! -e out
riffle_as graph_typo graph typo.toml
expect_rc "riffle graph on a scene with a typo key exits 2" graph_typo 2
riffle_as check_typo check typo.toml
expect_rc "riffle check on a scene with a typo key exits 2" check_typo 2
check "the typo is reported as file:line:column: key: message" \
  contains check_typo.err "typo.toml:4:1: run.end_tme: unknown key"
check "the required key the typo hides is reported too" contains check_typo.err "run.end_time: missing required key"
riffle_as check_missing check no_such_scene.toml
expect_rc "riffle check on a missing file exits 2" check_missing 2
check "the missing file is named" contains check_missing.err "no_such_scene.toml"
riffle_as run_missing run no_such_scene.toml --out run_missing
expect_rc "riffle run on a missing file exits 2" run_missing 2
riffle_as resume_missing resume no_such.ckpt --out resume_missing
expect_rc "riffle resume on a missing checkpoint exits 2" resume_missing 2
check "the missing checkpoint is named" contains resume_missing.err "no_such.ckpt"
riffle_as run_typo run typo.toml --out run_typo
expect_rc "riffle run on an invalid scene exits 2" run_typo 2
check "riffle run on an invalid scene writes nothing" test ! -e run_typo

# --set KEY=VALUE overrides a scene key; its problems name the --set; a run stores the changed scene in its
# checkpoints, so a resume needs no command line to rebuild it.
riffle_as set_check check small.toml --set run.end_time=0.02 --set 'tank.motion.amplitude=0.02'
expect_rc "riffle check with two --set exits 0" set_check 0
check "... and reports the overridden end time" contains set_check.out "t_end = 0.02 s"
riffle_as set_unknown check small.toml --set run.nonsense=1 --set run.dt=-1 --set run.end_time
expect_rc "riffle check with bad --set values exits 2" set_unknown 2
check "... each problem naming its --set" contains set_unknown.err "--set run.nonsense=1: run.nonsense: unknown key" \
  "--set run.dt=-1: run.dt: expected a number > 0" "--set run.end_time: expected KEY=VALUE"
riffle_as set_run run small.toml --set run.end_time=0.004 --set output.checkpoint_interval=0.002 --out set_run \
  --threads 1 --log-level warn
expect_rc "riffle run with --set exits 0" set_run 0
check "... ends at the overridden time (4 steps)" test "$(data_rows set_run/diagnostics.csv)" = 4
check "... and its checkpoints record the overrides" grep -qaF -- "--set run.end_time=0.004" \
  set_run/checkpoints/final.ckpt
check "... as does the scene it writes beside its outputs, which reads back with the changed values" \
  contains set_run/scene_as_run.toml "--set run.end_time=0.004" "end_time = 0.004"
riffle_as set_as_run check set_run/scene_as_run.toml
expect_rc "... and passes riffle check as it stands" set_as_run 0
riffle_as set_resume resume set_run/checkpoints/$(ckpt_name 2) --out set_resumed --threads 1 --log-level warn
expect_rc "a checkpoint of a --set run resumes without the --set" set_resume 0
check "... to the overridden end time (step 4)" test -e "set_resumed/checkpoints/$(ckpt_name 4)"

# ---------------------------------------------------------------------------------------------------------------
# 3. Outputs of a run (also run A of check 4: two threads, 50 steps).
riffle_as A run small.toml --out A --threads 2
expect_rc "riffle run on a small scene exits 0" A 0
final=$(ckpt_name 50)
grains=$(grep -a -o 'NumberOfPoints="[0-9]*"' A/vtk/solids_000000.vtp 2>/dev/null | head -n 1 | tr -dc 0-9)
diagnostics_ok() {
  head -n 1 A/diagnostics.csv | grep -q '^step,time_s,dt_s,' || { echo "#   bad header"; return 1; }
  local steps
  steps=$(tail -n +2 A/diagnostics.csv | cut -d, -f1 | tr '\n' ' ')
  [ "$steps" = "$(seq -s ' ' 1 50) " ] || { echo "#   steps: $steps"; return 1; }
  # Every row has as many fields as the header.
  awk -F, 'NR == 1 { n = NF } NF != n { exit 1 }' A/diagnostics.csv || { echo "#   ragged rows"; return 1; }
}
check "diagnostics.csv has a header and one row per step (1..50)" diagnostics_ok
timings_ok() {
  # The systems in timings.csv are exactly the wall_<system>_s columns of diagnostics.csv, once each (the rows of
  # phase "branch" are the wall times of the step's branches, not systems).
  local from_timings from_diagnostics
  from_timings=$(tail -n +2 A/timings.csv | grep -v '^[^,]*,branch,' | cut -d, -f1 | grep -v '^stepping$' | sort)
  from_diagnostics=$(head -n 1 A/diagnostics.csv | tr ',' '\n' | sed -n 's/^wall_\(.*\)_s$/\1/p' | sort)
  [ -n "$from_timings" ] && [ "$from_timings" = "$from_diagnostics" ] &&
    [ "$(printf '%s\n' "$from_timings" | uniq -d)" = "" ] &&
    head -n 1 A/timings.csv | grep -q '^system,' && grep -q '^stepping,' A/timings.csv ||
    { echo "#   timings: $(echo $from_timings) / diagnostics: $(echo $from_diagnostics)"; return 1; }
}
check "timings.csv has one row per system (those of diagnostics.csv) and a stepping row" timings_ok
frames_ok() {
  local kind k f
  for kind in solids walls; do
    [ "$(grep -c '<DataSet' "A/$kind.pvd")" = 6 ] || { echo "#   $kind.pvd does not list 6 frames"; return 1; }
    for k in 0 1 2 3 4 5; do
      f=$(printf 'vtk/%s_%06d.vtp' "$kind" "$k")
      grep -qF "file=\"$f\"" "A/$kind.pvd" && grep -q '^<VTKFile type="PolyData"' "A/$f" ||
        { echo "#   $kind frame $k missing"; return 1; }
    done
  done
  [ "$(ls A/vtk/*.vtp | wc -l)" = 12 ] || { echo "#   expected 12 .vtp files: $(ls A/vtk)"; return 1; }
  grep -qF 'timestep="0.05"' A/solids.pvd || { echo "#   no frame at t = 0.05"; return 1; }
}
check "solids.pvd and walls.pvd list 6 frames (t = 0 .. 0.05 s), each a vtk/*.vtp file" frames_ok
check "the solids frames hold every grain (${grains:-?} > 3000)" test "${grains:-0}" -gt 3000
check "the final checkpoint A/checkpoints/$final exists and is a riffle checkpoint" \
  test "$(head -c 8 "A/checkpoints/$final" 2>/dev/null)" = RIFFLECP
check "the interval checkpoints of steps 10..40 are kept" \
  test -f "A/checkpoints/$(ckpt_name 10)" -a -f "A/checkpoints/$(ckpt_name 40)"
check "no temporary files are left behind" test -z "$(find A -name '*.tmp')"
check "the log names the final checkpoint" contains A.err "final checkpoint: A/checkpoints/$final"

# ---------------------------------------------------------------------------------------------------------------
# 4. Determinism: resume == uninterrupted run, and --threads 1 == --threads 2, byte for byte.
riffle_as B resume "A/checkpoints/$(ckpt_name 20)" --out B --until 0.05 --threads 2
expect_rc "riffle resume from A's step-20 checkpoint into B exits 0" B 0
check "B's final checkpoint is byte-identical to A's" cmp "A/checkpoints/$final" "B/checkpoints/$final"
check "B's step-30 interval checkpoint is byte-identical to A's" \
  cmp "A/checkpoints/$(ckpt_name 30)" "B/checkpoints/$(ckpt_name 30)"
physics() { tail -n +2 "$1" | cut -d, -f1-11; }  # drops the wall-clock columns
# B is another folder than the checkpoint's: its series start with A's rows up to the checkpoint (steps 1..20), so
# the folder holds the whole run's, as A's does.
check "B's diagnostics rows (steps 1..20 carried from A, 21..50 its own) equal A's, wall-clock columns aside" \
  same_text "$(physics B/diagnostics.csv)" "$(physics A/diagnostics.csv)"
check "B's log says which series it carried from A" contains B.err "carried from $WORK/A " "diagnostics.csv"
b_frames_ok() {
  local k f
  for k in 0 1 2; do  # before the checkpoint: A's frames, where they are
    f=$(printf '../A/vtk/solids_%06d.vtp' "$k")
    grep -qF "file=\"$f\"" B/solids.pvd && [ -f "B/$f" ] || { echo "#   frame $k is not listed as $f"; return 1; }
  done
  for k in 3 4 5; do  # after it: B's own
    f=$(printf 'vtk/solids_%06d.vtp' "$k")
    grep -qF "file=\"$f\"" B/solids.pvd && [ -f "B/$f" ] || { echo "#   frame $k is not B's $f"; return 1; }
  done
  [ ! -e B/vtk/solids_000000.vtp ] || { echo "#   A's frames were copied into B"; return 1; }
}
check "B's solids.pvd lists the whole run: A's frames 0-2 by their path from B, its own 3-5" b_frames_ok
# B resumed again in its own folder keeps the links to A's frames; a checkpoint copied out of its run's checkpoints/
# names no run, so its resume into another folder carries nothing.
riffle_as B_again resume "B/checkpoints/$(ckpt_name 40)" --until 0.05 --threads 2
expect_rc "B resumed in place from its step-40 checkpoint exits 0" B_again 0
check "... and its solids.pvd still lists A's frames 0-2 and its own 3-5" b_frames_ok
cp "A/checkpoints/$(ckpt_name 20)" loose.ckpt
riffle_as loose resume loose.ckpt --out loose_out --until 0.025 --threads 2
expect_rc "a checkpoint outside any checkpoints/ folder resumes" loose 0
check "... carrying no series: its diagnostics start after the checkpoint (steps 21..25)" \
  test "$(tail -n +2 loose_out/diagnostics.csv | cut -d, -f1 | tr '\n' ' ')" = "21 22 23 24 25 "
riffle_as T1 run small.toml --out T1 --threads 1
expect_rc "riffle run --threads 1 exits 0" T1 0
check "--threads 1 and --threads 2 write byte-identical final checkpoints" \
  cmp "T1/checkpoints/$final" "A/checkpoints/$final"
check "--threads 1 and --threads 2 write identical diagnostics, wall-clock columns aside" \
  same_text "$(physics T1/diagnostics.csv)" "$(physics A/diagnostics.csv)"

# Resuming by a bare file name from inside checkpoints/ continues in the run directory (T1), not in checkpoints/.
rm -f "T1/checkpoints/$final"
(cd T1/checkpoints && riffle_as T1_inside resume "$(ckpt_name 40)")
expect_rc "riffle resume from inside checkpoints/ exits 0" T1_inside 0
check "... and continues in the run directory, to the same final checkpoint" \
  cmp "T1/checkpoints/$final" "A/checkpoints/$final"
check "a finished run also writes checkpoints/final.ckpt, identical to its last checkpoint" \
  cmp T1/checkpoints/final.ckpt "T1/checkpoints/$(ls T1/checkpoints | grep '^step_[0-9]*\.ckpt$' | tail -n 1)"
check "... and writes nothing inside checkpoints/ but checkpoints" \
  test -z "$(ls T1/checkpoints | grep -v -e '^step_[0-9]*\.ckpt$' -e '^final\.ckpt$')"

# ---------------------------------------------------------------------------------------------------------------
# 5. Damaged checkpoints are refused.
good="A/checkpoints/$final"
size=$(wc -c <"$good")
# Neutral file names, so that the words looked for cannot come from the path in the message.
head -c $((size - 100)) "$good" >damaged_1.ckpt
riffle_as truncated resume damaged_1.ckpt --out truncated_out
expect_rc "a truncated checkpoint is refused with exit 2" truncated 2
check "the refusal says 'truncated'" contains truncated.err "truncated"
cp "$good" damaged_2.ckpt
offset=$((size / 2))
byte=$(od -An -tu1 -j "$offset" -N 1 "$good" | tr -d ' ')
printf "\\$(printf '%03o' $((byte ^ 0x10)))" | dd of=damaged_2.ckpt bs=1 seek="$offset" count=1 conv=notrunc 2>/dev/null
check "the bit-flipped copy has the same size but differs" \
  test "$(wc -c <damaged_2.ckpt)" = "$size" -a "$(cmp -l "$good" damaged_2.ckpt 2>/dev/null | wc -l)" = 1
riffle_as flipped resume damaged_2.ckpt --out flipped_out
expect_rc "a bit-flipped checkpoint is refused with exit 2" flipped 2
check "the refusal says 'corrupted'" contains flipped.err "corrupted"
riffle_as not_ckpt resume small.toml --out not_ckpt_out
expect_rc "a file that is not a checkpoint is refused with exit 2" not_ckpt 2
check "the refusal says it is not a riffle checkpoint" contains not_ckpt.err "not a riffle checkpoint"
check "a refused resume writes nothing" test ! -e truncated_out -a ! -e flipped_out -a ! -e not_ckpt_out

# ---------------------------------------------------------------------------------------------------------------
# 6. SIGINT and SIGTERM: a checkpoint is written, the exit code says which signal, the run can be resumed.
# A non-interactive bash starts background jobs with SIGINT ignored; `trap - INT` in the subshell undoes that
# before exec, so the signal reaches riffle the way a Ctrl-C would.
signal_test() {
  local signal=$1 code=$2 dir=sig_$1 pid waited=0 got ckpts ckpt step
  if [ "$signal" = INT ]; then
    (trap - INT; exec "$RIFFLE" run long.toml --out "$dir" --threads 1 --until 1000 >"$dir.out" 2>"$dir.err") &
  else
    "$RIFFLE" run long.toml --out "$dir" --threads 1 --until 1000 >"$dir.out" 2>"$dir.err" &
  fi
  pid=$!
  background_pid=$pid
  # Wait (at most 30 s) for three diagnostics rows, i.e. 60 steps.
  while [ "$(data_rows "$dir/diagnostics.csv")" -lt 3 ] && kill -0 "$pid" 2>/dev/null &&
        [ $waited -lt 600 ]; do
    sleep 0.05
    waited=$((waited + 1))
  done
  if ! kill -0 "$pid" 2>/dev/null; then
    wait "$pid"
    not_ok "SIG$signal: the long run was still running when signalled" "it exited early with $?"
    show "$dir.err"
    return
  fi
  kill -s "$signal" "$pid"
  waited=0
  while kill -0 "$pid" 2>/dev/null && [ $waited -lt 300 ]; do
    sleep 0.05
    waited=$((waited + 1))
  done
  if kill -0 "$pid" 2>/dev/null; then
    kill -s KILL "$pid"
    wait "$pid" 2>/dev/null
    not_ok "SIG$signal stops the run within 15 s" "still running; killed"
    return
  fi
  wait "$pid"
  got=$?
  background_pid=
  if [ "$got" = "$code" ]; then ok "SIG$signal: riffle exits $code"; else not_ok "SIG$signal: riffle exits $code" "got $got"; show "$dir.err"; fi
  ckpts=$(ls "$dir/checkpoints" 2>/dev/null | grep -c '^step_[0-9]*\.ckpt$')
  ckpt=$(ls "$dir/checkpoints" 2>/dev/null | grep '^step_[0-9]*\.ckpt$' | tail -n 1)
  check "SIG$signal: one checkpoint was written ($ckpt)" test "$ckpts" = 1
  [ -n "$ckpt" ] || ckpt=none
  check "SIG$signal: stderr names the signal and where the checkpoint is" \
    contains "$dir.err" "stopped by SIG$signal" "checkpoint: $dir/checkpoints/$ckpt" "riffle resume $dir/checkpoints/$ckpt"
  step=$(echo "$ckpt" | tr -dc 0-9 | sed 's/^0*//')
  step=${step:-0}
  check "SIG$signal: it was stopped mid-run (step $step >= 60)" test "$step" -ge 60
  # Resume into the same run directory (the default) for 25 more steps; diagnostics rows come every 20 steps.
  local target=$((step + 25))
  riffle_as "${dir}_resume" resume "$dir/checkpoints/$ckpt" --until "$(awk -v s="$target" 'BEGIN { printf "%.6f", s * 1e-3 }')"
  expect_rc "SIG$signal: resuming from its checkpoint for 25 steps exits 0" "${dir}_resume" 0
  check "SIG$signal: the resumed run continues in the same directory to step $target" \
    test -f "$dir/checkpoints/$(ckpt_name $target)"
  check "SIG$signal: diagnostics.csv continues without repeated rows, to step $((target / 20 * 20))" \
    same_text "$(tail -n +2 "$dir/diagnostics.csv" | cut -d, -f1)" "$(seq 20 20 $target)"
}
signal_test INT 130
signal_test TERM 143

# ---------------------------------------------------------------------------------------------------------------
# 7. An unstable run stops with a diagnosis and keeps what it wrote.
riffle_as unstable run unstable.toml --out U --threads 2
expect_rc "a grain leaving the domain stops the run with exit 3" unstable 3
check "stderr names the particle id and the step" contains unstable.err "run stopped at step 14 " "particle id 1 left the domain"
check "stderr names the last good checkpoint" contains unstable.err "last good checkpoint: U/checkpoints/$(ckpt_name 10)"
check "the last good checkpoint is on disk" test -f "U/checkpoints/$(ckpt_name 10)"
check "diagnostics.csv still holds the rows of steps 1..14" \
  same_text "$(tail -n +2 U/diagnostics.csv 2>/dev/null | cut -d, -f1)" "$(seq 1 14)"
riffle_as unstable_resume resume "U/checkpoints/$(ckpt_name 10)" --out U2 --until 0.013
expect_rc "the last good checkpoint resumes (to step 13, before the failure)" unstable_resume 0

# ---------------------------------------------------------------------------------------------------------------
# 8. The fluid: a shipped scene runs and writes its outputs; a bad key is named; a blow-up stops with a diagnosis.
riffle_as dam run "$SRC/scenes/dam_break.toml" --out D --until 0.02 --threads 2
expect_rc "the dam-break scene runs" dam 0
check "it writes fluid frames" test -f D/fluid.pvd
check "diagnostics.csv reports the PPE iterations and residual" contains D/diagnostics.csv "ppe_iterations,ppe_relative_residual"
check "the surge-front probe has rows" test "$(data_rows D/probe_front.csv)" -ge 5
check "the timing table lists the pressure solve" contains dam.err "fluid_pressure"
# A pressure solve cut short (2 iterations) goes on, but says so: the 1st, 2nd, 4th, ... such step, and the count.
riffle_as short_solve run "$SRC/scenes/dam_break.toml" --out SS --until 0.01 --threads 2 --set fluid.solver_max_iterations=2
expect_rc "a run whose pressure solves stop short of the tolerance finishes" short_solve 0
check "... warning at the first such step with the residual and the limit" \
  contains short_solve.err "the pressure solve stopped at |r|/|b|" "fluid.solver_max_iterations = 2" "1 such step(s) so far"
check "... not at every step, and counting them at the end" \
  bash -c "[ \$(grep -c 'the pressure solve stopped' short_solve.err) -lt \$(grep -o 'after [0-9]* steps' short_solve.err | grep -o '[0-9]*') ] && grep -q 'step(s) went on with a pressure solve short of its tolerance' short_solve.err"
check "the dam break with the default solve has no such warning" bash -c "! grep -q 'pressure solve stopped' dam.err"
sed 's/^spacing = 0.005 .*/spacing = 0.005\nsurface_treshold = 0.9/' "$SRC/scenes/dam_break.toml" > bad_fluid.toml
riffle_as bad_fluid check bad_fluid.toml
expect_rc "a misspelt [fluid] key exits 2" bad_fluid 2
check "the error names the file, line and key" contains bad_fluid.err "bad_fluid.toml:" "fluid.surface_treshold"
sed -e 's/^high = \[0.1, 0.02, 0.2\]/high = [0.1, 0.02, 0.2]\nvelocity = [20.0, 0.0, 0.0]/' \
    -e 's/^spacing = 0.005 .*/spacing = 0.005\nmin_dt = 1.0e-4/' "$SRC/scenes/dam_break.toml" > fast_fluid.toml
riffle_as fast_fluid run fast_fluid.toml --out F --threads 2
expect_rc "a fluid whose Courant step falls below min_dt stops with exit 3" fast_fluid 3
check "the diagnosis names the time-step collapse and the limit that set it" \
  contains fast_fluid.err "below fluid.min_dt" "courant limit"
# A splash out of a low open tank: escaped droplets are removed and counted, and the run finishes.
riffle_as splash run "$SRC/tests/data/splash_escape.toml" --out SPL --threads 2
expect_rc "a splash that throws water out of an open tank finishes" splash 0
check "diagnostics.csv has the removed-particle columns" \
  contains SPL/diagnostics.csv "ppe_unknowns,fluid_removed_particles,fluid_removed_mass_kg"
check "the fluid_totals probe has the removed-particle columns" \
  contains SPL/probe_fluid_totals.csv "ppe_residual,removed_particles,removed_mass_kg,removed_volume_m3"
# The last totals row: water + removed = the 288 particles laid out, and something was removed (rho l0^3 = 1 g each).
splash_totals=$(tail -n 1 SPL/probe_fluid_totals.csv |
  awk -F, '{ d = $12 - $11 * 0.001; print $3 + $11, ($11 > 0), (d * d < 1e-20) }')
check "the last totals row: 288 particles in water + removed, some removed, 1 g each (got: $splash_totals)" \
  test "$splash_totals" = "288 1 1"
check "the log names each removed particle and the run's summary the count" \
  contains splash.err "removed: " "fluid particles removed as escaped"
# By reason: the domain's edge and the lone droplets add up to the removed count, in both CSVs, and this splash has
# some of each (droplets over the walls, and a few thrown up out of the domain).
splash_reasons=$(tail -n 1 SPL/probe_fluid_totals.csv | awk -F, '{ print ($14 + $15 == $11), ($14 > 0), ($15 > 0) }')
check "the totals' removals by reason add up, and both reasons occur (got: $splash_reasons)" \
  test "$splash_reasons" = "1 1 1"
check "diagnostics.csv has the removals by reason" \
  contains SPL/diagnostics.csv "fluid_removed_mass_kg,fluid_removed_left_domain,fluid_removed_lone_droplets"
sed 's/^escape_fraction_limit = 0.2/escape_fraction_limit = 0.01/' "$SRC/tests/data/splash_escape.toml" > splash_limit.toml
riffle_as splash_limit run splash_limit.toml --out SPL_limit --threads 2
expect_rc "more escaped water than fluid.escape_fraction_limit stops the run with exit 3" splash_limit 3
check "the diagnosis names the limit and says how to go on" \
  contains splash_limit.err "removed as escaped, more than fluid.escape_fraction_limit = 0.01" "last good checkpoint"
# A long run (1000 steps of dt) without output.checkpoint_interval checkpoints every end_time / 10 = 0.1 s: its stop
# (18 of 288 removed at t = 0.135 s, above 5 %) names the checkpoint of t = 0.1 s, which resumes to the same stop.
sed -e 's/^end_time = 0.15 .*/end_time = 1.0/' -e 's/^escape_fraction_limit = 0.2/escape_fraction_limit = 0.05/' \
  "$SRC/tests/data/splash_escape.toml" > splash_long.toml
riffle_as splash_long run splash_long.toml --out SPL_long --threads 2
expect_rc "a long splash above its escape limit stops with exit 3" splash_long 3
splash_ckpt=$(ls SPL_long/checkpoints 2>/dev/null | grep '^step_[0-9]*\.ckpt$' | tail -n 1)
check "without checkpoint_interval a long run wrote a default checkpoint before the stop ($splash_ckpt)" \
  test -n "$splash_ckpt"
[ -n "$splash_ckpt" ] || splash_ckpt=none
check "the diagnosis names it and how to go on from it" \
  contains splash_long.err "last good checkpoint: SPL_long/checkpoints/$splash_ckpt" \
  "riffle resume SPL_long/checkpoints/$splash_ckpt"
riffle_as splash_long_resume resume "SPL_long/checkpoints/$splash_ckpt" --out SPL_long2 --threads 1
expect_rc "resuming from it exits 3 again" splash_long_resume 3
stop_first=$(grep -o 'run stopped at step [0-9]*[^:]*: [0-9]* of' splash_long.err | head -n 1)
stop_resumed=$(grep -o 'run stopped at step [0-9]*[^:]*: [0-9]* of' splash_long_resume.err | head -n 1)
check "... at the same step, with the same removed count ($stop_first)" \
  test -n "$stop_first" -a "$stop_first" = "$stop_resumed"
reasons_first=$(grep -o '[0-9]* left the domain, [0-9]* lone droplets)' splash_long.err | tail -n 1)
reasons_resumed=$(grep -o '[0-9]* left the domain, [0-9]* lone droplets)' splash_long_resume.err | tail -n 1)
check "... and the same removals by reason, carried in the checkpoint ($reasons_first)" \
  test -n "$reasons_first" -a "$reasons_first" = "$reasons_resumed"
# A channel driven to a bulk velocity: the controller's integral is in the checkpoint, so a resume from the middle
# ends in the same bytes as the straight run.
sed -e 's/^end_time = 0.01$/end_time = 0.02/' "$SRC/tests/data/scene_keys/fluid_bulk_velocity.toml" > bulk.toml
printf '\n[output]\ncheckpoint_interval = 0.01\nvtk_interval = 0.0\n' >> bulk.toml
riffle_as bulk run bulk.toml --out BULK --threads 2
expect_rc "a channel held at a bulk velocity runs" bulk 0
riffle_as bulk_resume resume "BULK/checkpoints/$(ckpt_name 10)" --out BULK2 --threads 2
expect_rc "... and resumes from its step-10 checkpoint" bulk_resume 0
check "... to the straight run's final checkpoint, byte for byte (the controller's integral carried)" \
  cmp BULK/checkpoints/final.ckpt BULK2/checkpoints/final.ckpt

# ---------------------------------------------------------------------------------------------------------------
# 9. Where the outputs go and how long the run is: --until, --out, run.name, dt against end_time.
riffle_as until_nan run small.toml --out until_nan --until nan
expect_rc "--until nan exits 1" until_nan 1
check "... naming the option and the value" contains until_nan.err "--until: expected a finite time > 0 s, got nan"
riffle_as until_inf run small.toml --out until_inf --until inf
expect_rc "--until inf exits 1" until_inf 1
riffle_as until_far run small.toml --out until_far --until 1e10
expect_rc "--until 1e10 with dt = 1 ms (1e13 steps) exits 1" until_far 1
check "... naming the 1e12-step limit" contains until_far.err "more than 1e12 steps"
riffle_as until_short run small.toml --out until_short --until 0.0004
expect_rc "--until shorter than one step exits 1" until_short 1
check "... saying the run would end before its first step" contains until_short.err "less than one step (dt = 0.001 s)"
riffle_as until_past resume "A/checkpoints/$(ckpt_name 20)" --out until_past --until 0.01
expect_rc "resume --until before the checkpoint's time exits 1" until_past 1
check "... naming the checkpoint's time" contains until_past.err "--until 0.01 s is not after the checkpoint's time"
check "the refused --until runs write nothing" \
  test ! -e until_nan -a ! -e until_inf -a ! -e until_far -a ! -e until_short -a ! -e until_past
sed 's/^dt = 1.0e-3/dt = 0.06/' small.toml >long_dt.toml
riffle_as long_dt check long_dt.toml
expect_rc "a dt longer than end_time exits 2" long_dt 2
check "... as file:line:column: key: message" \
  contains long_dt.err "long_dt.toml:4:6: run.dt: dt = 0.06 s is longer than end_time = 0.05 s"
# `check`, not `run`: without the fix a run of this scene writes into the folder three levels above out/.
sed 's|^name = "cli_small"|name = "../../.."|' small.toml >escape_name.toml
riffle_as escape_name check escape_name.toml
expect_rc "run.name = \"../../..\" exits 2" escape_name 2
check "... naming run.name" \
  contains escape_name.err "escape_name.toml:2:8: run.name: expected a plain folder name without '/'"
sed 's|^name = "cli_small"|name = "nul\\u0000name"|' small.toml >nul_name.toml
riffle_as nul_name check nul_name.toml
expect_rc "a run.name with a NUL character exits 2 (a run aborted with SIGABRT)" nul_name 2
check "... naming run.name" \
  contains nul_name.err "nul_name.toml:2:8: run.name: expected a name without control characters"
riffle_as out_file run small.toml --out small.toml/out
expect_rc "an --out that cannot be created exits 4" out_file 4
check "... with a message naming it" contains out_file.err "cannot create the output directory 'small.toml/out'"
mkdir -p log_blocked/riffle.log
riffle_as log_blocked run small.toml --out log_blocked
expect_rc "a riffle.log that cannot be opened exits 4 (it aborted with SIGABRT)" log_blocked 4
check "... naming the log file" contains log_blocked.err "log_blocked/riffle.log: cannot open the log file"

# ---------------------------------------------------------------------------------------------------------------
# 10. One run per output folder: a second run or resume into a folder a run is writing is refused at once.
"$RIFFLE" run long.toml --out busy --threads 1 --until 1000 >busy.out 2>busy.err &
busy_pid=$!
background_pid=$busy_pid
waited=0
while [ "$(data_rows busy/diagnostics.csv)" -lt 2 ] && kill -0 "$busy_pid" 2>/dev/null && [ $waited -lt 600 ]; do
  sleep 0.05
  waited=$((waited + 1))
done
riffle_as second_run run long.toml --out busy --until 0.005
expect_rc "a second run into a folder another run is writing exits 4" second_run 4
check "... naming the folder and the run holding it" \
  contains second_run.err "busy: another riffle run (pid $busy_pid) is writing into this output folder"
riffle_as second_resume resume "A/checkpoints/$(ckpt_name 20)" --out busy --until 0.03
expect_rc "a resume into it exits 4 too" second_resume 4
kill -s TERM "$busy_pid" 2>/dev/null
wait "$busy_pid"
busy_rc=$?
background_pid=
check "the first run was undisturbed and stops on SIGTERM (exit $busy_rc)" test "$busy_rc" = 143
busy_rows=$(data_rows busy/diagnostics.csv)
check "its diagnostics.csv holds only its own rows (steps 20, 40, ...)" \
  same_text "$(tail -n +2 busy/diagnostics.csv | cut -d, -f1)" "$(seq 20 20 $((busy_rows * 20)))"
riffle_as reuse_busy run small.toml --out busy --until 0.002
expect_rc "once it has exited the folder is free again (the kernel dropped its lock)" reuse_busy 0

# ---------------------------------------------------------------------------------------------------------------
# 11. Ctrl-C inside a step of a million sub-steps: the step is abandoned (no checkpoint of a half-done step) and
# riffle exits 130 within a few seconds. It used to finish the step first, tens of seconds later.
cat >long_step.toml <<'EOF'
[run]
name = "cli_long_step"
end_time = 1.0
dt = 1.0e-3
solid_substeps = 1000000
gravity = [0.0, 0.0, 0.0]

[materials.grain]
density = 1318.0

[tank]
size = [0.10, 0.10, 0.10]
wall_material = "grain"

[[solids.blocks]]
min = [0.02, 0.02, 0.02]
max = [0.08, 0.08, 0.08]
spacing = 0.006
radius = 0.002
material = "grain"
EOF
(trap - INT; exec "$RIFFLE" run long_step.toml --out long_step --threads 1 >long_step.out 2>long_step.err) &
step_pid=$!
background_pid=$step_pid
waited=0
while ! grep -q "starting 'cli_long_step'" long_step.err 2>/dev/null && kill -0 "$step_pid" 2>/dev/null &&
      [ $waited -lt 600 ]; do
  sleep 0.05
  waited=$((waited + 1))
done
sleep 1  # well inside the first step
kill -s INT "$step_pid"
waited=0
while kill -0 "$step_pid" 2>/dev/null && [ $waited -lt 200 ]; do
  sleep 0.05
  waited=$((waited + 1))
done
if kill -0 "$step_pid" 2>/dev/null; then
  kill -s KILL "$step_pid"
  wait "$step_pid" 2>/dev/null
  not_ok "SIGINT inside a long step stops riffle within 10 s" "still running; killed"
else
  wait "$step_pid"
  step_rc=$?
  check "SIGINT inside a long step stops riffle within 10 s, exit 130 (got $step_rc)" test "$step_rc" = 130
fi
background_pid=
check "... saying the step was abandoned and that no checkpoint exists yet" \
  contains long_step.err "stopped by SIGINT during step 1" "the step was abandoned and no checkpoint of it written" \
  "last good checkpoint: none written yet"
check "... and writes no checkpoint of the half-done step" test -z "$(ls long_step/checkpoints 2>/dev/null)"

# ---------------------------------------------------------------------------------------------------------------
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
