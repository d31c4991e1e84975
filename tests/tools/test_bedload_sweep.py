#!/usr/bin/python3
"""Self-test of tools/riffle-tools bedload-sweep with a stand-in for riffle: a script that takes the sweep's command
lines, writes the settle's checkpoint and, for a channel run, a bedload_transport probe whose q* follows
q*^(2/3) = 2 (Theta - 0.045) (so the zero-flux extrapolation must give Theta_c = 0.045 exactly), after sleeping
2 s. Checks: every Shields number of every diameter is run once, with its own --set; the threshold comes out at
0.045 (+-1e-9) for each diameter; the runs of a diameter go side by side (--jobs 4: four 2 s runs in well under 8 s);
a second call runs nothing (each probe covers its end time) and writes the same tables; a failing run fails the
sweep.

Usage: /usr/bin/python3 tests/tools/test_bedload_sweep.py [WORK_DIR]   (exit 0 = pass)
"""
import csv
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
RIFFLE_TOOLS = [sys.executable, str(ROOT / "tools" / "riffle-tools")]

STAND_IN = r'''#!/usr/bin/python3
import os, sys, time
args = sys.argv[1:]
out = args[args.index("--out") + 1]
sets = dict(item.split("=", 1) for k, item in enumerate(args) if k > 0 and args[k - 1] == "--set")
os.makedirs(os.path.join(out, "checkpoints"), exist_ok=True)
with open(os.path.join(os.path.dirname(out) or ".", "calls.txt"), "a") as log:
    log.write(" ".join(args) + "\n")
if "bedload_channel_settle" in args[1]:
    open(os.path.join(out, "checkpoints", "final.ckpt"), "w").write("settled")
    sys.exit(0)
theta = float(sets["mean_flow.shields_number"])
if theta == 0.5 and os.environ.get("STAND_IN_FAIL"):
    print("stand-in: failing as asked", file=sys.stderr)
    sys.exit(3)
time.sleep(2.0)
q = max(0.0, 2.0 * (theta - 0.045)) ** 1.5
with open(os.path.join(out, "probe_bedload_transport.csv"), "w") as probe:
    probe.write("time_s,step,shields,u_star_m_s,q_star,moving_fraction,moving_ux_over_u_star,moving_height_over_d,"
                "moving_above_bed_ux_over_u_star\n")
    for k in range(11):
        probe.write(f"{0.3 * k},{k},{theta},0.02,{q},0.1,1.5,0.3,2.0\n")
print(f"stand-in: theta {theta} q* {q}")
'''

failures = []


def check(ok, what):
    print(("ok - " if ok else "not ok - ") + what)
    if not ok:
        failures.append(what)


def sweep(work, *extra, env=None):
    command = RIFFLE_TOOLS + ["bedload-sweep", "--riffle", str(work / "riffle"), "--diameters", "0.002", "0.001",
                              "--shields", "0.1", "0.2", "0.3", "0.4", "--out", str(work / "sweep"), *extra]
    started = time.monotonic()
    result = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, env=env)
    return result, time.monotonic() - started


def main():
    work = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="bedload_sweep_"))
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    (work / "riffle").write_text(STAND_IN)
    os.chmod(work / "riffle", 0o755)

    result, seconds = sweep(work, "--jobs", "4")
    check(result.returncode == 0, "the sweep runs (" + result.stderr.strip()[-300:] + ")")
    calls = []
    for diameter in ("d0.002", "d0.001"):
        path = work / "sweep" / diameter / "calls.txt"
        calls += path.read_text().splitlines() if path.exists() else []
    channel = [line for line in calls if "bedload_channel.toml" in line]
    check(len(channel) == 8 and len([c for c in calls if "settle" in c.split()[1]]) == 2,
          f"each diameter settled once and its four Shields numbers run once ({len(channel)} channel runs)")
    check(all(f"mean_flow.shields_number={t}" in " ".join(channel) for t in ("0.1", "0.2", "0.3", "0.4")),
          "every run carries its own Shields number")
    # Side by side: two diameters of four 2 s runs take about 4 s and the tool's start; one after another 16 s.
    check(seconds < 10.0, f"four 2 s runs of a diameter side by side: two diameters in {seconds:.1f} s")
    with open(work / "sweep" / "threshold.csv") as handle:
        thresholds = list(csv.DictReader(handle))
    check(len(thresholds) == 2 and all(abs(float(row["theta_c"]) - 0.045) < 1e-9 for row in thresholds),
          "the zero-flux extrapolation gives the stand-in's 0.045 for both diameters: "
          + ", ".join(row["theta_c"] for row in thresholds))
    first_tables = (work / "sweep" / "sweep.csv").read_text()

    result, seconds = sweep(work, "--jobs", "4")
    again = (work / "sweep" / "d0.002" / "calls.txt").read_text().splitlines()
    check(result.returncode == 0 and len([c for c in again if "bedload_channel.toml" in c]) == 4,
          "a second call runs nothing new")
    check((work / "sweep" / "sweep.csv").read_text() == first_tables, "... and writes the same table")

    env = dict(os.environ, STAND_IN_FAIL="1")
    command_extra = ["--jobs", "2"]
    result = subprocess.run(RIFFLE_TOOLS + ["bedload-sweep", "--riffle", str(work / "riffle"), "--diameters", "0.002",
                                            "--shields", "0.5", "0.6", "--out", str(work / "failing"), *command_extra],
                            cwd=ROOT, capture_output=True, text=True, env=env)
    check(result.returncode != 0 and "failing as asked" in result.stdout + result.stderr,
          "a failing run fails the sweep, its output shown")
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
