"""Summary table of a resolution study (tools/resolution_study.sh): per water spacing, the class centroids and the
segregation index S at t/T = 5 and 10 (fig06_centroids.csv), and per size class the mean forces per grain over the
last two periods (fig17_19_force_balance.csv): the vertical pressure, drag and contact forces over m g and the RMS of
the horizontal drag and pressure forces over m a_max (a_max = A (2 pi f)^2, the tank's peak acceleration).

Usage: tools/riffle-tools resolution-summary OUT_ROOT   (OUT_ROOT holds l0_<mm>mm/figures/)
"""
import argparse
import math
import pathlib
import sys

from .run_outputs import read_rows as read


def at(rows, t_over_T, key):
    best = min(rows, key=lambda r: abs(float(r["t_over_T"]) - t_over_T))
    return float(best[key]) if abs(float(best["t_over_T"]) - t_over_T) < 0.2 else math.nan


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out_root", type=pathlib.Path, metavar="OUT_ROOT", help="holds l0_<mm>mm/figures/")
    root = parser.parse_args(argv).out_root
    runs = sorted(root.glob("l0_*mm"), key=lambda p: -float(p.name[3:-2]))
    print(f"# {root}: centroids [mm above the floor] and S at t/T = 5 and 10")
    print("| l0 | small 5 | medium 5 | large 5 | S 5 | small 10 | medium 10 | large 10 | S 10 | wall time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for run in runs:
        path = run / "figures" / "fig06_centroids.csv"
        if not path.exists():
            print(f"| {run.name[3:]} | (no fig06) |")
            continue
        rows = read(path)
        cells = []
        for t in (5.0, 10.0):
            cells += [f"{1000 * at(rows, t, f'class_{k}_centroid_m'):.1f}" for k in (0, 1, 2)]
            cells.append(f"{at(rows, t, 'segregation_index'):.3f}")
        wall = ""
        if (run / "wall_s.txt").exists():  # the run's wall time (tools/resolution_study.sh)
            wall = (run / "wall_s.txt").read_text().strip() + " s"
        print(f"| {run.name[3:]} | " + " | ".join(cells) + f" | {wall} |")
    print()
    print("# mean force per grain over the last two periods: z over m g (pressure, drag, contact, and the new forces"
          " where written), x RMS over m a_max (drag, pressure)")
    for run in runs:
        path = run / "figures" / "fig17_19_force_balance.csv"
        if not path.exists():
            continue
        rows = read(path)
        last = max(float(r["t_over_T"]) for r in rows)
        window = [r for r in rows if float(r["t_over_T"]) >= last - 2.0]
        names = [n[:-len("_z_over_m_g")] for n in rows[0] if n.endswith("_z_over_m_g") and
                 not n.startswith(("gravity", "total"))]
        print(f"\n{run.name}: | class | " + " | ".join(f"{n} z/mg" for n in names) +
              " | drag x RMS/m a_max | pressure x RMS/m a_max |")
        for k in sorted({r["size_class"] for r in window}):
            sel = [r for r in window if r["size_class"] == k]
            mean_z = [sum(float(r[f"{n}_z_over_m_g"]) for r in sel) / len(sel) for n in names]
            rms = [math.sqrt(sum(float(r[f"{n}_x_over_m_amax"]) ** 2 for r in sel) / len(sel))
                   for n in ("drag_force", "pressure_force")]
            print(f"| {k} | " + " | ".join(f"{v:+.3f}" for v in mean_z) + " | " +
                  " | ".join(f"{v:.3f}" for v in rms) + " |")


if __name__ == "__main__":
    sys.exit(main())
