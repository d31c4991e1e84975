#!/usr/bin/python3
"""Self-test of tools/riffle-tools bed-tilt with a stand-in for riffle: a script that reads the tilt from the
command line's run.gravity and writes a moving-fraction probe that stays at 0 below 23.3 degrees (a bed that holds),
rises to 1 above it (a bed that flows), and rises then falls back to 0.2 at exactly 21 degrees (a partial slide,
counted as neither; at 23 instead, in a second sweep, where a halving lands on it). Checks: the gravity handed to riffle is 9.81 (sin, 0, -cos) of each angle; each listed angle is
run once per variant with the variant's own --set; the halvings close in on 23.3 (the interval after two is 2 wide
less two halvings: [23, 23.5]); the tangents in onset.csv are the interval's; the figure is written; a second call runs nothing and writes
the same tables; a failing run fails the sweep.

Usage: /usr/bin/python3 tests/tools/test_bed_tilt.py [WORK_DIR]   (exit 0 = pass)
"""
import csv
import math
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
RIFFLE_TOOLS = [sys.executable, str(ROOT / "tools" / "riffle-tools")]

STAND_IN = r'''#!/usr/bin/python3
import math, os, sys
args = sys.argv[1:]
out = args[args.index("--out") + 1]
sets = [item for k, item in enumerate(args) if k > 0 and args[k - 1] == "--set"]
gravity = [float(v) for v in sets[0].split("=", 1)[1].strip("[]").split(",")]
angle = math.degrees(math.atan2(gravity[0], -gravity[2]))
os.makedirs(out, exist_ok=True)
with open(os.path.join(os.path.dirname(os.path.dirname(out)), "calls.txt"), "a") as log:
    log.write(f"{angle:.6f} {math.hypot(gravity[0], gravity[2]):.6f} {gravity[1]} {' '.join(sets[1:])}\n")
if os.environ.get("STAND_IN_FAIL"):
    sys.exit(3)
with open(os.path.join(out, "probe_moving_fraction.csv"), "w") as probe:
    probe.write("time_s,step,class_0_moving_fraction,all_moving_fraction\n")
    for k in range(101):
        t = 0.01 * k
        if abs(angle - float(os.environ.get("PARTIAL_ANGLE", "21"))) < 1e-3:
            f = min(1.0, 10 * t) if t < 0.5 else 0.2
        else:
            f = 0.0 if angle < 23.3 else min(1.0, 5 * t)
        probe.write(f"{t:.2f},{k},{f},{f}\n")
'''


def run_tool(work, stand_in, env=None):
    command = RIFFLE_TOOLS + ["bed-tilt", "--riffle", str(stand_in), "--work", str(work), "--angles", "20", "21",
                              "22", "24", "26", "--refine", "2", "--variant", "rough:contact.friction=0.7"]
    return subprocess.run(command, capture_output=True, text=True, env=env)


def read(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def main():
    base = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(tempfile.mkdtemp())
    shutil.rmtree(base, ignore_errors=True)
    base.mkdir(parents=True)
    stand_in = base / "riffle"
    stand_in.write_text(STAND_IN)
    stand_in.chmod(0o755)
    work = base / "tilt"
    failures = []

    result = run_tool(work, stand_in)
    if result.returncode != 0:
        print(result.stdout, result.stderr)
        return 1
    calls = [line.split() for line in (work / "calls.txt").read_text().splitlines()]
    # 5 listed angles and 2 halvings ([22, 24] -> 23 holds -> [23, 24] -> 23.5 flows) for each of the two variants.
    expected = sorted([20, 21, 22, 24, 26, 23, 23.5] * 2)
    angles = sorted(round(float(call[0]), 4) for call in calls)
    if angles != expected:
        failures.append(f"angles run {angles}, expected {expected}")
    if any(abs(float(call[1]) - 9.81) > 1e-5 or float(call[2]) != 0.0 for call in calls):
        failures.append("gravity is not 9.81 in the x-z plane")
    if sum(1 for call in calls if call[3:] == ["contact.friction=0.7"]) != 7:
        failures.append("the variant's --set is not on its seven runs")
    tilt = read(work / "tilt.csv")
    states = {(row["variant"], float(row["angle_deg"])): row["state"] for row in tilt}
    if states[("scene", 21.0)] != "partial" or states[("scene", 20.0)] != "holds" or states[("scene", 24.0)] != "flows":
        failures.append(f"states {states}")
    onsets = read(work / "onset.csv")
    for row in onsets:
        low, high = float(row["holds_up_to_deg"]), float(row["flows_from_deg"])
        if (low, high) != (23.0, 23.5):
            failures.append(f"{row['variant']}: onset interval [{low}, {high}], expected [23, 23.5]")
        if abs(float(row["friction_low"]) - math.tan(math.radians(23.0))) > 1e-12:
            failures.append(f"{row['variant']}: tangent of the hold {row['friction_low']}")
    if not (work / "tilt.png").is_file() or (work / "tilt.png").stat().st_size < 1000:
        failures.append("no figure tilt.png")
    first_tables = ((work / "tilt.csv").read_text(), (work / "onset.csv").read_text())

    again = run_tool(work, stand_in)
    if again.returncode != 0 or len((work / "calls.txt").read_text().splitlines()) != len(calls):
        failures.append("a second call ran riffle again")
    if ((work / "tilt.csv").read_text(), (work / "onset.csv").read_text()) != first_tables:
        failures.append("a second call wrote other tables")

    # A partial slide at a halving's angle (23, in [22, 24]) ends the halving: no angle run twice, the interval
    # [22, 24] with the partial one named.
    partial = run_tool(base / "partial", stand_in, env={**os.environ, "PARTIAL_ANGLE": "23"})
    if partial.returncode != 0:
        failures.append("the sweep with a partial slide at 23 failed")
    else:
        angles = [(row["variant"], row["angle_deg"]) for row in read(base / "partial" / "tilt.csv")]
        if len(angles) != len(set(angles)) or len(angles) != 12:
            failures.append(f"with a partial slide at 23: runs {angles}")
        for row in read(base / "partial" / "onset.csv"):
            if (row["holds_up_to_deg"], row["flows_from_deg"], row["partial_deg"]) != ("22.0", "24.0", "23"):
                failures.append(f"with a partial slide at 23: onset {row}")

    # --start-from (a flowing bed) comes after every --set, so it overrides a bed given with --set.
    started = base / "started"
    command = RIFFLE_TOOLS + ["bed-tilt", "--riffle", str(stand_in), "--work", str(started), "--angles", "20",
                              "--set", 'solids.initial_state="settled.ckpt"', "--start-from", str(base / "flow.ckpt")]
    if subprocess.run(command, capture_output=True, text=True).returncode != 0:
        failures.append("the sweep with --start-from failed")
    else:
        logged = (started / "calls.txt").read_text().split()
        if logged[-1] != f'solids.initial_state="{(base / "flow.ckpt").resolve()}"':
            failures.append(f"--start-from is not the last initial_state: {logged}")

    failing = run_tool(base / "failing", stand_in, env={**os.environ, "STAND_IN_FAIL": "1"})
    if failing.returncode == 0:
        failures.append("a failing run did not fail the sweep")

    for failure in failures:
        print("FAIL:", failure)
    print("bed-tilt self-test:", "failed" if failures else "passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
