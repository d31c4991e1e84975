"""The slope at which a settled bed starts to flow: its maximum angle of stability, measured as a tilting-box
experiment does (docs/cases/bedload.md, "The angle at which the bed flows").

Runs riffle on a scene of a settled, periodic bed on a rough floor (scenes/bed_tilt.toml: seed 003's small bed, its
bottom layer fixed) once per angle, with gravity tilted by theta about y, g = |g| (sin theta, 0, -cos theta), and
reads the moving fraction (|v| > 0.01 m/s, fixed grains left out) over the run's last `--window` seconds: a bed that
holds has f_m near 0 there, one that flows near 1. Then halves the interval between the steepest angle that held and
the gentlest that flowed `--refine` times (stopping early where a halving lands on a partial slide). The onset angle is reported as that interval; its tangent is the bed's
friction against starting, the angle of repose that Dey's threshold model and seed 003's Sec. 5 read. With
`--start-from CKPT` (a flowing bed's checkpoint, e.g. a steeper run's final.ckpt) every run starts from that moving
bed instead, and the interval is the angle at which a flow stops (the dynamic angle of repose, below the onset's).

  tools/riffle-tools bed-tilt --angles 18 20 22 24 26 28 [--refine 2] [--work out/bed_tilt]
      [--variant "no_rolling:contact.rolling_friction=0.0"] [--scene scenes/bed_tilt.toml] [--threads 1]
      [--start-from out/bed_tilt/scene/30/checkpoints/final.ckpt] [--set KEY=VALUE]

A variant is NAME:KEY=VALUE[;KEY=VALUE...] (riffle's --set); the scene as written is always run as "scene"; --set
KEY=VALUE is added to every run (seed 003's large bed: --set 'solids.initial_state="/abs/path/final.ckpt"' --set
solids.fixed_below=0.0015).
Writes WORK/tilt.csv (every run), WORK/onset.csv (per variant) and WORK/tilt.png (f_m against time, a panel per
variant; the window read shaded). A run whose folder already holds a finished run
is read, not run again.
"""
import argparse
import csv
import math
import pathlib
import subprocess
import sys

import numpy as np

from riffle_tools import plotting
from riffle_tools.bed_creep import parse_variant

GRAVITY = 9.81  # [m/s^2]
FLOWS = 0.5     # f_m over the window above which the bed flows
HOLDS = 0.01    # ... and below which it holds (between: a partial slide, counted as neither)


def tilted_gravity(angle_degrees, magnitude=GRAVITY):
    """g tilted by the angle about y, down the slope along +x: magnitude (sin, 0, -cos)."""
    theta = math.radians(angle_degrees)
    return [magnitude * math.sin(theta), 0.0, -magnitude * math.cos(theta)]


def read_moving_fraction(run):
    """(times, f_m of all free grains) from a run's probe_moving_fraction.csv."""
    path = pathlib.Path(run) / "probe_moving_fraction.csv"
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    if not rows:
        raise SystemExit(f"{path}: no rows")
    return (np.array([float(row["time_s"]) for row in rows]),
            np.array([float(row["all_moving_fraction"]) for row in rows]))


def classify(times, moving, window):
    """The bed's state over the last `window` seconds: ('flows' | 'holds' | 'partial', mean f_m there)."""
    late = times >= times[-1] - window - 1e-9
    mean = float(moving[late].mean())
    if mean > FLOWS:
        return "flows", mean
    if mean < HOLDS:
        return "holds", mean
    return "partial", mean


def onset_interval(results):
    """(steepest angle that held, gentlest angle that flowed) from {angle: state}; None where there is none. The
    steepest hold is taken below the gentlest flow, so a bed that held once above a flow does not hide the flow."""
    flowed = [angle for angle, state in results.items() if state == "flows"]
    gentlest_flow = min(flowed) if flowed else None
    held = [angle for angle, state in results.items()
            if state == "holds" and (gentlest_flow is None or angle < gentlest_flow)]
    return (max(held) if held else None), gentlest_flow


def finished(run, end):
    try:
        times, _ = read_moving_fraction(run)
    except (OSError, SystemExit, KeyError, ValueError):
        return False
    return abs(times[-1] - end) < 1e-6 + 1e-3 * end


