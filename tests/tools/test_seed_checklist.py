#!/usr/bin/python3
"""Self-test of tools/riffle-tools seed-checklist on synthetic figure tables with known answers (the column names
are the ones tools/riffle-tools seed-figures writes; test_seed_figures.py checks those tables against a synthetic run).

Checks: fig15's largest fluid velocity below the bed height and the mean above it; fig17's r.m.s. force ratios; fig20's
peaks a period (a signal with two a period); fig11's most filled class per sub-layer; a missing table is reported.

Usage: /usr/bin/python3 tests/tools/test_seed_checklist.py WORK_DIR   (exit 0 = pass)
"""
import csv
import math
import pathlib
import shutil
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
RIFFLE_TOOLS = [sys.executable, str(ROOT / "tools" / "riffle-tools")]  # the tools' launcher
failures = []


def check(condition, text):
    print(("ok - " if condition else "not ok - ") + text)
    if not condition:
        failures.append(text)


def write(path, header, rows):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        writer.writerows(rows)


def main():
    work = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/seed_checklist_work")
    shutil.rmtree(work, ignore_errors=True)
    figures = work / "figures"
    figures.mkdir(parents=True)
    # fig15: period 10, seed phase pi/2, 5 mm sub-layers; |u| peaks at 0.08 m/s in 35-40 mm, 0.03 m/s above 45 mm.
    header = ["stage", "period_first", "period_last", "phase_index", "tank_phase_rad", "seed_phi", "frames",
              "mean_abs_phase_error_deg", "group", "sublayer", "z_low_m", "z_high_m", "samples", "mean_vx_lab_m_s",
              "mean_vx_relative_to_tank_m_s"]
    rows = []
    for layer in range(12):
        low = 0.005 * layer
        u = -0.08 if layer == 7 else (0.03 if low >= 0.045 else 0.01)
        rows.append(["period 10", 10, 10, 0, 0, "pi/2", 1, 0, "fluid", layer, low, low + 0.005, 10, u, u])
    write(figures / "fig15_fluid_velocity.csv", header, rows)
    # fig17: class 0 with contact x = 2 sin, pressure x = sin, drag x = 0.1 sin over periods 10-12 (t/T 9-12).
    header = ["time_s", "t_over_T", "tank_phase_rad", "size_class", "grains"] + [
        f"{name}_x_N" for name in ("pressure_force", "drag_force", "contact_force")]
    rows = []
    for i in range(31):
        t = 9.0 + 0.1 * i
        f = math.sin(2 * math.pi * t)
        rows.append([t / 1.7, t, 0, 0, 10, f, 0.1 * f, 2.0 * f])
    write(figures / "fig17_19_force_balance.csv", header, rows)
    # fig20: T_g = 1 + cos(4 pi t/T) sampled ten times a period over t/T 9-12 (two peaks a period; 1e-4 scale).
    rows = [[(9 + 0.1 * i) / 1.7, 9 + 0.1 * i, 0, 1e-4 * (1.0 + math.cos(4 * math.pi * (9 + 0.1 * i + 0.03)))]
            for i in range(31)]
    write(figures / "fig20_granular_temperature.csv", ["time_s", "t_over_T", "tank_phase_rad", "Tg_all_m2_s2"], rows)
    # fig11 at t/T = 85: small fills the bottom sub-layer, large the one above.
    header = ["target_t_over_T", "frame_t_over_T", "size_class", "sublayer", "z_low_m", "z_high_m", "grains",
              "grain_volume_m3", "volume_concentration"]
    rows = [[85, 85, k, layer, 0.015 * layer, 0.015 * (layer + 1), 1, 1, c]
            for layer, values in enumerate(((0.5, 0.1, 0.05), (0.1, 0.1, 0.3)))
            for k, c in enumerate(values)]
    write(figures / "fig11_concentration.csv", header, rows)

    result = subprocess.run([*RIFFLE_TOOLS, "seed-checklist", str(work)],
                            capture_output=True, text=True, timeout=60)
    out = result.stdout
    print(out)
    check(result.returncode == 0, f"exits 0 ({result.stderr[-300:]})")
    check("below 45 mm the largest 80 mm/s at 38 mm, above it 30 mm/s on average" in out,
          "fig15: the largest fluid velocity below the bed height (80 mm/s at 35-40 mm) and the mean above (30 mm/s)")
    check("class 0: contact / pressure 2.00, drag / pressure 0.10" in out, "fig17: r.m.s. ratios 2 and 0.1")
    check("2.0 peaks of T_g a period" in out, "fig20: two peaks a period")
    check("0 mm: 0.50 / 0.10 / 0.05 (most: class 0); 15 mm: 0.10 / 0.10 / 0.30 (most: class 2)" in out,
          "fig11: the most filled class per sub-layer")
    check("fig12_coordination_overlap.csv: not drawn" in out, "a table not drawn is named")
    missing = subprocess.run([*RIFFLE_TOOLS, "seed-checklist", str(work / "nothing")],
                             capture_output=True, text=True, timeout=60)
    check(missing.returncode != 0 and "no figure tables" in missing.stderr, "a run without figures: a clear error")
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
