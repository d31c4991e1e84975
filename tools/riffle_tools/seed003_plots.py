"""Seed 003's figures (Seil, Pirker & Lichtenegger 2018, Comp. Part. Mech. 5, 203-212) from the bed-load probes of a
set of riffle runs of scenes/sheared_bed_small.toml, sheared_bed_large.toml and sheared_bed_bidisperse.toml, one
run per bed and lid speed (docs/SCENES.md, "Seed 003's sheared beds"):

  fig4_moving_fraction.png  the fraction of moving grains against time per lid speed, one panel per bed (seed Fig. 4);
  fig6_mixture_classes.png  the mixture's moving fraction per class against time per lid speed (seed Fig. 6);
  fig5_shields.png          the cases on the Shields diagram, Theta against Re_f = u* d / nu, with the Shields curve
                            (Brownlie 1981 and Soulsby & Whitehouse 1997; seed Fig. 5 plots the Shields curve with
                            Dey's angle-of-repose curves, which are not drawn): filled where the grains keep moving;
                            the mixture per class and at its mean diameter D_m (Wilcock 1993; seed Eq. 31, Table 2);
  fig7_packing.png          the mixture: planar packing density lambda of the top layer and the large grains' moving
                            fraction against time, the onset of their motion marked (seed Fig. 7);
  bedload_vs_shields.png    the monodisperse beds' dimensionless bed-load flux q* = q_s / sqrt((s-1) g d^3) against
                            Theta, beside Meyer-Peter & Mueller (1948) and Wong & Parker (2006);
and seed003_summary.csv with one row per run and class (the numbers behind Figs. 5 and the flux plot).

Usage: tools/riffle-tools seed003-plots [--small U=DIR[@T] ...] [--large U=DIR[@T] ...]
           [--bidisperse U=DIR[@T] ...] [--out DIR] [--from T] [--stress b|lid] [--moving 0.01] [--onset 0.01]
           [--mixture-counts 2492 852] [--fluid-density 1000] [--viscosity 1e-6] [--gravity 9.81]

U is the lid speed [m/s] of the run in DIR (its output directory, holding probe_moving_fraction.csv,
probe_bedload_flux.csv, probe_bed_shear_stress.csv and, for the mixture, probe_packing_density.csv). Time means are
taken over t >= --from (default: the second half of each run), or t >= T for a run given as DIR@T. --stress picks
the bed shear stress: the momentum balance tau_b (default) or the lid's. A run "keeps moving" when its mean moving
fraction over the window exceeds --moving; the onset of the large grains' motion is the first row where their moving
fraction exceeds --onset.
Prints one line per figure and a table of the summary. Needs numpy and matplotlib.
"""
import argparse
import csv
import math
import os
import sys

import numpy as np

from . import plotting
from .bedload_plots import save
from .run_outputs import class_columns, read_columns

plt = plotting.pyplot("seed003_plots")

BEDS = ("small", "large", "bidisperse")


# The formulas of systems/physics/bedload.hpp (unit-tested there: tests/unit/systems/physics/measures/bedload_laws_test.cpp; the same values
# are checked here by tests/tools/test_seed003_plots.py).
def shields_brownlie(particle_reynolds):
    """Theta_c = 0.22 Re_p^-0.6 + 0.06 10^(-7.7 Re_p^-0.6) (Brownlie 1981)."""
    y = np.power(particle_reynolds, -0.6)
    return 0.22 * y + 0.06 * np.power(10.0, -7.7 * y)


def shields_soulsby_whitehouse(grain_size):
    """Theta_c = 0.30 / (1 + 1.2 D*) + 0.055 (1 - exp(-0.020 D*)) (Soulsby & Whitehouse 1997)."""
    return 0.30 / (1.0 + 1.2 * grain_size) + 0.055 * (1.0 - np.exp(-0.020 * grain_size))


def meyer_peter_mueller(shields):
    """q* = 8 (Theta - 0.047)^1.5, 0 below (Meyer-Peter & Mueller 1948)."""
    return 8.0 * np.power(np.maximum(np.asarray(shields, dtype=float) - 0.047, 0.0), 1.5)


