#!/usr/bin/env bash
# The dry DEM against LAMMPS on the same machine, interleaved: the settled seed bed (7,490 x 5 mm, 537 x 10 mm and
# 135 x 15 mm spheres, 8,162 in all) shaken dry with Hertz-Mindlin at a sub-step of 1e-5 s, riffle's
# scenes/dry_shaken_tank.toml against the LAMMPS GRANULAR deck of ../shared/peers/lammps (the same physics; see its
# README), at 1 thread / 1 rank and 2 threads / 2 ranks (riffle both ways at 2: one rank of 2 threads, and 2 MPI ranks of
# one thread, "riffle-ranks"), in the order riffle, riffle-ranks, LAMMPS, riffle, ... so that all see the same machine
# state. Reports particle-steps per second per run, the medians, and riffle / LAMMPS.
#
#   tools/bench_dem_peer.sh [build-dir] [reps] [substeps]     defaults: build, 3, 5000
#
# Needs Debian's `lammps` and `openmpi-bin` (apt-get install lammps openmpi-bin). Each side settles its own bed once
# and keeps it: riffle's in out/dry_bed_settle (scenes/dry_bed_settle.toml, a few minutes), LAMMPS's in $PEER_WORK
# (default out/peer_lammps: make_bed.py and tank_settle.in, 1 s of settling, several minutes). The beds are different
# random packings with the same counts and sizes: compare rates, not trajectories. The timed figure is riffle's
# "stepping (wall)" and LAMMPS's "Loop time", both without reading the input. Runs beside other jobs are slower and
# noisier: each line prints the 1-minute load average.
set -euo pipefail
main() {
cd "$(dirname "$0")/.."
build=${1:-build}
reps=${2:-3}
substeps=${3:-5000}
peers=${PEERS:-../shared/peers/lammps}
peer_work=${PEER_WORK:-out/peer_lammps}
command -v lmp >/dev/null || { echo "bench_dem_peer: lmp not found (apt-get install lammps openmpi-bin)" >&2; exit 1; }
command -v mpirun >/dev/null || { echo "bench_dem_peer: mpirun not found (apt-get install openmpi-bin)" >&2; exit 1; }
[ -x "$build/riffle" ] || { echo "bench_dem_peer: $build/riffle not found (build it first)" >&2; exit 1; }
[ -f "$peers/tank_shake.in" ] || { echo "bench_dem_peer: no LAMMPS decks in $peers (set PEERS)" >&2; exit 1; }
# riffle's sub-step is 1e-5 s, 100 per engine step of 1e-3 s (dry_shaken_tank.toml): --until in engine steps.
(( substeps % 100 == 0 )) || { echo "bench_dem_peer: substeps must be a multiple of 100" >&2; exit 1; }
until=$(awk -v n="$substeps" 'BEGIN { printf "%.6f", n * 1e-5 }')
grains=8162

if [ ! -f out/dry_bed_settle/checkpoints/final.ckpt ]; then
  echo "bench_dem_peer: settling riffle's bed (scenes/dry_bed_settle.toml)" >&2
  "$build/riffle" run scenes/dry_bed_settle.toml --log-level warn >/dev/null
fi
mkdir -p "$peer_work"
cp "$peers"/*.in "$peers"/make_bed.py "$peer_work/"
if [ ! -f "$peer_work/bed_settled.restart" ]; then
  echo "bench_dem_peer: settling LAMMPS's bed (make_bed.py, tank_settle.in)" >&2
  (cd "$peer_work" && /usr/bin/python3 make_bed.py >/dev/null && lmp -in tank_settle.in -log settle.log >/dev/null)
fi
work=$(mktemp -d /tmp/riffle_peer.XXXXXX)
cp "$build/riffle" "$work/riffle"   # a rebuild during the runs changes nothing

run_riffle() {  # threads -> seconds of stepping
  local out=$work/riffle_$1_$2
  "$work/riffle" run scenes/dry_shaken_tank.toml --until "$until" --threads "$1" --out "$out" >"$out.log" 2>&1 ||
    { echo "bench_dem_peer: riffle failed, see $out.log" >&2; exit 1; }
  awk '$1 == "stepping" && $2 == "(wall)" { print $3 }' "$out.log"
}
run_riffle-ranks() {  # ranks (one thread each) -> seconds of stepping (the slowest rank's)
  local out=$work/riffle_ranks_$1_$2
  [ "$1" = 1 ] && { run_riffle 1 "$2-ranks"; return; }
  mpirun --allow-run-as-root --oversubscribe -np "$1" "$work/riffle" run scenes/dry_shaken_tank.toml --until "$until" \
    --threads 1 --out "$out" >"$out.log" 2>&1 || { echo "bench_dem_peer: riffle over ranks failed, see $out.log" >&2; exit 1; }
  # Every rank may print its own line: the slowest rank's is the run's.
  awk '$1 == "stepping" && $2 == "(wall)" && $3 > m { m = $3 } END { print m }' "$out.log"
}
run_lammps() {  # ranks -> seconds of the loop
  local log=$work/lammps_$1_$2.log
  (cd "$peer_work" && if [ "$1" = 1 ]; then
     lmp -in tank_shake.in -var nsteps "$substeps" -log "$log" >/dev/null 2>&1
   else
     mpirun --allow-run-as-root --oversubscribe -np "$1" lmp -in tank_shake.in -var nsteps "$substeps" -log "$log" \
       >/dev/null 2>&1
   fi) || { echo "bench_dem_peer: lmp failed, see $log" >&2; exit 1; }
  awk '$1 == "Loop" && $2 == "time" { print $4 }' "$log"
}

cpu="$(lscpu | sed -n 's/^Model name: *//p') (family $(lscpu | sed -n 's/^CPU family: *//p'), model $(lscpu | sed -n 's/^Model: *//p'))"
echo "# machine: $(nproc) cores, $cpu"
echo "# riffle $(git rev-parse --short HEAD 2>/dev/null || echo '?') ($build); LAMMPS $(lmp -h 2>/dev/null | sed -n 's/^Large-scale[^-]*- //p' | head -1)"
echo "# $grains grains x $substeps sub-steps of 1e-5 s; $reps repetitions, riffle and LAMMPS alternating"
: >"$work/results.txt"
for rep in $(seq "$reps"); do
  for n in 1 2; do
    codes="riffle lammps"
    [ "$n" = 2 ] && codes="riffle riffle-ranks lammps"
    for code in $codes; do
      seconds=$("run_$code" "$n" "$rep")
      [ -n "$seconds" ] || { echo "bench_dem_peer: no timing from $code" >&2; exit 1; }
      echo "$code $n $rep $seconds" >>"$work/results.txt"
      printf '  %-6s %s thread(s)/rank(s) rep %s: %8.3f s  %.3g particle-steps/s  load %s\n' "$code" "$n" "$rep" \
        "$seconds" "$(awk -v s="$seconds" -v g=$grains -v n="$substeps" 'BEGIN { print g * n / s }')" \
        "$(cut -d' ' -f1 /proc/loadavg)"
    done
  done
done
/usr/bin/python3 - "$work/results.txt" "$grains" "$substeps" <<'EOF'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
work = int(sys.argv[2]) * int(sys.argv[3])
print(f"{'threads/ranks':<14} {'riffle [p-steps/s]':>24} {'riffle ranks [p-steps/s]':>26} {'LAMMPS [p-steps/s]':>24} "
      f"{'riffle/LAMMPS':>14} {'ranks/LAMMPS':>13}")
for n in ("1", "2"):
    rates = {code: [work / float(r[3]) for r in rows if r[0] == code and r[1] == n]
             for code in ("riffle", "riffle-ranks", "lammps")}
    text = {code: f"{statistics.median(v):.3g} ({min(v):.3g}-{max(v):.3g})" if v else "-" for code, v in rates.items()}
    ratio = statistics.median(rates["riffle"]) / statistics.median(rates["lammps"])
    ranks = (f"{statistics.median(rates['riffle-ranks']) / statistics.median(rates['lammps']):13.2f}"
             if rates["riffle-ranks"] else f"{'-':>13}")
    print(f"{n:<14} {text['riffle']:>24} {text['riffle-ranks']:>26} {text['lammps']:>24} {ratio:>14.2f} {ranks}")
EOF
rm -rf "$work"
}
main "$@"
exit $?
