"""The checkable claims of seed 000's result figures, measured on one riffle run, as a Markdown list.

The seed (Tazaki, Harada & Gotoh) gives almost no numbers for its results; what a run can be held to are the trends
its text states for each figure (line numbers of ../shared/seeds/000_*.txt in docs/RESULTS.md). This tool reads the
figure tables that tools/riffle-tools seed-figures writes into RUN_DIR/figures/ (run it first, with the stages 10 and
85 and the concentration times 85 and 100 inside the run) and prints, per figure, the numbers that decide each claim:

  fig11  the volume concentration per class per 15 mm sub-layer at t/T = 85 and 100 (layered, top sub-layer empty)
  fig12  the coordination number mid-bed (15-30 mm) and above 30 mm, and the mean overlap at the top and the bottom
         (below 15 mm) of the bed, at t/T = 10 and 85 (the seed: Z falls mid-bed, Z <= 1 above 30 mm, the overlap
         rises at the top and drops at the bottom)
  fig14  the grains' x-velocity relative to the tank per class, the phase-mean magnitude over the sub-layers where
         every class is present, periods 10 and 85 (small faster than large; larger when developed)
  fig15  the fluid's x-velocity (relative to the tank) at the seed's phases pi/2 and 3pi/2, periods 10 and 85: the
         largest below the initial bed height (45 mm) and where, and the mean above it (the seed: an overshoot just
         below the bed surface, larger than the flow above it, that descends)
  fig16  the heights of the largest |S|^2 and the largest mean positive Q, everywhere and up to 50 mm, periods 10
         and 85 (near the bed surface, descending)
  fig17  the r.m.s. over periods 10-12 and 85-87 of the contact, pressure-gradient and drag x-forces per class (the
         seed: contact about 2 x the pressure gradient, drag insignificant)
  fig20  the granular temperature's peaks per period and its largest value, periods 10 and 85 (two peaks a period,
         larger when developed)

Usage: tools/riffle-tools seed-checklist RUN_DIR [--figures DIR]
"""
import argparse
import csv
import math
import pathlib
import sys

STAGES = (10, 85)


def rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def mm(value):
    return f"{1e3 * value:.0f} mm" if not math.isnan(value) else "n/a"


def concentration_lines(table):
    """Per target time: each sub-layer's concentration per class, bottom to top, and the class that fills it most."""
    lines = []
    for target in sorted({r["target_t_over_T"] for r in table}, key=float):
        if float(target) < 80:
            continue
        picked = [r for r in table if r["target_t_over_T"] == target]
        layers = sorted({int(r["sublayer"]) for r in picked})
        parts = []
        for layer in layers:
            cells = {int(r["size_class"]): number(r["volume_concentration"]) for r in picked
                     if int(r["sublayer"]) == layer}
            top = max(cells, key=cells.get)
            parts.append(f"{1e3 * number(next(r['z_low_m'] for r in picked if int(r['sublayer']) == layer)):.0f} mm: "
                         + " / ".join(f"{cells[k]:.2f}" for k in sorted(cells)) + f" (most: class {top})")
        lines.append(f"- fig11, t/T = {float(target):g} (small / medium / large per sub-layer, bottom up): "
                     + "; ".join(parts))
    return lines


def coordination_lines(table):
    lines = []
    times = sorted({number(r["t_over_T"]) for r in table})
    for time in times:
        picked = [r for r in table if number(r["t_over_T"]) == time]

        def mean_of(key, low, high):
            cells = [r for r in picked if low <= number(r["z_low_m"]) < high and int(r["grains"]) > 0]
            weight = sum(int(r["grains"]) for r in cells)
            return sum(int(r["grains"]) * number(r[key]) for r in cells) / weight if weight else math.nan

        occupied = [number(r["z_high_m"]) for r in picked if int(r["grains"]) >= 10]
        top = max(occupied) if occupied else math.nan
        lines.append(f"- fig12, t/T = {time:.0f}: Z mid-bed (15-30 mm) {mean_of('coordination_number', 0.015, 0.03):.2f}, "
                     f"above 30 mm {mean_of('coordination_number', 0.03, 1.0):.2f}; mean overlap delta* in the top "
                     f"10 mm of the bed ({1e3 * (top - 0.01):.0f}-{1e3 * top:.0f} mm) "
                     f"{mean_of('mean_dimensionless_overlap', top - 0.0101, top):.2e}, below 15 mm "
                     f"{mean_of('mean_dimensionless_overlap', 0.0, 0.015):.2e}")
    return lines


def stage_rows(table, period):
    return [r for r in table if int(float(r["period_first"])) == period]


def grain_velocity_lines(table):
    lines = []
    for period in STAGES:
        picked = stage_rows(table, period)
        if not picked:
            continue
        classes = sorted({int(r["group"]) for r in picked})
        by_layer = {}
        for r in picked:
            by_layer.setdefault((r["phase_index"], int(r["sublayer"])), {})[int(r["group"])] = \
                abs(number(r["mean_vx_relative_to_tank_m_s"]))
        shared = [cells for cells in by_layer.values() if len(cells) == len(classes)]
        means = {k: sum(c[k] for c in shared) / len(shared) for k in classes} if shared else {}
        lines.append(f"- fig14, period {period}: mean |v_x - v_tank| over the {len(shared)} phase-sub-layers where "
                     "every class is present: "
                     + ", ".join(f"class {k} {1e3 * v:.1f} mm/s" for k, v in means.items()))
    return lines


def peak_height(cells, key):
    """The mid-height of the sub-layer with the largest |value| (nan without cells)."""
    cells = [c for c in cells if not math.isnan(number(c[key]))]
    if not cells:
        return math.nan
    best = max(cells, key=lambda c: abs(number(c[key])))
    return 0.5 * (number(best["z_low_m"]) + number(best["z_high_m"]))


