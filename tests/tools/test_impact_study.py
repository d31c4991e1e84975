#!/usr/bin/python3
"""Self-test of tools/riffle-tools impact-study's sensor measures on synthetic records whose answers are known: a
smooth impact pulse with a one-step spike on top (the peak reads the spike, the 1 ms mean peak the pulse plus the
spike's share of a millisecond), the arrival, the 15 ms impulse, and the scene it writes passing `riffle check`.

Usage: /usr/bin/python3 tests/tools/test_impact_study.py RIFFLE_BINARY [WORK_DIR]   (exit 0 = pass)
"""
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from riffle_tools import impact_study as study  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def main():
    riffle = sys.argv[1]
    work = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else tempfile.mkdtemp(prefix="impact_study_"))
    work.mkdir(parents=True, exist_ok=True)
    scale = study.PRESSURE_SCALE

    # Samples every 50 us (uneven steps are what the tool is written for: every third one 25 us) from 0.40 to 0.60 s:
    # dry (0) until 0.44 s, then a plateau of 2 rho g H for 20 ms, then 1 rho g H; one sample at 0.45 s carries a
    # spike of 30 rho g H (a one-step impact).
    times, pressures = [], []
    t = 0.40
    k = 0
    while t < 0.60:
        times.append(t)
        if t < 0.44 - 1e-12:
            p = 0.0
        elif t < 0.46:
            p = 2.0
        else:
            p = 1.0
        pressures.append(p * scale)
        t += 25e-6 if k % 3 == 2 else 50e-6
        k += 1
    spike = min(range(len(times)), key=lambda i: abs(times[i] - 0.45))
    pressures[spike] = 30.0 * scale
    step_before, step_after = times[spike] - times[spike - 1], times[spike + 1] - times[spike]
    metrics = study.sensor_metrics(times, pressures)
    check(abs(metrics["arrival_T"] - 0.44 * study.TIME_SCALE) < 60e-6 * study.TIME_SCALE,
          f"arrival T {metrics['arrival_T']}")
    check(metrics["peak"] == 30.0, f"peak {metrics['peak']}")
    # The spike is a triangle of height 28 above the plateau with half-width the steps either side: its area
    # 28 (dt_before + dt_after) / 2, spread over 1 ms, on top of the plateau's 2.
    expected = 2.0 + 28.0 * 0.5 * (step_before + step_after) / 0.001
    check(abs(metrics["peak1ms"] - expected) < 1e-6, f"peak1ms {metrics['peak1ms']}, expected {expected}")
    # The impulse over 15 ms after arrival: the plateau's 2 and the spike's area.
    arrival_t = times[next(i for i, p in enumerate(pressures) if p > 0.1 * scale)]
    check(abs(metrics["P15"] * 0.015 - (2.0 * 0.015 + 28.0 * 0.5 * (step_before + step_after)))
          < 2.0 * 50e-6 + 1e-9 + abs(arrival_t - 0.44) * 2.0, f"P15 {metrics['P15']}")

    # Without the spike the 1 ms mean peak is the plateau (the step at its end is more than 1 ms away from most of it).
    pressures[spike] = 2.0 * scale
    smooth = study.sensor_metrics(times, pressures)
    check(abs(smooth["peak1ms"] - 2.0) < 1e-12, f"peak1ms without the spike {smooth['peak1ms']}")
    check(smooth["peak"] == 2.0, f"peak without the spike {smooth['peak']}")

    # The scene the study writes is a valid scene.
    scene = work / "l10_cr02.toml"
    scene.write_text(study.make_scene(0.01, 0.2, 0.05, []))
    code = subprocess.run([riffle, "check", str(scene)], stdout=subprocess.DEVNULL).returncode
    check(code == 0, f"riffle check of the study's scene exited {code}")

    print("impact-study self-test:", "FAIL" if failures else "ok")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
