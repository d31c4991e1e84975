"""Plots of the bed-load probes (docs/SCENES.md, "Bed-load measures") of one riffle run's output directory: the
fraction of moving grains per class against time (seed 003 Figs. 4 and 6), the planar packing density lambda of the
top layer against time (its Fig. 7), the bed-load flux per class against time, the bed shear stress and Shields
numbers against time, and the horizontally averaged velocity profiles of water and grains with the solid fraction
at chosen times. Each figure is written as PNG into OUT_DIR/figures/ (or --out DIR); a figure whose probe file is
missing is skipped with a note.

Usage: tools/riffle-tools bedload-plots OUT_DIR [--out DIR] [--times T ...]
           [--moving FILE] [--packing FILE] [--flux FILE] [--shear FILE] [--profile FILE]

The probe files default to the default names, probe_<kind>.csv: probe_moving_fraction.csv,
probe_packing_density.csv, probe_bedload_flux.csv, probe_bed_shear_stress.csv, probe_velocity_profile.csv.
--times picks the profile times (the nearest row of each); default: the first, middle and last.
Prints one line per figure written. Needs numpy and matplotlib (Debian's python3-numpy and python3-matplotlib,
installed by tools/setup.sh).
"""
import argparse
import os
import sys

import numpy as np

from . import plotting
from .run_outputs import class_columns, read_columns

plt = plotting.pyplot("bedload_plots")


def save(figure, path):
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
    print(f"wrote {path}")


def plot_per_class(columns, suffix, all_name, ylabel, title, path):
    figure, axes = plt.subplots(figsize=(6.4, 4.0))
    time = columns["time_s"]
    for size_class, name in class_columns(columns, suffix):
        axes.plot(time, columns[name], label=f"class {size_class}")
    if all_name and all_name in columns:
        axes.plot(time, columns[all_name], "k--", label="all")
    axes.set_xlabel("t [s]")
    axes.set_ylabel(ylabel)
    axes.set_title(title)
    axes.legend()
    save(figure, path)


def plot_packing(columns, path):
    figure, axes = plt.subplots(figsize=(6.4, 4.0))
    axes.plot(columns["time_s"], columns["lambda"], "k-")
    axes.set_xlabel("t [s]")
    axes.set_ylabel(r"planar packing density $\lambda$ [1]")
    axes.set_title("top layer of the bed")
    save(figure, path)


def plot_shear(columns, path):
    figure, (top, bottom) = plt.subplots(2, 1, figsize=(6.4, 6.0), sharex=True)
    time = columns["time_s"]
    top.plot(time, columns["tau_b_Pa"], "k-", label=r"$\tau_b$ (momentum balance)")
    if "tau_lid_Pa" in columns:
        top.plot(time, columns["tau_lid_Pa"], "r--", label=r"$\tau$ (lid)")
    top.set_ylabel(r"$\tau$ [Pa]")
    top.legend()
    for size_class, name in class_columns(columns, "shields_b"):
        bottom.plot(time, columns[name], label=f"class {size_class}")
    bottom.set_xlabel("t [s]")
    bottom.set_ylabel(r"Shields number $\Theta$ [1]")
    bottom.legend()
    save(figure, path)


def plot_profiles(columns, times, path):
    """Velocity profiles of water and grains and the solid fraction at the rows nearest `times`."""
    row_times = np.unique(columns["time_s"])
    if not times:
        times = [row_times[0], row_times[len(row_times) // 2], row_times[-1]]
    figure, (velocity, fraction) = plt.subplots(1, 2, figsize=(9.0, 4.5), sharey=True)
    for k, wanted in enumerate(times):
        at = row_times[np.argmin(np.abs(row_times - wanted))]
        rows = columns["time_s"] == at
        height = 0.5 * (columns["z_low_m"][rows] + columns["z_high_m"][rows])
        colour = f"C{k}"
        velocity.plot(columns["fluid_ux_m_s"][rows], height, "-", color=colour, label=f"water, t = {at:g} s")
        velocity.plot(columns["grain_ux_m_s"][rows], height, "o", color=colour, markersize=3,
                      label=f"grains, t = {at:g} s")
        fraction.plot(columns["solid_fraction"][rows], height, "-", color=colour, label=f"t = {at:g} s")
    velocity.set_xlabel(r"$\langle u_x \rangle$ relative to the tank [m/s]")
    velocity.set_ylabel("height above the floor [m]")
    velocity.legend(fontsize=7)
    fraction.set_xlabel("solid fraction [1]")
    fraction.legend(fontsize=7)
    save(figure, path)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out_dir")
    parser.add_argument("--out", help="directory for the figures (default OUT_DIR/figures)")
    parser.add_argument("--times", type=float, nargs="*", default=[], help="profile times [s]")
    parser.add_argument("--moving", default="probe_moving_fraction.csv")
    parser.add_argument("--packing", default="probe_packing_density.csv")
    parser.add_argument("--flux", default="probe_bedload_flux.csv")
    parser.add_argument("--shear", default="probe_bed_shear_stress.csv")
    parser.add_argument("--profile", default="probe_velocity_profile.csv")
    args = parser.parse_args(argv)
    out = args.out or os.path.join(args.out_dir, "figures")
    os.makedirs(out, exist_ok=True)
    written = 0

    def probe(name):
        path = os.path.join(args.out_dir, name)
        if not os.path.exists(path):
            print(f"skipped: no {path}")
            return None
        return read_columns(path)

    if (columns := probe(args.moving)) is not None:
        plot_per_class(columns, "moving_fraction", "all_moving_fraction", "fraction of grains moving [1]",
                       "moving grains (|v - v_tank| > threshold)", os.path.join(out, "moving_fraction.png"))
        written += 1
    if (columns := probe(args.packing)) is not None:
        plot_packing(columns, os.path.join(out, "packing_density.png"))
        written += 1
    if (columns := probe(args.flux)) is not None:
        plot_per_class(columns, "q_m2_s", "all_q_m2_s", r"bed-load flux $q_s$ [m$^2$/s]", "bed-load flux per width",
                       os.path.join(out, "bedload_flux.png"))
        written += 1
    if (columns := probe(args.shear)) is not None:
        plot_shear(columns, os.path.join(out, "bed_shear_stress.png"))
        written += 1
    if (columns := probe(args.profile)) is not None:
        plot_profiles(columns, args.times, os.path.join(out, "velocity_profiles.png"))
        written += 1
    if written == 0:
        print("no bed-load probe files found", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