def main(argv=None):
    parser = argparse.ArgumentParser(prog="riffle-tools bed-tilt", description=__doc__.split("\n\n")[0])
    parser.add_argument("--riffle", default="build/riffle")
    parser.add_argument("--scene", default="scenes/bed_tilt.toml")
    parser.add_argument("--work", default="out/bed_tilt")
    parser.add_argument("--angles", type=float, nargs="+", default=[18, 20, 22, 24, 26, 28],
                        help="[deg] the slopes run first")
    parser.add_argument("--refine", type=int, default=0,
                        help="times to halve the interval between the steepest hold and the gentlest flow")
    parser.add_argument("--variant", type=parse_variant, action="append", default=[])
    parser.add_argument("--set", dest="common", action="append", default=[], metavar="KEY=VALUE",
                        help="riffle's --set for every run, the scene's own included (another bed, say)")
    parser.add_argument("--end", type=float, default=1.0, help="[s] the run's length (the scene's end_time)")
    parser.add_argument("--window", type=float, default=0.2, help="[s] the run's last seconds read")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--start-from", default=None,
                        help="a checkpoint of a flowing bed to start every run from (the stopping angle)")
    args = parser.parse_args(argv)
    if not 0.0 < args.window <= args.end:
        parser.error("--window must lie in (0, --end]")
    work = pathlib.Path(args.work)
    work.mkdir(parents=True, exist_ok=True)

    table, onsets, histories = [], [], {}
    for name, sets in [("scene", [])] + args.variant:
        results = {}

        def run_angle(angle):
            if angle in results:  # run already (a halving that lands on a listed angle)
                return
            run = work / name / f"{angle:g}"
            if not finished(run, args.end):
                gravity = ", ".join(f"{value:.6f}" for value in tilted_gravity(angle))
                command = [args.riffle, "run", args.scene, "--threads", str(args.threads), "--out", str(run),
                           "--until", str(args.end), "--log-level", "warn", "--set", f"run.gravity=[{gravity}]"]
                for item in args.common + sets:
                    command += ["--set", item]
                if args.start_from:  # last: riffle takes the last --set of a key, and this one overrides a bed's
                    start = pathlib.Path(args.start_from).resolve()
                    command += ["--set", f'solids.initial_state="{start}"']
                print("running:", " ".join(command), file=sys.stderr, flush=True)
                if subprocess.run(command).returncode != 0:
                    raise SystemExit(f"riffle failed for {run}")
            times, moving = read_moving_fraction(run)
            state, mean = classify(times, moving, args.window)
            results[angle] = state
            histories[(name, angle)] = (times, moving, state)
            table.append({"variant": name, "angle_deg": angle, "state": state, "late_moving_fraction": mean,
                          "peak_moving_fraction": float(moving.max())})

        for angle in args.angles:
            run_angle(angle)
        for _ in range(args.refine):
            low, high = onset_interval(results)
            if low is None or high is None:
                break
            middle = round(0.5 * (low + high), 4)
            if middle in results:  # a partial slide there: halving cannot narrow the interval further
                break
            run_angle(middle)
        low, high = onset_interval(results)
        partial = sorted(angle for angle, state in results.items() if state == "partial"
                         and (low is None or angle > low) and (high is None or angle < high))
        onsets.append({"variant": name, "holds_up_to_deg": low, "flows_from_deg": high,
                       "partial_deg": " ".join(f"{angle:g}" for angle in partial),
                       "friction_low": math.tan(math.radians(low)) if low is not None else None,
                       "friction_high": math.tan(math.radians(high)) if high is not None else None})

    table.sort(key=lambda row: (row["variant"], row["angle_deg"]))
    for path, rows in ((work / "tilt.csv", table), (work / "onset.csv", onsets)):
        with open(path, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    print("| variant | angle [deg] | state | f_m, last window | f_m, peak |")
    print("|---|---|---|---|---|")
    for row in table:
        print(f"| {row['variant']} | {row['angle_deg']:g} | {row['state']} | {row['late_moving_fraction']:.3f} | "
              f"{row['peak_moving_fraction']:.3f} |")
    print("\n| variant | holds up to [deg] | flows from [deg] | tan, the two | partial slides between [deg] |")
    print("|---|---|---|---|---|")
    for row in onsets:
        def show(value, form):
            return "-" if value is None else format(value, form)
        print(f"| {row['variant']} | {show(row['holds_up_to_deg'], 'g')} | {show(row['flows_from_deg'], 'g')} | "
              f"{show(row['friction_low'], '.3f')} - {show(row['friction_high'], '.3f')} | "
              f"{row['partial_deg'] or '-'} |")
    plot_histories(histories, args.window, work / "tilt.png")
    print(f"\n({work / 'tilt.csv'}, {work / 'onset.csv'}, {work / 'tilt.png'})")
    return 0


def plot_histories(histories, window, path):
    """f_m against time for every run, a panel per variant, coloured by angle, dashed where the bed held."""
    plt = plotting.pyplot("bed_tilt")
    variants = sorted({name for name, _ in histories})
    figure, axes = plt.subplots(1, len(variants), figsize=(5.0 * len(variants), 3.8), squeeze=False, sharey=True)
    angles = sorted({angle for _, angle in histories})
    colours = plt.get_cmap("viridis")
    for axis, name in zip(axes[0], variants):
        for angle in angles:
            if (name, angle) not in histories:
                continue
            times, moving, state = histories[(name, angle)]
            shade = colours((angle - angles[0]) / max(angles[-1] - angles[0], 1e-9))
            axis.plot(times, moving, color=shade, linestyle="-" if state == "flows" else "--" if state == "holds"
                      else ":", label=f"{angle:g}° {state}")
        axis.axvspan(max(times[-1] - window, 0.0), times[-1], color="0.9", zorder=0)
        axis.set_title(name)
        axis.set_xlabel("t [s]")
        axis.legend(fontsize=7, ncol=2)
    axes[0][0].set_ylabel("moving fraction f_m (|v| > 0.01 m/s)")
    figure.tight_layout()
    plotting.write(figure, path, "bed_tilt")
    plt.close(figure)


if __name__ == "__main__":
    sys.exit(main())
