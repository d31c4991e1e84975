#!/usr/bin/python3
"""Self-test of tools/riffle-tools seed003-plots: its formulas against the hand-worked values of
tests/unit/bedload_laws_test.cpp, its summary on synthetic probe files with known answers, and (given a riffle binary)
that the probe files of a tiny real closed-box run have the columns the synthetic ones assume and go through the tool.

Usage: /usr/bin/python3 tests/tools/test_seed003_plots.py WORK_DIR [RIFFLE]   (exit 0 = pass)
"""
import csv
import math
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
RIFFLE_TOOLS = [sys.executable, str(ROOT / "tools" / "riffle-tools")]  # the tools' launcher
sys.path.insert(0, str(ROOT / "tools"))
import numpy as np  # noqa: E402
from riffle_tools import seed003_plots  # noqa: E402

G, S, RHO, NU = 9.81, 2.65, 1000.0, 1.0e-6


def close(a, b, rel):
    assert abs(a - b) <= rel * abs(b), (a, b, rel)


def check_formulas():
    close(float(seed003_plots.shields_soulsby_whitehouse(1.0)), 0.137453, 1e-5)
    close(float(seed003_plots.shields_soulsby_whitehouse(25.296)), 0.031404, 1e-4)
    close(float(seed003_plots.shields_brownlie(127.23)), 0.034801, 1e-4)
    close(float(seed003_plots.meyer_peter_mueller(0.1)), 0.097612, 1e-5)
    close(float(seed003_plots.wong_parker(0.1)), 0.045053, 1e-5)
    assert seed003_plots.meyer_peter_mueller(0.04) == 0.0 and seed003_plots.wong_parker(0.049) == 0.0
    # The curve in Re_f: Re_p = 127.23 (1 mm sand) gives Re_f = sqrt(0.034801) * 127.23 = 23.735.
    friction_reynolds, theta = seed003_plots.shields_curve_in_friction_reynolds(np.array([127.23]), "brownlie")
    close(float(friction_reynolds[0]), 23.735, 1e-4)


# Columns of the probes as systems/physics/measures/bedload_probes.cpp writes them (checked against a real run below).
HEADERS = {
    "moving_fraction": lambda k: ["time_s", "step"] + [f"class_{c}_moving_fraction" for c in range(k)]
    + ["all_moving_fraction"],
    "bedload_flux": lambda k: ["time_s", "step"] + [f"class_{c}_q_m2_s" for c in range(k)] + ["all_q_m2_s"]
    + [f"class_{c}_q_mean_m2_s" for c in range(k)] + ["all_q_mean_m2_s"],
    "bed_shear_stress": lambda k: ["time_s", "step", "grains_fx_N", "floor_fx_N", "tau_b_Pa", "tau_lid_Pa"]
    + [f"class_{c}_{name}" for name in ("diameter_m", "shields_b", "shields_lid") for c in range(k)],
    "packing_density": lambda k: ["time_s", "step", "lambda", "top_layer_grains"],
}


