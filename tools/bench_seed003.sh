#!/usr/bin/env bash
# Seed 003's sheared beds: wall time per simulated second and throughput at 1 and 2 threads, interleaved (1, 2, 1,
# 2, ...), resumed from a checkpoint of a released run, so that the water moves over grains free to move (the scenes
# hold the bed for the first 2 s). Results go to docs/BENCHMARKS.md by hand, with this command beside them.
#   tools/bench_seed003.sh CHECKPOINT UNTIL [REPS] [build-dir]
# CHECKPOINT: a checkpoint of a scenes/sheared_bed_*.toml run after t = 2 s (e.g. DIR/checkpoints/step_0000008006.ckpt
# of a 5 s run, t = 4.0 s; docs/RESULTS.md, the sheared beds); UNTIL: the end time [s]. Prints one line per run:
# threads, engine steps, stepping wall time, wall s per simulated s, grain sub-steps per s (grains x sub-steps x steps /
# wall) and fluid particle-steps per s (fluid particles x steps / wall), from the run's log and diagnostics.
set -euo pipefail
cd "$(dirname "$0")/.."
checkpoint=$1
until=$2
reps=${3:-2}
build=${4:-build}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
[ -f "$checkpoint" ] || { echo "bench_seed003: no checkpoint $checkpoint" >&2; exit 1; }
echo "# machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); $checkpoint to t = $until s"
echo "threads steps stepping_s wall_s_per_simulated_s grain_substeps_per_s fluid_particle_steps_per_s"
for rep in $(seq "$reps"); do
  for threads in 1 2; do
    out="$scratch/run_${rep}_$threads"
    "$build/riffle" resume "$checkpoint" --out "$out" --threads "$threads" --until "$until" > "$out.log" 2>&1 ||
      { echo "bench_seed003: riffle resume failed:" >&2; tail -n 5 "$out.log" >&2; exit 1; }
    /usr/bin/python3 - "$out" "$out.log" "$threads" "$checkpoint" <<'PY'
import csv, re, sys
out, log_path, threads = sys.argv[1:4]
log = open(log_path).read()
start = re.search(r"from .*?: t = ([\d.e+-]+) s to [\d.e+-]+ s, dt = [\d.e+-]+ s, (\d+) solid sub-steps, (\d+) grains", log)
t0, substeps, grains = float(start.group(1)), int(start.group(2)), int(start.group(3))
end = re.search(r"finished at t = ([\d.e+-]+) s after (\d+) steps; final checkpoint: .*step_(\d+)\.ckpt", log)
if end is None:
    sys.exit(f"bench_seed003: the run did not finish (is UNTIL after the checkpoint's time?): see {log_path}")
t1 = float(end.group(1))
# The checkpoint's step is in its name (the resumed run counts on from it); the run ends at end.group(2).
first = int(re.search(r"step_(\d+)\.ckpt", sys.argv[4]).group(1))
steps = int(end.group(2)) - first
wall = float(re.search(r"stepping \(wall\)\s+([\d.]+)", log).group(1))
rows = list(csv.DictReader(open(out + "/diagnostics.csv")))
fluid = int(rows[-1]["fluid_particles"])
print(f"{threads} {steps} {wall:.2f} {wall / (t1 - t0):.1f} {grains * substeps * steps / wall:.3g} {fluid * steps / wall:.3g}")
PY
  done
done