def wong_parker(shields):
    """q* = 3.97 (Theta - 0.0495)^1.5, 0 below (Wong & Parker 2006)."""
    return 3.97 * np.power(np.maximum(np.asarray(shields, dtype=float) - 0.0495, 0.0), 1.5)


def shields_curve_in_friction_reynolds(particle_reynolds, law):
    """(Re_f, Theta_c) along the curve: u* = sqrt(Theta (s-1) g d) gives Re_f = sqrt(Theta_c) Re_p, free of s."""
    theta = shields_brownlie(particle_reynolds) if law == "brownlie" else shields_soulsby_whitehouse(
        np.power(particle_reynolds, 2.0 / 3.0))
    return np.sqrt(theta) * particle_reynolds, theta


def parse_runs(items, bed):
    """[(U, DIR, T)] sorted by U from U=DIR or U=DIR@T items: T the run's own start of the time means (None: --from).
    Only a number after the last '@' is a start, so a directory whose name holds '@' is read whole."""
    runs = []
    for item in items or []:
        speed, sep, directory = item.partition("=")
        if not sep:
            raise SystemExit(f"--{bed} {item}: expected U=DIR or U=DIR@T")
        start = None
        head, at, tail = directory.rpartition("@")
        if at:
            try:
                start = float(tail)
                directory = head
            except ValueError:
                pass
        runs.append((float(speed), directory, start))
    return sorted(runs, key=lambda run: run[:2])


def probe(directory, kind):
    path = os.path.join(directory, f"probe_{kind}.csv")
    return read_columns(path) if os.path.exists(path) else None


def window(columns, start):
    """Rows at t >= start (default: the second half of the run); at least the last row."""
    time = columns["time_s"]
    if start is None:
        start = 0.5 * time[-1]
    rows = time >= start
    if not rows.any():
        rows = time == time[-1]
    return rows


def time_mean(columns, name, rows):
    """Mean of a column over `rows`, each row held over the time to the previous one (uniform rows: plain mean)."""
    values = columns[name][rows]
    finite = np.isfinite(values)
    return float(np.mean(values[finite])) if finite.any() else float("nan")


