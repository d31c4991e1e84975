"""Plot a run's bed statistics (seed 000 Figs. 6 and 12): the concentration centroid height of each size class
against t/T (class_centroids.csv), and vertical profiles of the coordination number Z and the mean dimensionless
overlap delta* at a few times (bed_profile.csv). The scene must set output.bed_profile_interval.

Usage: tools/riffle-tools plot-bed OUT_DIR [--times T ...] [--output FILE.png]

--times picks the profile times, in t/T when the tank oscillates (else in seconds); the nearest written time is
used for each. By default: up to four times spread over the run, the last included.

Needs Debian's python3-matplotlib (installed by tools/setup.sh); run it with /usr/bin/python3.
"""
import argparse
import pathlib
import sys

from . import plotting, run_outputs
from .run_outputs import number

plt = plotting.pyplot("plot_bed")


def read_rows(path):
    if not path.exists():
        sys.exit(f"plot_bed: {path} does not exist (set output.bed_profile_interval in the scene)")
    rows = run_outputs.read_rows(path)
    if not rows:
        sys.exit(f"plot_bed: {path} has no rows yet")
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out_dir", type=pathlib.Path, help="a run's output directory")
    parser.add_argument("--times", type=float, nargs="+", help="profile times (t/T if the tank oscillates, else s)")
    parser.add_argument("--output", type=pathlib.Path, help="PNG to write (default OUT_DIR/bed.png)")
    args = parser.parse_args(argv)

    centroids = read_rows(args.out_dir / "class_centroids.csv")
    profile = read_rows(args.out_dir / "bed_profile.csv")
    periodic = centroids[0]["t_over_T"] != ""
    clock = "t_over_T" if periodic else "time_s"
    clock_label = "t/T" if periodic else "t [s]"

    figure, axes = plt.subplots(1, 3, figsize=(14, 4.8), constrained_layout=True)

    ax = axes[0]
    x = [number(row[clock]) for row in centroids]
    for key in centroids[0]:
        if key.startswith("class_") and key.endswith("_centroid_m"):
            size_class = key[len("class_"):-len("_centroid_m")]
            ax.plot(x, [1e3 * number(row[key]) for row in centroids], label=f"class {size_class}")
    ax.set(xlabel=clock_label, ylabel="centroid height above the floor [mm]", title="concentration centroid per class")
    ax.legend()

    # Profiles: group the long-format rows by time.
    by_time = {}
    for row in profile:
        by_time.setdefault(row["time_s"], []).append(row)
    # In file order, i.e. ascending; the t = 0 rows have no contact data (no contact list before the first step).
    times = [t for t in by_time if any(row["contacts"] != "" for row in by_time[t])]
    if not times:
        sys.exit(f"plot_bed: {args.out_dir / 'bed_profile.csv'} has no rows with contact data yet")
    clocks = [number(by_time[t][0][clock]) for t in times]
    if args.times:
        chosen = []
        for wanted in args.times:
            nearest = min(range(len(times)), key=lambda k: abs(clocks[k] - wanted))
            if nearest not in chosen:
                chosen.append(nearest)
    else:
        count = min(4, len(times))
        chosen = sorted({round(k * (len(times) - 1) / max(count - 1, 1)) for k in range(count)})
    thickness = number(profile[0]["z_high_m"]) - number(profile[0]["z_low_m"])
    # Only the layers that ever hold a grain: the empty ones above the bed would flatten the plot.
    top = max((int(row["layer"]) for row in profile if int(row["grains"]) > 0), default=0)
    for k in chosen:
        rows = [row for row in by_time[times[k]] if int(row["layer"]) <= top]
        height = [(number(row["z_low_m"]) + number(row["z_high_m"])) / 2 / thickness for row in rows]
        label = f"{clock_label} = {clocks[k]:.4g}"
        axes[1].plot([number(row["coordination_number"]) for row in rows], height, "o-", label=label)
        axes[2].plot([number(row["mean_dimensionless_overlap"]) for row in rows], height, "o-", label=label)
    axes[1].set(xlabel="coordination number Z = 2 Nc / Np", ylabel=f"z / h (h = {1e3 * thickness:.3g} mm)",
                title="coordination number per sub-layer")
    axes[2].set(xlabel="mean dimensionless overlap δ*", ylabel=f"z / h (h = {1e3 * thickness:.3g} mm)",
                title="contact overlap per sub-layer")
    axes[2].ticklabel_format(axis="x", style="sci", scilimits=(-2, 3))
    for ax in axes[1:]:
        ax.legend(fontsize="small")

    plotting.write(figure, args.output or args.out_dir / "bed.png", "plot_bed")


if __name__ == "__main__":
    sys.exit(main())
