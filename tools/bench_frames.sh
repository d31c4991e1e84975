#!/usr/bin/env bash
# The ParaView frames' cost: the 5 mm seed scene (scenes/oscillating_tank.toml, from the settled seed bed) for 30 steps
# on 2 threads, with a frame every step (31 frames) in the scenes' format (raw appended arrays, single precision, no
# dummy particles) and as base64 doubles with the dummies, alternated, REPS times (default 3); and once without
# frames, for the set-up and the final checkpoint that the time outside the stepping also holds.
#   tools/bench_frames.sh [build-dir] [reps]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
reps=${2:-3}
work=$(mktemp -d /tmp/bench_frames.XXXXXX)
run() {  # name, then extra arguments
  local name=$1; shift
  rm -rf "$work/$name"
  local start end stepping
  start=$(date +%s.%N)
  "$build/riffle" run scenes/oscillating_tank.toml --until 0.03 --threads 2 --out "$work/$name" "$@" > "$work/$name.log" 2>&1
  end=$(date +%s.%N)
  stepping=$(grep "stepping (wall)" "$work/$name.log" | awk '{print $3}')
  printf '%s wall %.2f s, stepping %.2f s, outside the stepping %.2f s' "$name" "$(echo "$end - $start" | bc -l)" \
    "$stepping" "$(echo "$end - $start - $stepping" | bc -l)"
  if ls "$work/$name"/vtk/fluid_*.vtp > /dev/null 2>&1; then
    printf ', %d frames, %d bytes' "$(ls "$work/$name"/vtk/fluid_*.vtp | wc -l)" "$(du -sb "$work/$name/vtk" | cut -f1)"
  fi
  echo
}
echo "bench_frames: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), load $(cut -d' ' -f1-3 /proc/loadavg)"
run none --set output.vtk_interval=0
for rep in $(seq "$reps"); do
  run new --set output.vtk_interval=0.001
  run old --set output.vtk_interval=0.001 --set 'output.vtk_encoding="inline"' --set 'output.vtk_precision="double"' \
    --set output.vtk_dummy_particles=true
done
rm -rf "$work"
