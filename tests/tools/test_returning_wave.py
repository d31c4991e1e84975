#!/usr/bin/python3
"""Self-test of tools/riffle-tools returning-wave: the scenes it writes pass `riffle check`, and its timing of the
returning bore is right on a synthetic run whose crossings are known.

Usage: /usr/bin/python3 tests/tools/test_returning_wave.py RIFFLE_BINARY [WORK_DIR]   (exit 0 = pass)
"""
import math
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from riffle_tools import returning_wave as rw  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def near(a, b, tolerance=1e-9):
    return a is not None and abs(a - b) <= tolerance


def main():
    riffle = sys.argv[1]
    work = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else tempfile.mkdtemp(prefix="returning_wave_"))
    work.mkdir(parents=True, exist_ok=True)

    # The scene as shipped, and as the tool rewrites it, are valid scenes.
    variants = {"shipped": rw.SCENE.read_text(),
                "l23_s8": rw.scene_text(0.023, 8, [("courant", "0.1"), ("kinematic_viscosity", "0")],
                                        [("ecs", "false")], 0.02)}
    for name, text in variants.items():
        scene = work / f"{name}.toml"
        scene.write_text(text)
        result = subprocess.run([riffle, "check", str(scene)], capture_output=True, text=True)
        check(result.returncode == 0, f"riffle check {name}: exit {result.returncode}\n{result.stderr[-2000:]}")
    text = variants["l23_s8"]
    check("spacing = 0.023" in text and "size = [1.61, 0.184, 0.621]" in text and "courant = 0.1" in text
          and "[fluid.schemes]\necs = false" in text and "vtk_interval = 0.02" in text,
          "scene_text did not rewrite spacing, tank, keys, schemes and vtk interval")
    check(text.count("[0.3, 0.092]") == 1 and text.count(", 0.092]") == 4 + len(rw.EXTRA),
          "gauges not in the slab's middle plane")
    text = rw.scene_text(0.01, 4, [("density", "998")], [])
    check("[materials.glass]\ndensity = 2500.0" in text and "[fluid]\ndensity = 998\n" in text,
          "--set density must change the fluid's density, not the glass's")
    try:
        rw.scene_text(0.02, 4, [], [])
        check(False, "a spacing that does not divide 1.61 m was accepted")
    except SystemExit:
        pass

    # The reference: the mean of the two digitisations.
    ref = rw.reference()
    check(near(ref[("H3", 0.5)], 0.5 * (6.872 + 6.912)) and near(ref[("H4", 0.5)], 0.5 * (6.116 + 6.108)),
          f"reference times {ref}")

    # A synthetic run: every gauge's level ramps from 0.2 H to 0.8 H between T0 and T0 + 0.6 (so it crosses 0.5 H at
    # T0 + 0.3 and 0.4 H at T0 + 0.2), with a spike to 0.9 H at T = 3 that must be ignored (before T = 4.5); the
    # front reaches 1.6 m at T = 2.5.
    run = work / "synthetic"
    run.mkdir(exist_ok=True)
    start = {"H3": 7.0, "H4": 6.0}
    names = list(rw.GAUGES) + [f"x{x:.3f}" for x in rw.EXTRA]
    with open(run / "probe_gauges.csv", "w") as gauges, open(run / "probe_front.csv", "w") as front:
        gauges.write("time_s,step," + ",".join(f"gauge{k}_z_m" for k in range(len(names))) + "\n")
        front.write("time_s,step,front_m\n")
        for step in range(0, 1601):
            T = step * 0.005
            t = T / rw.T_SCALE
            levels = []
            for name in names:
                t0 = start.get(name, 6.5)
                h = 0.2 + 0.6 * min(1.0, max(0.0, (T - t0) / 0.6))
                if abs(T - 3.0) < 1e-9:
                    h = 0.9
                levels.append(f"{h * rw.H:.9g}")
            gauges.write(f"{t!r},{step}," + ",".join(levels) + "\n")
            front.write(f"{t!r},{step},{min(1.61, 0.6 + T * 0.4):.9g}\n")
    result = rw.analyse(run)
    check(near(result["H3@0.5"], 7.3, 1e-6) and near(result["H4@0.5"], 6.3, 1e-6), f"0.5 crossings {result}")
    check(near(result["H3@0.4"], 7.2, 1e-6) and near(result["H4@0.4"], 6.2, 1e-6), f"0.4 crossings {result}")
    check(near(result["H3@0.5_late"], 7.3 - ref[("H3", 0.5)], 1e-6), "late")
    check(near(result["speed"], (1.3625 - 1.114) / 0.3 / 1.0, 1e-6), f"speed {result['speed']}")
    check(near(result["impact"], 2.5, 1e-6), f"impact {result['impact']}")
    check(all(near(t, 6.8, 1e-6) for _, t in result["trace"]), "trace")
    check(math.isclose(result["H3_before"], 0.2, abs_tol=1e-9), f"level before {result['H3_before']}")
    print("PASS" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
