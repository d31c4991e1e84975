"""A Shields-number sweep of the bed-load channel (scenes/bedload_channel.toml, docs/cases/bedload.md): for each grain
diameter, settle the bed once (the settle scene scaled to d: the box 20 d x 10 d, the layers d thick), then run the
channel at each Shields number, and collect the means over each run's second half of its bedload_transport probe:
Theta, q* (the dimensionless flux), the moving fraction, u_p/u* and h_p/d. Then the threshold by zero-flux
extrapolation (a line through q*^(2/3) against Theta, the form of Meyer-Peter & Mueller's law, over the points that
move; Theta_c where it crosses zero, with its standard error), and a figure of q* against Theta beside Meyer-Peter &
Mueller (1948), Wong & Parker (2006) and the Shields curve of Soulsby & Whitehouse (1997), and of u_p/u* against
u*_c/u* beside Lajeunesse, Malverti & Charru (2010), u_p = 4.4 (u* - u*_c).

Usage: tools/riffle-tools bedload-sweep [--riffle build/riffle] [--diameters 0.002 0.001] [--shields 0.03 ...]
           [--out out/bedload_sweep] [--until T] [--threads 1] [--jobs N] [--cells N] [--set KEY=VALUE ...]
           [--collect-only]

The runs of one diameter go side by side, --jobs at a time (default: the cores over --threads): a 1,150-grain bed
gains only 1.2 x from a second thread, so one-thread runs two at a time finish a sweep sooner (docs/BENCHMARKS.md).

Writes OUT/sweep.csv (one row per run), OUT/threshold.csv (per diameter) and OUT/bedload_sweep.png; prints the table.
Each run's directory is OUT/d<d>/theta_<Theta>; a run whose probe file covers its end time is not run again.
Needs numpy and matplotlib (tools/setup.sh installs them).
"""
import argparse
import concurrent.futures
import csv
import math
import os
import subprocess
import sys

import numpy as np

from . import plotting
from .run_outputs import probe_path, read_columns

GRAVITY = 9.81
DENSITY = 1000.0
NU = 1.0e-6
DEFAULT_SHIELDS = [0.03, 0.04, 0.05, 0.06, 0.08, 0.1, 0.15, 0.2, 0.3, 0.45, 0.6]


def mpm(theta):
    """Meyer-Peter & Mueller (1948): q* = 8 (Theta - 0.047)^1.5."""
    return 8.0 * np.clip(np.asarray(theta) - 0.047, 0.0, None) ** 1.5


def wong_parker(theta):
    """Wong & Parker (2006): q* = 3.97 (Theta - 0.0495)^1.5."""
    return 3.97 * np.clip(np.asarray(theta) - 0.0495, 0.0, None) ** 1.5


def soulsby_whitehouse(diameter, relative_density=2.65):
    """Theta_c of Soulsby & Whitehouse (1997) at D* = d ((s - 1) g / nu^2)^(1/3)."""
    grain_size = diameter * ((relative_density - 1.0) * GRAVITY / NU ** 2) ** (1.0 / 3.0)
    return 0.30 / (1.0 + 1.2 * grain_size) + 0.055 * (1.0 - math.exp(-0.020 * grain_size))


def scaled_sets(diameter, cells):
    """--set overrides that scale both scenes from their 2 mm grains to `diameter` (the same bed in diameters)."""
    scale = diameter / 0.002
    size = f"[{0.04 * scale:.6g}, {0.02 * scale:.6g}, {0.05 * scale:.6g}]"
    settle = [f"tank.size={size}", f"solids.layered_beds[0].layer_thickness={0.002 * scale:.6g}",
              f"solids.layered_beds[0].classes[0].diameter={diameter:.6g}"]
    channel = [f"tank.size={size}", f"solids.fixed_below={0.002 * scale:.6g}", f"mean_flow.depth={0.04 * scale:.6g}",
               f"mean_flow.shields_diameter={diameter:.6g}"]
    if cells:
        channel.append(f"mean_flow.cells={cells}")
    return settle, channel


def run(command):
    print("+ " + " ".join(command), flush=True)
    subprocess.run(command, check=True)


def run_side_by_side(commands, jobs):
    """Runs every command, up to `jobs` at a time; each one's output is printed whole when it ends, after its command
    line. The first that fails raises CalledProcessError (after the others have ended)."""
    def one(command):
        return command, subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)

    failed = None
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        for command, result in pool.map(one, commands):
            print("+ " + " ".join(command), flush=True)
            print(result.stdout, end="", flush=True)
            if result.returncode != 0 and failed is None:
                failed = subprocess.CalledProcessError(result.returncode, command)
    if failed is not None:
        raise failed


