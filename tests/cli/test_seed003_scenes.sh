#!/usr/bin/env bash
# Seed 003's sheared beds and the oscillatory sheet flow (scenes/sheared_bed_*.toml, scenes/oscillatory_sheet_flow.toml)
# wait for the periodic MPS water and the coupling across the seam (issue 24). Until then `riffle check` must refuse
# each of them for that reason ONLY: exactly one problem, the `tank.periodic` refusal of `[fluid]`. And the same scene
# with its periodic axes removed (a closed box) must be valid and run its first steps (1 ms), so nothing else in it is
# wrong. (Only the first steps: closed, a lid that spans the box has its own seam at the water's ends, which
# docs/SCENES.md "Lids" warns against, and at 1 m/s such a copy blows up after ~0.01 s.)
# WHEN PERIODIC WATER LANDS this test fails on the first check: replace it by `riffle check` passing on the scenes
# themselves (and keep the closed-box check or drop it).
# The sheared beds start from a bed settled dry by scenes/sheared_bed_*_settle.toml ([solids] initial_state): each
# settle scene (grains only, so periodic already) must be valid and run; its 1 ms checkpoint (periodic, and a closed
# copy's for the closed box) stands in for the settled bed, the sheared scene's initial_state pointed at it.
# Usage: test_seed003_scenes.sh RIFFLE SOURCE_DIR WORK_DIR
set -u
riffle=$1
source_dir=$2
work=$3
mkdir -p "$work"
status=0
for scene in sheared_bed_small sheared_bed_large sheared_bed_bidisperse oscillatory_sheet_flow; do
  file="$source_dir/scenes/$scene.toml"
  closed_bed=""
  if [ -f "$source_dir/scenes/${scene}_settle.toml" ]; then
    settle="$source_dir/scenes/${scene}_settle.toml"
    sed 's/^periodic = \["x", "y"\]$/# closed box: periodic removed/' "$settle" > "$work/${scene}_settle_closed.toml"
    for variant in periodic closed; do
      settle_file=$settle
      [ $variant = closed ] && settle_file="$work/${scene}_settle_closed.toml"
      if ! ran=$("$riffle" run "$settle_file" --until 0.001 --threads 1 --out "$work/${scene}_settle_$variant" 2>&1) ||
         [ ! -s "$work/${scene}_settle_$variant/checkpoints/final.ckpt" ]; then
        echo "FAIL $scene: its $variant settle scene does not run (or writes no final checkpoint):"
        echo "$ran" | tail -5
        status=1
      fi
    done
    grep -q '^initial_state = "../out/'"${scene}"'_settle/checkpoints/final.ckpt"' "$file" ||
      { echo "FAIL $scene: its initial_state is not its settle scene's final checkpoint"; status=1; }
    sed "s|^initial_state = .*|initial_state = \"$work/${scene}_settle_periodic/checkpoints/final.ckpt\"|" "$file" \
      > "$work/${scene}_periodic.toml"
    file="$work/${scene}_periodic.toml"
    closed_bed="$work/${scene}_settle_closed/checkpoints/final.ckpt"
  fi
  output=$("$riffle" check "$file" 2>&1)
  code=$?
  if [ $code -eq 0 ]; then
    echo "FAIL $scene: riffle check accepted it: periodic water has landed? update this test (see its header)"
    status=1
  elif ! grep -q "^1 problem(s) found" <<<"$output" ||
       ! grep -q "tank.periodic: a periodic box takes grains only for now" <<<"$output"; then
    echo "FAIL $scene: expected only the periodic-water refusal, got:"
    echo "$output"
    status=1
  fi
  grep -q '^periodic = \["x", "y"\]$' "$file" || { echo "FAIL $scene: no 'periodic = [\"x\", \"y\"]' line"; status=1; }
  sed 's/^periodic = \["x", "y"\]$/# closed box: periodic removed/' "$file" > "$work/${scene}_closed.toml"
  [ -n "$closed_bed" ] && sed -i "s|^initial_state = .*|initial_state = \"$closed_bed\"|" "$work/${scene}_closed.toml"
  if ! closed=$("$riffle" check "$work/${scene}_closed.toml" 2>&1); then
    echo "FAIL $scene: the closed-box copy is not valid:"
    echo "$closed"
    status=1
  elif ! ran=$("$riffle" run "$work/${scene}_closed.toml" --until 0.001 --threads 1 --out "$work/${scene}_run" 2>&1) ||
       [ ! -s "$work/${scene}_run/probe_bedload_flux.csv" ]; then
    echo "FAIL $scene: the closed-box copy does not run its first steps (or writes no bed-load probe):"
    echo "$ran" | tail -5
    status=1
  else
    echo "ok $scene: refused for periodic water only; closed-box copy valid and runs its first steps"
  fi
done
exit $status
