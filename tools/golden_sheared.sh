#!/usr/bin/env bash
# The bit-identity check for the periodic, sheared and coupled paths that tools/golden.sh does not run: seed 003's
# large bed settled (scenes/sheared_bed_large_settle.toml), then sheared under a 1.0 m/s lid to 0.1 s past its
# release (scenes/sheared_bed_large.toml --until 2.1), and the periodic-grains scene to its end, all at 2 threads.
# Prints "sha256  name" for their final checkpoints, diagnostics (wall-clock columns removed by header name) and
# every probe; run it with the binary before and after a change and `diff` the two listings.
#   tools/golden_sheared.sh <riffle-binary> <work-dir>          (about 3 minutes on 2 cores)
set -u
RIFFLE=$(realpath "$1") || exit 1
WORK=$2
SRC=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$WORK" && mkdir -p "$WORK/scenes" || exit 1
cp "$SRC/scenes/sheared_bed_large_settle.toml" "$SRC/scenes/sheared_bed_large.toml" "$SRC/scenes/periodic_grains.toml" \
  "$WORK/scenes/" || exit 1
cd "$WORK" || exit 1
run() {  # run <log> <riffle run arguments...>: fail loudly with the log's tail
  local log=$1
  shift
  "$RIFFLE" run "$@" --threads 2 >"$log" 2>&1 || { echo "golden_sheared: riffle run $* failed:" >&2; tail "$log" >&2; exit 1; }
}
run settle.log scenes/sheared_bed_large_settle.toml
run sheared.log scenes/sheared_bed_large.toml --set 'fluid.wall_boxes[0].velocity=1.0' \
  --set 'fluid.initial_velocity.velocity=1.0' --until 2.1 --out out/sheared
run periodic.log scenes/periodic_grains.toml --out out/periodic
for dir in out/sheared_bed_large_settle out/sheared out/periodic; do
  sha256sum "$dir/checkpoints/final.ckpt"
  /usr/bin/python3 - "$dir/diagnostics.csv" <<'PY'
import hashlib, sys
rows = [line.rstrip("\n").split(",") for line in open(sys.argv[1])]
keep = [i for i, name in enumerate(rows[0]) if not (name == "step_wall_s" or (name.startswith("wall_") and name.endswith("_s")))]
text = "\n".join(",".join(row[i] for i in keep) for row in rows)
print(hashlib.sha256(text.encode()).hexdigest(), sys.argv[1], "(without wall-clock columns)")
PY
  for probe in "$dir"/probe_*.csv; do [ -f "$probe" ] && sha256sum "$probe"; done
done
