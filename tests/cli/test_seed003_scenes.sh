#!/usr/bin/env bash
# Seed 003's sheared beds (the small one also in a box 4 x wider in x and y, for runs over MPI ranks) and the
# oscillatory sheet flow (scenes/sheared_bed_*.toml, scenes/oscillatory_sheet_flow.toml),
# and the mean-flow fluid's beds (scenes/sheared_bed_mean_flow.toml, sheared_bed_profile_forcing.toml,
# bedload_channel.toml, single_grain_channel.toml)
# are periodic along x and y with grains and water: since the coupling looks across the seam, `riffle check`
# must accept each of them, and each must run its first millisecond periodic and write its bed-load probe.
# (Only the first steps: the whole runs are studies, docs/RESULTS.md.)
# The sheared beds and the oscillatory sheet flow start from a bed settled dry by their scenes/*_settle.toml ([solids]
# initial_state): each settle scene must be valid and run; its 1 ms checkpoint stands in for the settled bed, the
# scene's initial_state pointed at it. A scene with a rough floor ([solids] fixed_below) must fix some of those grains.
# Usage: test_seed003_scenes.sh RIFFLE SOURCE_DIR WORK_DIR
set -u
riffle=$1
source_dir=$2
work=$3
mkdir -p "$work"
status=0
for scene in sheared_bed_small sheared_bed_small_wide sheared_bed_large sheared_bed_large_deep sheared_bed_bidisperse \
             oscillatory_sheet_flow sheared_bed_mean_flow bedload_channel single_grain_channel; do
  file="$source_dir/scenes/$scene.toml"
  grep -q '^periodic = \["x", "y"\]$' "$file" || { echo "FAIL $scene: no 'periodic = [\"x\", \"y\"]' line"; status=1; }
  if [ -f "$source_dir/scenes/${scene}_settle.toml" ]; then
    settle="$source_dir/scenes/${scene}_settle.toml"
    if ! ran=$("$riffle" run "$settle" --until 0.001 --threads 1 --out "$work/${scene}_settle" 2>&1) ||
       [ ! -s "$work/${scene}_settle/checkpoints/final.ckpt" ]; then
      echo "FAIL $scene: its settle scene does not run (or writes no final checkpoint):"
      echo "$ran" | tail -5
      status=1
    fi
    grep -q '^initial_state = "../out/'"${scene}"'_settle/checkpoints/final.ckpt"' "$file" ||
      { echo "FAIL $scene: its initial_state is not its settle scene's final checkpoint"; status=1; }
    sed "s|^initial_state = .*|initial_state = \"$work/${scene}_settle/checkpoints/final.ckpt\"|" "$file" \
      > "$work/${scene}.toml"
    file="$work/${scene}.toml"
  fi
  if ! output=$("$riffle" check "$file" 2>&1); then
    echo "FAIL $scene: riffle check refused it:"
    echo "$output"
    status=1
  elif ! ran=$("$riffle" run "$file" --until 0.001 --threads 1 --out "$work/${scene}_run" 2>&1) ||
       { [ ! -s "$work/${scene}_run/probe_bedload_flux.csv" ] &&
         [ ! -s "$work/${scene}_run/probe_bedload_transport.csv" ]; }; then
    echo "FAIL $scene: does not run its first steps periodic (or writes no bed-load probe):"
    echo "$ran" | tail -5
    status=1
  elif grep -q '^fixed_below = ' "$file" && ! grep -q 'of the grains are fixed for the whole run' <<<"$ran"; then
    echo "FAIL $scene: it sets fixed_below, but its run fixed no grain:"
    echo "$ran" | tail -5
    status=1
  else
    echo "ok $scene: valid, and runs its first steps periodic"
  fi
done
# The small bed under seed 003's own drive (scenes/sheared_bed_profile_forcing.toml: a free top, the water pulled
# towards the seed's 1/7-power profile) starts from the mean-flow small bed's settled checkpoint too; its first steps
# must pull the water (a positive Shields number in its probe) and `riffle check` must name the drive.
file="$source_dir/scenes/sheared_bed_profile_forcing.toml"
grep -q '^initial_state = "../out/sheared_bed_mean_flow_settle/checkpoints/final.ckpt"' "$file" ||
  { echo "FAIL sheared_bed_profile_forcing: its initial_state is not the mean-flow small bed's settled checkpoint"; status=1; }
sed "s|^initial_state = .*|initial_state = \"$work/sheared_bed_mean_flow_settle/checkpoints/final.ckpt\"|" "$file" \
  > "$work/sheared_bed_profile_forcing.toml"
if ! checked=$("$riffle" check "$work/sheared_bed_profile_forcing.toml" 2>&1) ||
   ! grep -q 'drive: pulled towards u = 0.6 m/s' <<<"$checked"; then
  echo "FAIL sheared_bed_profile_forcing: riffle check refused it or does not name its drive:"
  echo "$checked" | tail -5
  status=1
elif ! ran=$("$riffle" run "$work/sheared_bed_profile_forcing.toml" --until 0.012 --threads 1 \
               --out "$work/sheared_bed_profile_forcing_run" 2>&1) ||
     ! awk -F, 'NR > 2 && $3 > 0 { pulled = 1 } END { exit !pulled }' \
         "$work/sheared_bed_profile_forcing_run/probe_bedload_transport.csv"; then
  echo "FAIL sheared_bed_profile_forcing: does not run its first steps, or its drive puts no stress on the bed:"
  echo "$ran" | tail -5
  status=1
else
  echo "ok sheared_bed_profile_forcing: valid, names its drive, and its first steps pull the water over the bed"
fi

# The tilted bed (scenes/bed_tilt.toml, dry: the slope at which the small bed flows) starts from the mean-flow small
# bed's settle: valid, fixes its bottom layer, and runs its first steps periodic with gravity tilted.
file="$source_dir/scenes/bed_tilt.toml"
grep -q '^initial_state = "../out/sheared_bed_mean_flow_settle/checkpoints/final.ckpt"' "$file" ||
  { echo "FAIL bed_tilt: its initial_state is not the mean-flow small bed's settled checkpoint"; status=1; }
sed "s|^initial_state = .*|initial_state = \"$work/sheared_bed_mean_flow_settle/checkpoints/final.ckpt\"|" "$file" \
  > "$work/bed_tilt.toml"
if ! ran=$("$riffle" run "$work/bed_tilt.toml" --until 0.001 --threads 1 --out "$work/bed_tilt_run" \
             --set 'run.gravity=[3.355218, 0.0, -9.218385]' 2>&1) ||
   [ ! -s "$work/bed_tilt_run/probe_moving_fraction.csv" ]; then
  echo "FAIL bed_tilt: does not run its first steps tilted (or writes no moving-fraction probe):"
  echo "$ran" | tail -5
  status=1
elif ! grep -q 'of the grains are fixed for the whole run' <<<"$ran"; then
  echo "FAIL bed_tilt: it sets fixed_below, but its run fixed no grain:"
  echo "$ran" | tail -5
  status=1
else
  echo "ok bed_tilt: valid, fixes its floor, and runs its first steps tilted"
fi
exit $status
