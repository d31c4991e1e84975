#!/usr/bin/env bash
# The seed's sloshing tank driven by its motion as a table (scenes/sloshing_table.toml) against the analytic motion
# (scenes/sloshing_tank.toml) and against the analytic motion with A perturbed by 1e-6, at l0 = 10 mm for UNTIL
# seconds on one thread: the wave gauges' largest difference per half second (docs/RESULTS.md, "Tank motion").
#   bash tools/table_vs_analytic.sh build/riffle [work_dir] [until]
set -euo pipefail
riffle=$(realpath "$1")
work=${2:-/tmp/riffle_table_vs_analytic}
until=${3:-3.0}
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$work"
sed 's/^spacing = 0.005 .*/spacing = 0.01/' "$root/scenes/sloshing_tank.toml" > "$work/analytic.toml"
sed 's/^spacing = 0.005 .*/spacing = 0.01/' "$root/scenes/sloshing_table.toml" > "$work/table.toml"
sed 's/^amplitude = 0.01 .*/amplitude = 0.01000001/' "$work/analytic.toml" > "$work/perturbed.toml"
cp "$root/scenes/sloshing_table.csv" "$work/"
for run in analytic table perturbed; do
  rm -rf "$work/out_$run"
  "$riffle" run "$work/$run.toml" --until "$until" --out "$work/out_$run" --threads 1 > "$work/$run.log" 2>&1
done
/usr/bin/python3 - "$work" <<'PY'
import csv, math, sys
work = sys.argv[1]
def load(run):
    rows = list(csv.reader(open(f"{work}/out_{run}/probe_gauges.csv")))[1:]
    return [[float(x) for x in row] for row in rows]
analytic = load("analytic")
for other in ("table", "perturbed"):
    rows = load(other)
    print(f"analytic vs {other}:")
    t0 = 0.0
    while t0 < analytic[-1][0] - 1e-9:
        pairs = [(a, b) for a, b in zip(analytic, rows) if t0 <= a[0] < t0 + 0.5]
        diff = max(abs(a[k] - b[k]) for a, b in pairs for k in (2, 3, 4) if not (math.isnan(a[k]) or math.isnan(b[k])))
        eta = max(abs(a[k] - 0.06) for a, _ in pairs for k in (2, 3, 4) if not math.isnan(a[k]))
        print(f"  t in [{t0:.1f}, {t0 + 0.5:.1f}) s: largest gauge difference {diff:.3g} m, largest |eta| {eta:.3g} m")
        t0 += 0.5
PY