def probe_means(run_dir):
    """The means of a run's bedload_transport rows over its second half, or None without the probe file."""
    path = probe_path(run_dir, "bedload_transport")
    if not os.path.exists(path):
        return None
    columns = read_columns(path)
    time = columns["time_s"]
    if time.size < 4:
        return None
    keep = time >= 0.5 * time[-1]
    names = ("shields", "u_star_m_s", "q_star", "moving_fraction", "moving_ux_over_u_star", "moving_height_over_d",
             "moving_above_bed_ux_over_u_star")
    # (runs written before the probe had the above-bed column read NaN there)
    mean = {name: float(np.nanmean(columns[name][keep]))
            if name in columns and np.any(np.isfinite(columns[name][keep])) else math.nan for name in names}
    mean["end_s"] = float(time[-1])
    return mean


def threshold_by_extrapolation(theta, flux_star):
    """Theta_c from a least-squares line through (Theta, q*^(2/3)) over the points with q* > 0: where it crosses zero,
    and its standard error (the line's parameter covariance, by the delta method). NaN with fewer than 3 points."""
    theta = np.asarray(theta, float)
    flux_star = np.asarray(flux_star, float)
    moving = np.isfinite(flux_star) & (flux_star > 0.0)
    if moving.sum() < 3:
        return math.nan, math.nan
    x, y = theta[moving], flux_star[moving] ** (2.0 / 3.0)
    design = np.vstack([np.ones_like(x), x]).T
    coefficients, residuals, _, _ = np.linalg.lstsq(design, y, rcond=None)
    intercept, slope = coefficients
    dof = max(1, x.size - 2)
    sigma2 = float(residuals[0]) / dof if residuals.size else float(np.sum((design @ coefficients - y) ** 2)) / dof
    covariance = sigma2 * np.linalg.inv(design.T @ design)
    theta_c = -intercept / slope
    gradient = np.array([-1.0 / slope, intercept / slope ** 2])
    return float(theta_c), float(math.sqrt(max(0.0, gradient @ covariance @ gradient)))