def write_probe(directory, kind, classes, rows):
    header = HEADERS[kind](classes)
    with open(directory / f"probe_{kind}.csv", "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        for row in rows:
            writer.writerow([row.get(name, "") for name in header])


def synthetic_run(directory, diameters, tau, moving, q_star, onset=None):
    """A run of 2 s at 0.01 s rows: constant tau; class k moving fraction `moving[k]` (the largest class from `onset`
    on, 0 before), its flux q*_k sqrt((s-1) g d^3); lambda falling from 0.42 to 0.26."""
    directory.mkdir(parents=True, exist_ok=True)
    times = np.arange(201) * 0.01
    classes = len(diameters)
    rows = {kind: [] for kind in HEADERS}
    for step, t in enumerate(times):
        base = dict(time_s=t, step=step)
        fractions = [moving[k] if (onset is None or k < classes - 1 or t >= onset) else 0.0 for k in range(classes)]
        rows["moving_fraction"].append(dict(base, **{f"class_{k}_moving_fraction": f for k, f in enumerate(fractions)},
                                            all_moving_fraction=float(np.mean(fractions))))
        flux = {f"class_{k}_q_m2_s": q_star[k] * math.sqrt((S - 1) * G * d ** 3) for k, d in enumerate(diameters)}
        rows["bedload_flux"].append(dict(base, **flux, all_q_m2_s=sum(flux.values())))
        shear = dict(base, tau_b_Pa=tau, tau_lid_Pa=tau)
        for k, d in enumerate(diameters):
            shear[f"class_{k}_diameter_m"] = d
            shear[f"class_{k}_shields_b"] = shear[f"class_{k}_shields_lid"] = tau / ((S - 1) * RHO * G * d)
        rows["bed_shear_stress"].append(shear)
        rows["packing_density"].append(dict(base, **{"lambda": 0.42 - 0.16 * t / times[-1], "top_layer_grains": 10}))
    for kind, kind_rows in rows.items():
        write_probe(directory, kind, classes, kind_rows)


def check_synthetic(work):
    small, large, mixture = work / "small_06", work / "large_10", work / "mixture_10"
    synthetic_run(small, [0.001], tau=1.2, moving=[0.05], q_star=[0.02])
    synthetic_run(large, [0.002], tau=1.5, moving=[0.0], q_star=[0.0])
    synthetic_run(mixture, [0.001, 0.002], tau=1.5, moving=[0.03, 0.02], q_star=[0.01, 0.002], onset=0.5)
    out = work / "figures"
    result = subprocess.run([*RIFFLE_TOOLS, "seed003-plots", "--small", f"0.6={small}",
                             "--large", f"1.0={large}", "--bidisperse", f"1.0={mixture}", "--out", str(out),
                             "--mixture-counts", "623", "213"],
                            capture_output=True, text=True, check=True)
    print(result.stdout)
    for name in ("fig4_moving_fraction.png", "fig5_shields.png", "fig6_mixture_classes.png", "fig7_packing.png",
                 "bedload_vs_shields.png", "seed003_summary.csv"):
        assert (out / name).stat().st_size > 0, name
    assert "onset of the large grains' motion at t = 0.5 s" in result.stdout, result.stdout
    rows = list(csv.DictReader(open(out / "seed003_summary.csv")))
    assert [(r["bed"], r["size_class"]) for r in rows] == [("small", "0"), ("large", "0"), ("bidisperse", "0"),
                                                           ("bidisperse", "1"), ("bidisperse", "D_m")]
    small_row = rows[0]
    theta = 1.2 / ((S - 1) * RHO * G * 0.001)  # 0.074135
    close(float(small_row["shields"]), theta, 1e-12)
    close(float(small_row["friction_reynolds"]), math.sqrt(1.2 / RHO) * 0.001 / NU, 1e-12)  # u* d / nu = 34.64
    close(float(small_row["relative_density"]), S, 1e-12)
    close(float(small_row["q_star"]), 0.02, 1e-12)
    close(float(small_row["q_star_mpm"]), 8 * (theta - 0.047) ** 1.5, 1e-12)
    close(float(small_row["q_star_wong_parker"]), 3.97 * (theta - 0.0495) ** 1.5, 1e-12)
    close(float(small_row["moving_fraction"]), 0.05, 1e-12)
    assert float(rows[1]["moving_fraction"]) == 0.0
    # The mixture's large class moves from 0.5 s: over the second half (1-2 s) its mean is 0.02.
    close(float(rows[3]["moving_fraction"]), 0.02, 1e-12)
    # D_m of the seed's mixture counts (623 x 1 mm + 213 x 2 mm, its Eq. 31): 1.2548 mm, Theta = 1.5 / (1650 g D_m).
    close(float(rows[4]["diameter_m"]), 0.001 * (623 + 2 * 213) / (623 + 213), 1e-12)
    close(float(rows[4]["shields"]), 1.5 / ((S - 1) * RHO * G * 0.001 * (623 + 2 * 213) / (623 + 213)), 1e-12)
    # A run's own window start (DIR@T) overrides --from for that run only: the mixture from 0.25 s holds 25 rows
    # (0.25-0.49 s) before its large class's onset and 151 after; the small bed keeps --from's window (constant).
    out_at = work / "figures_at"
    subprocess.run([*RIFFLE_TOOLS, "seed003-plots", "--small", f"0.6={small}",
                    "--bidisperse", f"1.0={mixture}@0.25", "--from", "1.5", "--out", str(out_at),
                    "--mixture-counts", "623", "213"], capture_output=True, text=True, check=True)
    rows_at = list(csv.DictReader(open(out_at / "seed003_summary.csv")))
    close(float(rows_at[2]["moving_fraction"]), 0.02 * 151 / 176, 1e-12)
    close(float(rows_at[0]["moving_fraction"]), 0.05, 1e-12)
    close(float(rows_at[0]["from_s"]), 1.5, 1e-9)
    close(float(rows_at[2]["from_s"]), 0.25, 1e-9)
    # A directory whose name holds '@' without a number after it is read whole; the same directory twice, with and
    # without its own start, keeps each run's window.
    odd = work / "runs@host" / "small"
    synthetic_run(odd, [0.001], tau=1.2, moving=[0.05], q_star=[0.02])
    parsed = seed003_plots.parse_runs([f"0.6={odd}", f"0.8={mixture}@0.25", f"1.0={mixture}"], "small")
    assert parsed == [(0.6, str(odd), None), (0.8, str(mixture), 0.25), (1.0, str(mixture), None)], parsed


TINY_SCENE = """
[run]
name = "seed003_tiny"
end_time = 0.005
dt = 5.0e-4
[materials.grain]
density = 2650.0
young_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
restitution = 0.5
friction = 0.5
rolling_friction = 0.05
max_impact_speed = 0.5
[tank]
size = [0.02, 0.02, 0.0175]
wall_material = "grain"
[solids]
[[solids.layered_beds]]
layers = 1
layer_thickness = 0.003
loose_factor = 1.5
[[solids.layered_beds.classes]]
diameter = 0.002
count = 6
material = "grain"
size_class = 1
[[solids.layered_beds.classes]]
diameter = 0.001
count = 30
material = "grain"
size_class = 0
[fluid]
spacing = 0.0025
clamp_negative_pressure = false
[[fluid.boxes]]
low = [0.0, 0.0, 0.0]
high = [0.02, 0.02, 0.01]
[[fluid.wall_boxes]]
low = [0.0, 0.0, 0.01]
high = [0.02, 0.02, 0.0175]
lid = "no_slip"
velocity = 0.01
[[output.probes]]
kind = "moving_fraction"
interval = 0.001
[[output.probes]]
kind = "packing_density"
layer_bottom = 0.001
interval = 0.001
[[output.probes]]
kind = "bedload_flux"
interval = 0.001
[[output.probes]]
kind = "bed_shear_stress"
interval = 0.001
"""


def check_real_run(work, riffle):
    """A tiny closed box of two grain sizes under a slow lid (0.01 m/s, 10 steps): the probes' headers are those
    assumed above."""
    scene = work / "tiny.toml"
    scene.write_text(TINY_SCENE)
    out = work / "tiny_run"
    subprocess.run([riffle, "run", str(scene), "--out", str(out), "--threads", "1"], check=True,
                   capture_output=True)
    for kind, header in HEADERS.items():
        with open(out / f"probe_{kind}.csv", newline="") as handle:
            found = next(csv.reader(handle))
        assert found == header(2), (kind, found, header(2))
    result = subprocess.run([*RIFFLE_TOOLS, "seed003-plots", "--bidisperse", f"0.0={out}",
                             "--out", str(work / "tiny_figures")], capture_output=True, text=True, check=True)
    assert (work / "tiny_figures" / "fig7_packing.png").exists(), result.stdout


def main():
    work = pathlib.Path(sys.argv[1])
    work.mkdir(parents=True, exist_ok=True)
    check_formulas()
    check_synthetic(work)
    if len(sys.argv) > 2:
        check_real_run(work, sys.argv[2])
    print("seed003_plots: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