def summarise(bed, speed, directory, args, start=None):
    """One summary dict per size class of the run: diameter, Theta, Re_f, moving fraction, q*, MPM, Wong-Parker; the
    means from `start` (default --from)."""
    start = args.start if start is None else start
    shear = probe(directory, "bed_shear_stress")
    moving = probe(directory, "moving_fraction")
    flux = probe(directory, "bedload_flux")
    if shear is None:
        raise SystemExit(f"{directory}: no probe_bed_shear_stress.csv")
    rows = window(shear, start)
    stress = "tau_lid_Pa" if args.stress == "lid" else "tau_b_Pa"
    if stress not in shear:
        raise SystemExit(f"{directory}: probe_bed_shear_stress.csv has no {stress} (no moving lid?)")
    tau = time_mean(shear, stress, rows)
    friction_velocity = math.sqrt(max(tau, 0.0) / args.fluid_density)
    summary = []
    for size_class, name in class_columns(shear, "diameter_m"):
        diameter = float(shear[name][-1])
        shields = time_mean(shear, f"class_{size_class}_shields_{'lid' if args.stress == 'lid' else 'b'}", rows)
        # (rho_p - rho_f) g d = tau / Theta, hence s; a run at rest (tau = 0) leaves s unknown.
        relative_density = (1.0 + tau / (shields * args.fluid_density * args.gravity * diameter)
                            if shields > 0 else float("nan"))
        entry = dict(bed=bed, lid_speed_m_s=speed, run=directory, from_s=float(shear["time_s"][rows][0]),
                     size_class=size_class, diameter_m=diameter,
                     tau_Pa=tau, shields=shields, friction_reynolds=friction_velocity * diameter / args.viscosity,
                     relative_density=relative_density)
        if moving is not None:
            moving_rows = window(moving, start)
            entry["moving_fraction"] = time_mean(moving, f"class_{size_class}_moving_fraction", moving_rows)
            entry["all_moving_fraction"] = time_mean(moving, "all_moving_fraction", moving_rows)
        if flux is not None:
            flux_rows = window(flux, start)
            q = time_mean(flux, f"class_{size_class}_q_m2_s", flux_rows)
            scale = math.sqrt((relative_density - 1.0) * args.gravity * diameter ** 3) if relative_density > 1 else 0
            entry["q_m2_s"] = q
            entry["q_star"] = q / scale if scale > 0 else float("nan")
            entry["q_star_mpm"] = float(meyer_peter_mueller(shields))
            entry["q_star_wong_parker"] = float(wong_parker(shields))
        summary.append(entry)
    if bed == "bidisperse" and len(summary) == len(args.mixture_counts):
        # Wilcock (1993): a strongly bimodal bed moves as a whole at the threshold of its number-weighted mean
        # diameter D_m (seed Eq. 31; 1.3 mm for the seed's 623 + 213 grains), the point the seed's Table 2 places.
        counts = np.array(args.mixture_counts, dtype=float)
        diameters = np.array([entry["diameter_m"] for entry in summary])
        mean_diameter = float(np.sum(counts * diameters) / np.sum(counts))
        relative_density = summary[0]["relative_density"]
        shields = (tau / ((relative_density - 1.0) * args.fluid_density * args.gravity * mean_diameter)
                   if relative_density > 1 else float("nan"))
        summary.append(dict(bed=bed, lid_speed_m_s=speed, run=directory, size_class="D_m", diameter_m=mean_diameter,
                            tau_Pa=tau, shields=shields,
                            friction_reynolds=friction_velocity * mean_diameter / args.viscosity,
                            relative_density=relative_density,
                            moving_fraction=summary[0].get("all_moving_fraction", float("nan")),
                            all_moving_fraction=summary[0].get("all_moving_fraction", float("nan"))))
    return summary


def onset_time(columns, name, threshold):
    """The first time the column exceeds `threshold` (NaN if never)."""
    above = np.where(columns[name] > threshold)[0]
    return float(columns["time_s"][above[0]]) if len(above) else float("nan")


def largest_class(directory):
    """The class number of the largest grains (from the shear probe's diameters; else the highest class number)."""
    shear = probe(directory, "bed_shear_stress")
    if shear is not None:
        diameters = [(float(shear[name][-1]), k) for k, name in class_columns(shear, "diameter_m")]
        if diameters:
            return max(diameters)[1]
    moving = probe(directory, "moving_fraction")
    return max(k for k, _ in class_columns(moving, "moving_fraction"))


def figure_moving(runs, path):
    beds = [bed for bed in BEDS if runs[bed]]
    figure, axes = plt.subplots(1, len(beds), figsize=(5.0 * len(beds), 4.0), squeeze=False)
    for axis, bed in zip(axes[0], beds):
        for speed, directory in runs[bed]:
            columns = probe(directory, "moving_fraction")
            if columns is not None:
                axis.plot(columns["time_s"], columns["all_moving_fraction"], label=f"$u_{{top}}$ = {speed:g} m/s")
        axis.set_xlabel("t [s]")
        axis.set_ylabel(r"$f_m$ [1]")
        axis.set_title(f"{bed} bed")
        axis.legend(fontsize=8)
    save(figure, path)


def figure_mixture_classes(runs, args, path):
    figure, axes = plt.subplots(1, len(runs), figsize=(4.5 * len(runs), 4.0), squeeze=False, sharey=True)
    for axis, (speed, directory) in zip(axes[0], runs):
        columns = probe(directory, "moving_fraction")
        large = largest_class(directory)
        for size_class, name in class_columns(columns, "moving_fraction"):
            axis.plot(columns["time_s"], columns[name], label="large" if size_class == large else "small")
        axis.plot(columns["time_s"], columns["all_moving_fraction"], "k--", label="all")
        axis.set_title(f"mixture, $u_{{top}}$ = {speed:g} m/s")
        axis.set_xlabel("t [s]")
        axis.legend(fontsize=8)
    axes[0][0].set_ylabel(r"$f_m$ [1]")
    save(figure, path)