def main(argv=None):
    parser = argparse.ArgumentParser(prog="riffle-tools bedload-sweep", description=__doc__.split("\n\n")[0])
    parser.add_argument("--riffle", default="build/riffle")
    parser.add_argument("--diameters", type=float, nargs="+", default=[0.002, 0.001])
    parser.add_argument("--shields", type=float, nargs="+", default=DEFAULT_SHIELDS)
    parser.add_argument("--out", default="out/bedload_sweep")
    parser.add_argument("--until", type=float, default=None, help="end time of each run (default: the scene's)")
    parser.add_argument("--threads", type=int, default=1, help="threads of each run (default 1)")
    parser.add_argument("--jobs", type=int, default=None,
                        help="runs side by side (default: the cores over --threads)")
    parser.add_argument("--cells", type=int, default=None, help="mean_flow.cells (default: the scene's)")
    parser.add_argument("--set", action="append", default=[], help="a further override of the channel scene")
    parser.add_argument("--collect-only", action="store_true")
    parser.add_argument("--fit-up-to", type=float, default=math.inf,
                        help="fit the zero-flux line only to the points with Theta at most this (default: all that "
                             "move); the extrapolation leans on its range where q*^(2/3) bends")
    args = parser.parse_args(argv)

    jobs = args.jobs if args.jobs else max(1, (os.cpu_count() or 1) // max(1, args.threads))
    rows = []
    for diameter in args.diameters:
        settle_sets, channel_sets = scaled_sets(diameter, args.cells)
        base = os.path.join(args.out, f"d{diameter:g}")
        settled = os.path.join(base, "settle")
        settled_ckpt = os.path.abspath(os.path.join(settled, "checkpoints", "final.ckpt"))
        if not args.collect_only and not os.path.exists(settled_ckpt):
            command = [args.riffle, "run", "scenes/bedload_channel_settle.toml", "--out", settled, "--threads",
                       str(args.threads)]
            for item in settle_sets:
                command += ["--set", item]
            run(command)
        pending = []
        for theta in args.shields:
            run_dir = os.path.join(base, f"theta_{theta:g}")
            means = probe_means(run_dir)
            wanted_end = args.until
            done = means is not None and (wanted_end is None or means["end_s"] >= wanted_end - 1e-9)
            if not args.collect_only and not done:
                command = [args.riffle, "run", "scenes/bedload_channel.toml", "--out", run_dir, "--threads",
                           str(args.threads), "--set", f"mean_flow.shields_number={theta:g}",
                           "--set", f"solids.initial_state=\"{settled_ckpt}\""]
                for item in channel_sets + args.set:
                    command += ["--set", item]
                if args.until is not None:
                    command += ["--until", f"{args.until:g}"]
                pending.append(command)
        run_side_by_side(pending, jobs)
        for theta in args.shields:
            means = probe_means(os.path.join(base, f"theta_{theta:g}"))
            if means is None:
                continue
            rows.append({"diameter_m": diameter, "shields_set": theta, **means})

    if not rows:
        print("no runs to collect", file=sys.stderr)
        return 1
    os.makedirs(args.out, exist_ok=True)
    names = list(rows[0].keys())
    with open(os.path.join(args.out, "sweep.csv"), "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=names)
        writer.writeheader()
        writer.writerows(rows)
    print(f"{'d [mm]':>7} {'Theta':>7} {'q*':>9} {'q*_MPM':>9} {'q*_WP':>9} {'moving':>7} {'u_p/u*':>7} {'h_p/d':>6}")
    for row in rows:
        print(f"{row['diameter_m'] * 1e3:7.2f} {row['shields']:7.3f} {row['q_star']:9.3g} {float(mpm(row['shields'])):9.3g} "
              f"{float(wong_parker(row['shields'])):9.3g} {row['moving_fraction']:7.3f} "
              f"{row['moving_ux_over_u_star']:7.2f} {row['moving_height_over_d']:6.2f}")
    thresholds = []
    for diameter in args.diameters:
        mine = [row for row in rows if row["diameter_m"] == diameter]
        fitted = [r for r in mine if r["shields_set"] <= args.fit_up_to]  # the Theta asked for, not the measured
        theta_c, error = threshold_by_extrapolation([r["shields"] for r in fitted], [r["q_star"] for r in fitted])
        reference = soulsby_whitehouse(diameter)
        thresholds.append({"diameter_m": diameter, "theta_c": theta_c, "theta_c_error": error,
                           "soulsby_whitehouse": reference, "ratio": theta_c / reference,
                           "fit_up_to": max(r["shields_set"] for r in fitted) if fitted else math.nan})
        print(f"d = {diameter * 1e3:g} mm: Theta_c = {theta_c:.4f} +- {error:.4f} by zero-flux extrapolation; "
              f"Soulsby & Whitehouse {reference:.4f} (ratio {theta_c / reference:.2f})")
    with open(os.path.join(args.out, "threshold.csv"), "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(thresholds[0].keys()))
        writer.writeheader()
        writer.writerows(thresholds)

    plt = plotting.pyplot("bedload_sweep")
    figure, (flux_axes, speed_axes) = plt.subplots(1, 2, figsize=(11.0, 4.4))
    theta_line = np.linspace(0.02, 0.7, 300)
    flux_axes.plot(theta_line, mpm(theta_line), "k-", label="Meyer-Peter & Mueller 1948")
    flux_axes.plot(theta_line, wong_parker(theta_line), "k--", label="Wong & Parker 2006")
    for diameter, marker in zip(args.diameters, "os^v"):
        mine = [row for row in rows if row["diameter_m"] == diameter]
        flux_axes.plot([r["shields"] for r in mine], [r["q_star"] for r in mine], marker, label=f"riffle, d = {diameter * 1e3:g} mm")
        flux_axes.axvline(soulsby_whitehouse(diameter), color="0.6", lw=0.8)
        u_c = np.array([math.sqrt(soulsby_whitehouse(diameter) / r["shields"]) if r["shields"] > 0 else math.nan
                        for r in mine])
        speed_axes.plot(u_c, [r["moving_ux_over_u_star"] for r in mine], marker, label=f"riffle, d = {diameter * 1e3:g} mm")
        above = [r.get("moving_above_bed_ux_over_u_star", math.nan) for r in mine]
        if any(math.isfinite(value) for value in above):
            speed_axes.plot(u_c, above, marker, mfc="none",
                            label=f"riffle, d = {diameter * 1e3:g} mm, above the bed surface")
    ratio = np.linspace(0.0, 1.0, 50)
    speed_axes.plot(ratio, 4.4 * (1.0 - ratio), "k-", label="Lajeunesse et al. 2010: 4.4 (1 - u*_c/u*)")
    flux_axes.set_xscale("log")
    flux_axes.set_yscale("log")
    flux_axes.set_ylim(1e-4, 10.0)
    flux_axes.set_xlabel("Shields number Theta")
    flux_axes.set_ylabel("q* = q / sqrt((s - 1) g d^3)")
    flux_axes.legend(fontsize=8)
    speed_axes.set_xlabel("u*_c / u* (u*_c of Soulsby & Whitehouse)")
    speed_axes.set_ylabel("moving grains' mean u_p / u* (filled: all; open: above the bed)")
    speed_axes.legend(fontsize=8)
    plotting.write(figure, os.path.join(args.out, "bedload_sweep.png"), "bedload_sweep")
    return 0


if __name__ == "__main__":
    sys.exit(main())
