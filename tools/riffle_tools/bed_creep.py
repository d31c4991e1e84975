"""A settled bed at rest, and how fast it creeps: the drift a contact law's time integration leaves in a bed whose
exact answer is rest (docs/cases/seed-experiment.md, "A bed at rest creeps under the constant-torque rolling friction").

Runs riffle on a scene of a settled bed with nothing driving it (tests/data/resting_bed_creep.toml: the seed bed
under gravity tilted below the rolling angle) once per sub-step count and variant, then reads the grains' frames at
two times and prints, per size class, the mean drift along x and z and the mean distance travelled, as rates in
micrometres per second. Grains are matched by id.

  tools/riffle-tools bed-creep --riffle build/riffle --work out/bed_creep [--substeps 40 80]
      [--variant "flat:run.gravity=[0.0, 0.0, -9.81]"] [--variant "no_rolling:contact.rolling_friction=0.0"]
      [--scene tests/data/resting_bed_creep.toml] [--start 1.0] [--end 3.0] [--threads 1]

A variant is NAME:KEY=VALUE[;KEY=VALUE...] (riffle's --set); the scene as written is always run as "scene".
Writes WORK/creep.csv. Runs whose folder already holds a finished run (its last frame at --end) are read, not run.
"""
import argparse
import csv
import os
import pathlib
import subprocess
import sys

import numpy as np

from riffle_tools.vtp import read_pvd, read_vtp


def parse_variant(text):
    name, _, sets = text.partition(":")
    if not name or not sets:
        raise argparse.ArgumentTypeError(f"a variant is NAME:KEY=VALUE[;KEY=VALUE...], got {text!r}")
    return name, [item.strip() for item in sets.split(";") if item.strip()]


def frame_at(run, time):
    frames = read_pvd(pathlib.Path(run) / "solids.pvd")
    if not frames:
        raise SystemExit(f"{run}: no frames in solids.pvd")
    found_time, path = min(frames, key=lambda frame: abs(frame[0] - time))
    if abs(found_time - time) > 1e-6 + 1e-3 * abs(time):
        raise SystemExit(f"{run}: no frame at t = {time} s (nearest {found_time} s)")
    data = read_vtp(path, ["id", "radius"])
    order = np.argsort(data["id"])
    return {name: values[order] for name, values in data.items()}


def finished(run, end):
    try:
        frames = read_pvd(pathlib.Path(run) / "solids.pvd")
    except Exception:  # no run yet, or an unreadable one: run it again
        return False
    return bool(frames) and abs(frames[-1][0] - end) < 1e-6 + 1e-3 * end


def drift_rows(run, start, end):
    """Per size class: grains, mean dx, mean dz and mean |d| between start and end, in um/s."""
    first, last = frame_at(run, start), frame_at(run, end)
    if not np.array_equal(first["id"], last["id"]):
        raise SystemExit(f"{run}: the grains at {start} s and {end} s differ")
    moved = last["points"] - first["points"]
    seconds = end - start
    rows = []
    radii = np.round(first["radius"], 6)
    for radius in np.unique(radii):
        mask = radii == radius
        rows.append({"diameter_mm": 2e3 * radius, "grains": int(mask.sum()),
                     "dx_um_s": 1e6 * moved[mask, 0].mean() / seconds,
                     "dz_um_s": 1e6 * moved[mask, 2].mean() / seconds,
                     "distance_um_s": 1e6 * np.linalg.norm(moved[mask], axis=1).mean() / seconds})
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(prog="riffle-tools bed-creep", description=__doc__.split("\n\n")[0])
    parser.add_argument("--riffle", default="build/riffle")
    parser.add_argument("--scene", default="tests/data/resting_bed_creep.toml")
    parser.add_argument("--work", default="out/bed_creep")
    parser.add_argument("--substeps", type=int, nargs="+", default=[40, 80])
    parser.add_argument("--variant", type=parse_variant, action="append", default=[])
    parser.add_argument("--start", type=float, default=1.0, help="[s] the first frame read (after the bed settled)")
    parser.add_argument("--end", type=float, default=3.0, help="[s] the last frame read (the scene's end)")
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args(argv)
    work = pathlib.Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    table = []
    for name, sets in [("scene", [])] + args.variant:
        for substeps in args.substeps:
            run = work / f"{name}_{substeps}"
            if not finished(run, args.end):
                command = [args.riffle, "run", args.scene, "--threads", str(args.threads), "--out", str(run),
                           "--until", str(args.end), "--log-level", "warn", "--set", f"run.solid_substeps={substeps}"]
                for item in sets:
                    command += ["--set", item]
                print("running:", " ".join(command), file=sys.stderr, flush=True)
                if subprocess.run(command).returncode != 0:
                    raise SystemExit(f"riffle failed for {run}")
            for row in drift_rows(run, args.start, args.end):
                table.append({"variant": name, "substeps": substeps, **row})
    with open(work / "creep.csv", "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(table[0]))
        writer.writeheader()
        writer.writerows(table)
    print(f"| variant | sub-steps | d [mm] | grains | drift x [um/s] | drift z [um/s] | mean distance [um/s] |")
    print("|---|---|---|---|---|---|---|")
    for row in table:
        print(f"| {row['variant']} | {row['substeps']} | {row['diameter_mm']:.0f} | {row['grains']} | "
              f"{row['dx_um_s']:.2f} | {row['dz_um_s']:.2f} | {row['distance_um_s']:.2f} |")
    print(f"\n(between t = {args.start} and {args.end} s; {work / 'creep.csv'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
