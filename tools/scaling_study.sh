#!/usr/bin/env bash
# Strong and weak scaling over MPI ranks (docs/SCALING.md), for a machine with more cores than the reference's two
# (the device machine, when one is lent): one thread a rank, the runs one after another, each rank count once.
#
#   tools/scaling_study.sh strong SCENE UNTIL "1 2 4 8 16" [--set KEY=VALUE ...]
#       SCENE as it is on every rank count: stepping time, speed-up and parallel efficiency against the first rank
#       count (speed-up x first / N), the imbalance (the longest computing time over the ranks' mean) and the MPI
#       calls' share of the stepping (exchanges, reductions; waiting for the slowest rank included), from riffle.log.
#   tools/scaling_study.sh weak UNTIL "1 2 4 8 16" [--set KEY=VALUE ...]
#       the seed's tank of water alone (scenes/sloshing_tank.toml, 18,432 fluid particles at l0 = 5 mm) N times as
#       long on N ranks (tank and water box lengthened by --set): the same work a rank; the efficiency is the first
#       rank count's stepping time over this one's.
#
#   tools/scaling_study.sh strong scenes/sloshing_tank.toml 0.05 "1 2 4 8 16" --set fluid.spacing=0.0025
#   tools/scaling_study.sh strong scenes/flume_2p4m.toml 0.02 "1 2 4 8 16"    # after scenes/flume_2p4m_settle.toml
#   tools/scaling_study.sh weak 0.05 "1 2 4 8 16"
#
# Prints a Markdown table (and the CPU, the commit and the load before each run); RIFFLE names the binary
# (build/riffle), OUT the folder the runs are written to (a temporary one, removed at the end).
set -euo pipefail
cd "$(dirname "$0")/.."
usage() { sed -n '2,19p' "$0" >&2; exit 2; }
[ $# -ge 3 ] || usage
kind=$1
shift
case $kind in
  strong) [ $# -ge 3 ] || usage; scene=$1 until=$2 counts=$3; shift 3 ;;
  weak) scene=scenes/sloshing_tank.toml until=$1 counts=$2; shift 2 ;;
  *) usage ;;
esac
riffle=${RIFFLE:-build/riffle}
[ -x "$riffle" ] || { echo "scaling_study: no riffle binary at $riffle" >&2; exit 2; }
work=${OUT:-$(mktemp -d)}
[ -n "${OUT:-}" ] || trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

echo "# $kind scaling of $scene to t = $until s, one thread a rank"
echo "# $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores; commit $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
echo
echo "| ranks | particles | stepping [s] | speed-up | efficiency | imbalance | exchanges | reductions |"
echo "|---|---|---|---|---|---|---|---|"
first_count="" first_seconds=""
for n in $counts; do
  settings=(--set output.vtk_interval=0 --set output.checkpoint_interval=0)
  if [ "$kind" = weak ]; then
    length=$(awk -v n="$n" 'BEGIN { printf "%.6g", 0.24 * n }')
    settings+=(--set "tank.size=[$length, 0.16, 0.30]" --set "fluid.boxes[0].high=[$length, 0.16, 0.06]")
  fi
  out=$work/ranks$n
  rm -rf "$out"
  command=("$riffle" run "$scene" --out "$out" --until "$until" --threads 1 "${settings[@]}" "$@")
  [ "$n" = 1 ] || command=(mpirun -n "$n" "${command[@]}")
  echo "# $n rank(s), load $(cut -d' ' -f1 /proc/loadavg)" >&2
  # The grains and MPS particles (fluid, wall and dummy) of the scene as run, from riffle check.
  particles=$("$riffle" check "$scene" "${settings[@]}" "$@" 2>&1 |
    awk '/valid scene/ { for (i = 1; i < NF; ++i) if ($(i + 1) ~ /^grains,?$/) n += $i }
         /^ *fluid: [0-9]+ MPS particles/ { n += $2 } END { print n + 0 }')
  "${command[@]}" >"$out.log" 2>&1 || { echo "scaling_study: the run on $n rank(s) failed: $out.log" >&2; tail -5 "$out.log" >&2; exit 1; }
  # Rank 0's log: the stepping line and, over ranks, the imbalance and each rank's calls.
  /usr/bin/python3 - "$out/riffle.log" "$n" "$kind" "${first_count:-$n}" "${first_seconds:-0}" "$particles" <<'PY'
import re, sys
log, n, kind, first_n, first_s = open(sys.argv[1]).read(), int(sys.argv[2]), sys.argv[3], int(sys.argv[4]), float(sys.argv[5])
particles = int(sys.argv[6])
stepping = float(re.search(r"stepping \(wall\)\s+([0-9.]+)", log).group(1))
imbalance = re.search(r"the longest computing time over the mean: ([0-9.]+)", log)
ranks = re.findall(r"rank \d+: \d+ \S+(?: particles)?, stepping ([0-9.]+) s: computing ([0-9.]+) s, exchanging ([0-9.]+) s "
                   r"\(\d+ calls\), reducing ([0-9.]+) s", log)
exchanges = max((float(r[2]) / float(r[0]) for r in ranks), default=0.0)
reductions = max((float(r[3]) / float(r[0]) for r in ranks), default=0.0)
first_s = first_s or stepping
speedup = first_s / stepping
efficiency = speedup if kind == "weak" else speedup * first_n / n
print(f"| {n} | {particles:,} | {stepping:.2f} | {speedup:.2f} | {efficiency:.2f} | "
      f"{float(imbalance.group(1)) if imbalance else 1.0:.3f} | {100 * exchanges:.0f} % | {100 * reductions:.0f} % |")
PY
  if [ -z "$first_count" ]; then
    first_count=$n
    first_seconds=$(grep -o -m1 "stepping (wall) *[0-9.]*" "$out/riffle.log" | awk '{print $NF}')
  fi
done