def figure_shields(summary, args, path):
    figure, axis = plt.subplots(figsize=(6.4, 4.8))
    particle_reynolds = np.logspace(-1, 5, 400)
    for law, style, label in (("brownlie", "k-", "Shields curve (Brownlie 1981)"),
                              ("soulsby", "k--", "Soulsby & Whitehouse (1997)")):
        friction_reynolds, theta = shields_curve_in_friction_reynolds(particle_reynolds, law)
        axis.plot(friction_reynolds, theta, style, label=label)
    markers = dict(small="o", large="s", bidisperse="^")
    for entry in summary:
        if not (entry["shields"] > 0 and entry["friction_reynolds"] > 0):
            continue
        moving = entry.get("moving_fraction", float("nan")) > args.moving
        marker = "*" if entry["size_class"] == "D_m" else markers[entry["bed"]]
        axis.plot(entry["friction_reynolds"], entry["shields"], marker, color=f"C{BEDS.index(entry['bed'])}",
                  markerfacecolor=None if moving else "none")
        axis.annotate(f"{entry['lid_speed_m_s']:g}", (entry["friction_reynolds"], entry["shields"]), fontsize=7,
                      xytext=(3, 3), textcoords="offset points")
    for bed in BEDS:
        axis.plot([], [], markers[bed], color=f"C{BEDS.index(bed)}", label=f"{bed} (filled: moving)")
    axis.plot([], [], "*", color=f"C{BEDS.index('bidisperse')}", label="mixture at $D_m$ (Wilcock 1993)")
    axis.set_xscale("log")
    axis.set_yscale("log")
    axis.set_xlim(1, 1e3)
    axis.set_ylim(0.01, 1)
    axis.set_xlabel(r"$Re_f = u_* d / \nu$")
    axis.set_ylabel(r"$\Theta$")
    axis.set_title("cases on the Shields diagram (labels: lid speed, m/s)")
    axis.legend(fontsize=7)
    save(figure, path)


def figure_packing(runs, args, path):
    figure, (top, bottom) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True)
    onsets = []
    for k, (speed, directory) in enumerate(runs):
        colour = f"C{k}"
        packing = probe(directory, "packing_density")
        if packing is not None:
            top.plot(packing["time_s"], packing["lambda"], color=colour, label=f"$u_{{top}}$ = {speed:g} m/s")
        moving = probe(directory, "moving_fraction")
        name = f"class_{largest_class(directory)}_moving_fraction"
        bottom.plot(moving["time_s"], moving[name], color=colour)
        onset = onset_time(moving, name, args.onset)
        onsets.append((speed, onset))
        if math.isfinite(onset):
            for axis in (top, bottom):
                axis.axvline(onset, color=colour, linestyle=":")
    top.set_ylabel(r"planar packing density $\lambda$")
    top.legend(fontsize=8)
    bottom.set_ylabel(r"$f_{m,large}$")
    bottom.set_xlabel("t [s]")
    top.set_title(f"mixture: top layer and the large grains (dotted: onset, $f_{{m,large}}$ > {args.onset:g})")
    save(figure, path)
    return onsets


def figure_flux(summary, path):
    figure, axis = plt.subplots(figsize=(6.4, 4.8))
    theta = np.linspace(0.0, max([0.3] + [e["shields"] for e in summary if np.isfinite(e.get("shields", np.nan))]),
                        200)
    axis.plot(theta, meyer_peter_mueller(theta), "k-", label="Meyer-Peter & Mueller (1948)")
    axis.plot(theta, wong_parker(theta), "k--", label="Wong & Parker (2006)")
    for entry in summary:
        if entry["bed"] == "bidisperse" or not np.isfinite(entry.get("q_star", np.nan)):
            continue
        axis.plot(entry["shields"], entry["q_star"], "os"[entry["bed"] == "large"],
                  color=f"C{BEDS.index(entry['bed'])}")
    for bed in ("small", "large"):
        axis.plot([], [], "os"[bed == "large"], color=f"C{BEDS.index(bed)}", label=f"riffle, {bed} bed")
    axis.set_xlabel(r"$\Theta$")
    axis.set_ylabel(r"$q^* = q_s / \sqrt{(s-1) g d^3}$")
    axis.set_title("bed-load flux of the monodisperse beds")
    axis.legend(fontsize=8)
    save(figure, path)


