#!/usr/bin/env bash
# The fluid's speed-against-error benchmark (docs/BENCHMARKS.md, "Fluid (MPS)"): builds riffle_fluid_accuracy,
# runs the accuracy sweep (hydrostatic tank and dam break at several resolutions, each enhanced scheme off in turn,
# three PPE tolerances; one thread, under nice: its errors do not depend on the load and its CPU times hardly do),
# then the sloshing-tank timing at 1 and 2 threads over the first SLOSH_TIME s (inside the ramp), over SLOSH_TIME s
# from t = 0.6 s (full amplitude) and from t = 1.2 s (violent: spray) (not niced: run it on a quiet machine; the
# load is printed),
# then plots docs/fluid_speed_vs_error.png.
#   tools/bench_fluid.sh [build-dir] [out-dir]
# Environment: FINE=0 leaves out l0 = 2.5 mm and a/25, a/30; HYDRO_TIME (default 3) simulated seconds of still
# water; SLOSH_TIME (default 0.3) simulated seconds of the sloshing tank; SKIP_ACCURACY=1 / SKIP_SLOSHING=1;
# MARTIN_MOYCE=path of martin_moyce_1952_surge_front_n2_2.csv (default ../shared/refdata/ beside the checkout).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-out/bench_fluid}
mkdir -p "$out"
reference=${MARTIN_MOYCE:-}
if [ -z "$reference" ]; then
  for root in .. "$(dirname "$(git rev-parse --path-format=absolute --git-common-dir 2>/dev/null || echo .)")/.."; do
    if [ -f "$root/shared/refdata/martin_moyce_1952_surge_front_n2_2.csv" ]; then
      reference="$root/shared/refdata/martin_moyce_1952_surge_front_n2_2.csv"
      break
    fi
  done
fi
[ -n "$reference" ] || { echo "bench_fluid: set MARTIN_MOYCE to the Martin & Moyce surge-front table" >&2; exit 1; }

cmake --build "$build" --target riffle_fluid_accuracy -j 2
echo "# machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); commit $(git rev-parse --short HEAD)"
fine=()
[ "${FINE:-1}" = 1 ] && fine=(--fine)
if [ "${SKIP_ACCURACY:-0}" != 1 ]; then
  echo "## accuracy sweep (1 thread, nice): $(uptime)"
  nice -n 10 "$build/riffle_fluid_accuracy" accuracy "$out/fluid_accuracy.csv" --threads 1 "${fine[@]}" \
    --hydro-time "${HYDRO_TIME:-3}" --reference "$reference"
fi
if [ "${SKIP_SLOSHING:-0}" != 1 ]; then
  echo "## sloshing-tank timing, load before: $(uptime)"
  echo "### the first ${SLOSH_TIME:-0.3} s (inside the one-period ramp)"
  "$build/riffle_fluid_accuracy" sloshing "$out/fluid_sloshing_timing.csv" --threads 1,2 --time "${SLOSH_TIME:-0.3}"
  echo "### ${SLOSH_TIME:-0.3} s from t = 0.6 s (full amplitude; the lead-in is not timed)"
  "$build/riffle_fluid_accuracy" sloshing "$out/fluid_sloshing_timing_full.csv" --threads 1,2 --from 0.6 \
    --time "${SLOSH_TIME:-0.3}"
  echo "### ${SLOSH_TIME:-0.3} s from t = 1.2 s (the violent stage: spray, neighbour rebuilds every step)"
  "$build/riffle_fluid_accuracy" sloshing "$out/fluid_sloshing_timing_violent.csv" --threads 1,2 --from 1.2 \
    --time "${SLOSH_TIME:-0.3}"
  echo "## load after: $(uptime)"
fi
if [ -f "$out/fluid_accuracy.csv" ]; then
  if /usr/bin/python3 -c 'import numpy, matplotlib' 2>/dev/null; then
    tools/riffle-tools plot-fluid-accuracy "$out/fluid_accuracy.csv" docs/fluid_speed_vs_error.png
  else
    echo "bench_fluid: no plot: /usr/bin/python3 lacks numpy or matplotlib (apt-get install python3-numpy python3-matplotlib)" >&2
  fi
fi
