#!/usr/bin/env bash
# The seed experiment's resolution study in the water spacing: the quick seed scene at water spacings of 20, 10 and 5 mm
# for 10 periods, with optional [coupling] lines added, then the centroid (Fig. 6) and force (Figs. 17-19) tables.
#
# Usage, from the repository root (needs out/dry_bed_settle, made by `build/riffle run scenes/dry_bed_settle.toml`):
#   tools/resolution_study.sh BINARY OUT_ROOT [COUPLING_LINE ...]
#   e.g. tools/resolution_study.sh build/riffle out/resolution/after 'added_mass = true' 'lubrication = true'
# Writes OUT_ROOT/l0_<mm>mm/ (the run and its figures/) and OUT_ROOT/summary.txt. Set SPACINGS="0.02 0.01" to run a
# subset, PERIODS to change the length, THREADS (default 2).
set -euo pipefail
binary=${1:?usage: $0 BINARY OUT_ROOT [COUPLING_LINE ...]}
out_root=${2:?usage: $0 BINARY OUT_ROOT [COUPLING_LINE ...]}
shift 2
spacings=${SPACINGS:-"0.02 0.01 0.005"}
periods=${PERIODS:-10}
threads=${THREADS:-2}
root=$(pwd)
mkdir -p "$out_root"
until_time=$(awk -v k="$periods" 'BEGIN { printf "%.6f", k / 1.7 }')
for spacing in $spacings; do
  mm=$(awk -v s="$spacing" 'BEGIN { printf "%g", s * 1000 }')
  run="$out_root/l0_${mm}mm"
  mkdir -p "$run"
  scene="$run/scene.toml"
  # The quick scene with its spacing, an absolute initial state, and the extra coupling lines after [coupling].
  sed -e "s|^spacing = 0.01 .*|spacing = $spacing|" \
      -e "s|^initial_state = \"../out/|initial_state = \"$root/out/|" scenes/oscillating_tank_quick.toml > "$scene.tmp"
  {
    while IFS= read -r line; do
      printf '%s\n' "$line"
      if [ "$line" = "[coupling]" ]; then for extra in "$@"; do printf '%s\n' "$extra"; done; fi
    done < "$scene.tmp"
  } > "$scene"
  rm -f "$scene.tmp"
  start=$(date +%s.%N)
  "$binary" run "$scene" --until "$until_time" --threads "$threads" --out "$run" --log-level warn > "$run/stdout.txt"
  awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f\n", b - a }' > "$run/wall_s.txt"
  tools/riffle-tools seed-figures "$run" --figures fig06 fig17_19 fig19 --stages "$((periods - 2))-$periods" \
      > "$run/figures.log" 2>&1 || echo "figures failed for $run (see $run/figures.log)"
done
/usr/bin/python3 "$root/tools/riffle-tools" resolution-summary "$out_root" > "$out_root/summary.txt"
cat "$out_root/summary.txt"