BED_TOP = 0.045  # [m] the seed's initial bed height (z/d_s1 = 9): its Figs. 15-16 compare below and above it


def fluid_velocity_lines(table):
    lines = []
    for period in STAGES:
        picked = stage_rows(table, period)
        if not picked:
            continue
        parts = []
        for phi in ("pi/2", "3pi/2"):
            cells = [r for r in picked if r["seed_phi"] == phi and int(r["samples"]) > 0]
            below = [r for r in cells if number(r["z_high_m"]) <= BED_TOP + 1e-9]
            above = [r for r in cells if number(r["z_low_m"]) >= BED_TOP - 1e-9]
            key = "mean_vx_relative_to_tank_m_s"
            peak_below = max((abs(number(r[key])) for r in below), default=math.nan)
            mean_above = sum(abs(number(r[key])) for r in above) / len(above) if above else math.nan
            parts.append(f"seed phase {phi}: below {1e3 * BED_TOP:.0f} mm the largest {1e3 * peak_below:.0f} mm/s at "
                         f"{mm(peak_height(below, key))}, above it {1e3 * mean_above:.0f} mm/s on average")
        lines.append(f"- fig15, period {period}: fluid |u_x - v_tank|, " + "; ".join(parts))
    return lines


def strain_lines(table):
    lines = []
    for period in STAGES:
        picked = [r for r in stage_rows(table, period) if int(r["particles"]) > 0]
        if not picked:
            continue
        inside = [r for r in picked if number(r["z_high_m"]) <= BED_TOP + 0.005 + 1e-9]
        lines.append(f"- fig16, period {period}: largest |S|^2 at {mm(peak_height(picked, 'mean_S2_1_s2'))} "
                     f"(up to {1e3 * (BED_TOP + 0.005):.0f} mm: at {mm(peak_height(inside, 'mean_S2_1_s2'))}), "
                     f"largest mean positive Q at {mm(peak_height(picked, 'mean_positive_Q_1_s2'))} "
                     f"(up to {1e3 * (BED_TOP + 0.005):.0f} mm: at {mm(peak_height(inside, 'mean_positive_Q_1_s2'))})")
    return lines


def force_lines(table):
    lines = []
    for period in STAGES:
        low, high = period - 1, period + 2  # periods k..k+2: t/T in [k-1, k+2]
        picked = [r for r in table if low <= number(r["t_over_T"]) <= high]
        if not picked:
            continue
        parts = []
        for k in sorted({int(r["size_class"]) for r in picked}):
            cells = [r for r in picked if int(r["size_class"]) == k]

            def rms(name):
                return math.sqrt(sum(number(r[f"{name}_x_N"]) ** 2 for r in cells) / len(cells))

            pressure = rms("pressure_force")
            parts.append(f"class {k}: contact / pressure {rms('contact_force') / pressure:.2f}, "
                         f"drag / pressure {rms('drag_force') / pressure:.2f}" if pressure > 0 else f"class {k}: n/a")
        lines.append(f"- fig17, periods {period}-{period + 2}: r.m.s. x-forces per grain, " + "; ".join(parts))
    return lines


def temperature_lines(table):
    lines = []
    for period in STAGES:
        cells = [r for r in table if period - 1 <= number(r["t_over_T"]) <= period + 2]
        values = [number(r["Tg_all_m2_s2"]) for r in cells]
        if len(values) < 5:
            continue
        spacing = (number(cells[-1]["t_over_T"]) - number(cells[0]["t_over_T"])) / (len(values) - 1)
        if spacing > 0.125:  # two peaks a period need at least 8 frames a period to be told from aliasing
            lines.append(f"- fig20, periods {period}-{period + 2}: frames {spacing:.2f} periods apart, too sparse "
                         "for peaks a period")
            continue
        # Peaks a period from the first to the last peak (the window's ends cut a peak or not, by phase alone).
        peaks = [number(cells[i]["t_over_T"]) for i in range(1, len(values) - 1)
                 if values[i] > values[i - 1] and values[i] >= values[i + 1]]
        rate = (len(peaks) - 1) / (peaks[-1] - peaks[0]) if len(peaks) > 1 and peaks[-1] > peaks[0] else math.nan
        lines.append(f"- fig20, periods {period}-{period + 2}: {rate:.1f} peaks of T_g a period "
                     f"({len(values)} frames), largest T_g {max(values):.2e} m^2/s^2")
    return lines


SECTIONS = (("fig11_concentration.csv", concentration_lines), ("fig12_coordination_overlap.csv", coordination_lines),
            ("fig14_velocity_phases.csv", grain_velocity_lines), ("fig15_fluid_velocity.csv", fluid_velocity_lines),
            ("fig16_strain_q.csv", strain_lines), ("fig17_19_force_balance.csv", force_lines),
            ("fig20_granular_temperature.csv", temperature_lines))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run_dir", type=pathlib.Path)
    parser.add_argument("--figures", type=pathlib.Path, help="the figure tables (default RUN_DIR/figures)")
    args = parser.parse_args(argv)
    figures = args.figures or args.run_dir / "figures"
    if not figures.is_dir():
        parser.error(f"{figures}: no figure tables (run tools/riffle-tools seed-figures {args.run_dir} first)")
    print(f"# seed 000's checkable claims, measured on {args.run_dir}")
    for name, lines_of in SECTIONS:
        path = figures / name
        if not path.exists():
            print(f"- {name}: not drawn")
            continue
        for line in lines_of(rows(path)) or [f"- {name}: no rows at the stages {STAGES}"]:
            print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