SUMMARY_COLUMNS = ("bed", "lid_speed_m_s", "size_class", "diameter_m", "tau_Pa", "shields", "friction_reynolds",
                   "relative_density", "moving_fraction", "all_moving_fraction", "q_m2_s", "q_star", "q_star_mpm",
                   "q_star_wong_parker", "from_s", "run")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for bed in BEDS:
        parser.add_argument(f"--{bed}", action="append", metavar="U=DIR[@T]", help=f"a run of the {bed} bed")
    parser.add_argument("--out", default="seed003_figures")
    parser.add_argument("--from", dest="start", type=float, default=None, help="start of the time means [s]")
    parser.add_argument("--stress", choices=("b", "lid"), default="b")
    parser.add_argument("--moving", type=float, default=0.01, help="mean moving fraction of a moving case")
    parser.add_argument("--onset", type=float, default=0.01, help="large grains' moving fraction at the onset")
    parser.add_argument("--mixture-counts", type=float, nargs="+", default=[2492, 852],
                        help="grains per class of the mixture, class order (for D_m; scenes/sheared_bed_bidisperse)")
    parser.add_argument("--fluid-density", type=float, default=1000.0)
    parser.add_argument("--viscosity", type=float, default=1.0e-6)
    parser.add_argument("--gravity", type=float, default=9.81)
    args = parser.parse_args(argv)
    windowed = {bed: parse_runs(getattr(args, bed), bed) for bed in BEDS}
    runs = {bed: [(speed, directory) for speed, directory, _ in windowed[bed]] for bed in BEDS}
    if not any(runs.values()):
        parser.error("no runs given (--small, --large, --bidisperse)")
    os.makedirs(args.out, exist_ok=True)
    summary = [entry for bed in BEDS for speed, directory, start in windowed[bed]
               for entry in summarise(bed, speed, directory, args, start)]
    figure_moving(runs, os.path.join(args.out, "fig4_moving_fraction.png"))
    figure_shields(summary, args, os.path.join(args.out, "fig5_shields.png"))
    if runs["bidisperse"]:
        figure_mixture_classes(runs["bidisperse"], args, os.path.join(args.out, "fig6_mixture_classes.png"))
        for speed, onset in figure_packing(runs["bidisperse"], args, os.path.join(args.out, "fig7_packing.png")):
            print(f"mixture, u_top = {speed:g} m/s: onset of the large grains' motion at t = {onset:.4g} s")
    if runs["small"] or runs["large"]:
        figure_flux(summary, os.path.join(args.out, "bedload_vs_shields.png"))
    path = os.path.join(args.out, "seed003_summary.csv")
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=SUMMARY_COLUMNS, extrasaction="ignore")
        writer.writeheader()
        for entry in summary:
            writer.writerow({key: entry.get(key, "") for key in SUMMARY_COLUMNS})
    print(f"wrote {path}")
    for entry in summary:
        print(f"{entry['bed']:>10} U = {entry['lid_speed_m_s']:4g} m/s class {entry['size_class']} "
              f"d = {entry['diameter_m'] * 1e3:g} mm: Theta = {entry['shields']:.4g}, Re_f = "
              f"{entry['friction_reynolds']:.4g}, f_m = {entry.get('moving_fraction', float('nan')):.3g}, q* = "
              f"{entry.get('q_star', float('nan')):.3g} (MPM {entry.get('q_star_mpm', float('nan')):.3g}, "
              f"Wong-Parker {entry.get('q_star_wong_parker', float('nan')):.3g})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
