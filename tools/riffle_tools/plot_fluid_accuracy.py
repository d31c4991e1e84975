"""Speed against error of the MPS fluid: one marker per run of riffle_fluid_accuracy (tools/bench_fluid.sh).

    tools/riffle-tools plot-fluid-accuracy ACCURACY.csv [OUT.png] [--wall]

Left: hydrostatic tank, RMS pressure error over rho g H against the exact discrete answer rho g (H - l0/2 - z)
(filled) and against the continuum rho g (H - z) (hollow). Right: dam break, RMS of the surge front Z(T) against
Martin & Moyce after the best time shift (filled) and raw (hollow). The x axis is the run's CPU time (the sweep
runs on one thread, so that equals its wall time on an idle core and does not depend on the machine's load);
--wall plots the wall time instead. Runs that failed are drawn as crosses along the top of their panel; still-water
runs that drifted more than l0/2 as crosses at their error.
"""
import argparse
import math
import sys

from . import plotting
from .run_outputs import number, read_rows

plt = plotting.pyplot("plot_fluid_accuracy")


def resolution_label(row):
    l0 = number(row["l0"])
    if row["case"] == "dam_break":
        return f"a/{round(0.1 / l0)}"
    return f"{l0 * 1000:g} mm"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("accuracy", metavar="ACCURACY.csv", help="riffle_fluid_accuracy's table")
    parser.add_argument("out", metavar="OUT.png", nargs="?", default="docs/fluid_speed_vs_error.png",
                        help="the figure (default docs/fluid_speed_vs_error.png)")
    parser.add_argument("--wall", action="store_true", help="the wall time on the x axis instead of the CPU time")
    args = parser.parse_args(argv)
    out = args.out
    rows = read_rows(args.accuracy)
    time_key = "wall_s" if args.wall else "cpu_s"

    panels = [
        ("hydrostatic", "rms_vs_rho_g_H_minus_l0half_minus_z", "rms_vs_rho_g_H_minus_z",
         "hydrostatic tank",
         "RMS(p - p_exact) / (rho g H)\nfilled: vs rho g (H - l0/2 - z); hollow: vs rho g (H - z)"),
        ("dam_break", "front_rms_shifted", "front_rms_raw", "dam break vs Martin & Moyce (T <= 3.33)",
         "RMS of front Z(T)\nfilled: after best time shift; hollow: raw"),
    ]
    variants = sorted({r["variant"] for r in rows} - {"all"})
    colours = {"all": "black"}
    palette = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, v in enumerate(variants):
        colours[v] = palette[k % len(palette)]

    fig, axes = plt.subplots(1, 2, figsize=(14, 6.5))
    for ax, (case, main_key, second_key, title, ylabel) in zip(axes, panels):
        case_rows = [r for r in rows if r["case"] == case]
        if not case_rows:
            ax.set_visible(False)
            continue
        finite = [number(r[k]) for r in case_rows for k in (main_key, second_key)
                  if math.isfinite(number(r[k])) and number(r[k]) > 0]
        top = max(finite) * 2.0 if finite else 1.0
        # The resolution series of the full scheme set, joined by lines.
        base = sorted((r for r in case_rows if r["variant"] == "all" and r["stable"] == "1"),
                      key=lambda r: number(r[time_key]))
        for key, style in ((main_key, "-"), (second_key, ":")):
            xs = [number(r[time_key]) for r in base]
            ys = [number(r[key]) for r in base]
            ax.plot(xs, ys, style, color="grey", lw=1, zorder=1)
        # Variants whose error equals the full set's at the same resolution (within 0.5 %) are not labelled one by
        # one: the full set's label lists them instead.
        same = {}
        for r in case_rows:
            if r["variant"] == "all" or r["stable"] != "1":
                continue
            for b in case_rows:
                if b["variant"] == "all" and b["l0"] == r["l0"] and b["stable"] == "1":
                    y, y0 = number(r[main_key]), number(b[main_key])
                    if math.isfinite(y) and math.isfinite(y0) and abs(y / y0 - 1.0) < 0.005:
                        same.setdefault(r["l0"], []).append(r["variant"])
                        r["_same"] = True
        failed = 0
        for r in case_rows:
            x = max(number(r[time_key]), 1e-3)
            colour = colours.get(r["variant"], "grey")
            label = resolution_label(r) if r["variant"] == "all" else f"{r['variant']} {resolution_label(r)}"
            if r["stable"] != "1" and math.isfinite(number(r[main_key])):  # drifted: keep its error, mark it
                y1 = number(r[main_key])
                ax.scatter([x], [y1], marker="x", s=60, color=colour, zorder=3)
                ax.annotate(f"{label} (drift {number(r['drift_l0']):.0f} l0, > l0/2 from t={number(r.get('unstable_from_t')):.2f})", (x, y1),
                            textcoords="offset points", xytext=(4, 3), fontsize=7, color=colour)
                continue
            if r["stable"] != "1":
                reached = number(r.get("unstable_from_t", r["reached_time"]))
                when = reached * math.sqrt(2 * 9.81 / 0.1) if case == "dam_break" else reached
                ax.scatter([x], [top], marker="x", s=60, color=colour, zorder=3)
                failed += 1
                ax.annotate(f"{label}: {r['status']} at {'T' if case == 'dam_break' else 't'}={when:.2f}",
                            (x, top), textcoords="offset points", xytext=(-60, -12 * failed), fontsize=7,
                            color=colour)
                continue
            y1, y2 = number(r[main_key]), number(r[second_key])
            ax.scatter([x], [y1], marker="o", s=36, color=colour, zorder=3)
            if math.isfinite(y2):
                ax.scatter([x], [y2], marker="o", s=36, facecolors="none", edgecolors=colour, zorder=3)
            if r.get("_same"):
                continue
            if r["variant"] == "all" and r["l0"] in same:
                label += " = " + ", ".join(same[r["l0"]])
            ax.annotate(label, (x, y1), textcoords="offset points", xytext=(4, 3), fontsize=7, color=colour)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(("wall time" if args.wall else "run time: CPU seconds, 1 thread") + " [s]")
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_title("hydrostatic tank 0.06 x 0.03 m, H = 6 cm")
    fig.suptitle("riffle MPS fluid: speed against error (one marker per run; black = all schemes on, "
                 "colours = one scheme off or a looser PPE tolerance)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"plot_fluid_accuracy: wrote {out}")


if __name__ == "__main__":
    sys.exit(main())
