#!/usr/bin/python3
"""Self-test of tools/riffle-tools study and study-collect on a tiny study that really runs riffle: two variants on
two beds settled with different generator seeds, one run interrupted by SIGTERM and resumed by the next `run`.

Checks: each bed is settled once, with its own seed (different grain positions); a run's overrides reach riffle
(the variant's restitution is in its checkpoint's scene); the interrupted run resumes from its checkpoint (two
segments, the second a `riffle resume`) and ends with the same class centroids as an uninterrupted run of the same
job; a finished study is not rerun; collect writes the ensemble and sensitivity tables with the base variant's S
equal to the segregation index computed here from class_centroids.csv; merge joins two studies' runs.csv into one
sensitivity table (each variant's beds from both, the counts rule from the base's spread).

Usage: /usr/bin/python3 tests/tools/test_study.py RIFFLE_BINARY [WORK_DIR]   (exit 0 = pass)
"""
import csv
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
RIFFLE_TOOLS = [sys.executable, str(ROOT / "tools" / "riffle-tools")]  # the tools' launcher

# The tank, grain and contact both scenes share: the bed is settled in the tank it is shaken in.
TANK = """
[materials.grain]
density = 1318.0
young_modulus = 1.0e6
poisson_ratio = 0.3

[contact]
restitution = 0.5
friction = 0.4
max_impact_speed = 1.0

[tank]
size = [0.05, 0.03, 0.08]
open_faces = ["z_max"]
wall_material = "grain"
"""

BED = """
[run]
name = "tiny_bed"
end_time = 0.06
dt = 1.0e-3
""" + TANK + """
[solids]
[[solids.layered_beds]]
layers = 1
layer_thickness = 0.012
loose_factor = 1.5
seed = 1

[[solids.layered_beds.classes]]
diameter = 0.010
count = 3
material = "grain"
size_class = 1
arrangement = "regular"

[[solids.layered_beds.classes]]
diameter = 0.004
count = 60
material = "grain"
size_class = 0
arrangement = "random"
"""

RUN = """
[run]
name = "tiny_run"
end_time = 1.0
dt = 1.0e-3
""" + TANK + """
[tank.motion]
kind = "sinusoidal"
direction = [1.0, 0.0, 0.0]
amplitude = 0.004
frequency = 5.0
ramp_time = 0.0

[solids]
initial_state = "set by the study"

[output]
vtk_interval = 0.1
checkpoint_interval = 0.02
bed_profile_interval = 0.01
"""

STUDY_FILE = """
[study]
name = "tiny"
scene = "{run}"
bed_scene = "{bed}"
periods = 2
frequency = 5.0
workers = 1
threads = 1
binary = "{binary}"
set = []

[[variants]]
name = "base"
beds = [1, 2]

[[variants]]
name = "bouncy"
beds = [1]
set = ["contact.restitution=0.9"]
"""

failures = []


def check(condition, text):
    print(("ok - " if condition else "FAIL - ") + text)
    if not condition:
        failures.append(text)


def rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def check_job_order(work):
    """order = "beds" runs every variant's first bed before any second one; the default keeps the file's order."""
    sys.path.insert(0, str(ROOT / "tools"))
    from riffle_tools import study
    head = '[study]\nname = "order"\nscene = "a.toml"\nbed_scene = "b.toml"\nperiods = 1\nfrequency = 1.0\n'
    body = ('[[variants]]\nname = "p"\nbeds = [1, 2]\n[[variants]]\nname = "q"\nbeds = [3]\n'
            '[[variants]]\nname = "r"\nbeds = [1, 2]\n')
    for order, expected in (("", ["p1", "p2", "q3", "r1", "r2"]), ('order = "beds"\n', ["p1", "q3", "r1", "p2", "r2"])):
        (work / "order.toml").write_text(head + order + body)
        got = [f"{variant['name']}{seed}" for variant, seed in study.Study(work / "order.toml", work).jobs()]
        check(got == expected, f"job order {order.strip() or 'default'}: {got}, expected {expected}")


def main():
    binary = pathlib.Path(sys.argv[1]).resolve()
    work = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else "/tmp/test_study").resolve()
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    check_job_order(work)
    (work / "bed.toml").write_text(BED)
    (work / "run.toml").write_text(RUN)
    # The study file names scenes relative to the repository root; absolute paths work as well.
    (work / "study.toml").write_text(STUDY_FILE.format(run=work / "run.toml", bed=work / "bed.toml", binary=binary))
    out = work / "out"
    command = [*RIFFLE_TOOLS, "study", "run", str(work / "study.toml"), "--out", str(out)]

    # 1. Start the runner and stop it (SIGTERM) once the first run has written a checkpoint past its start.
    runner = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, cwd=ROOT)
    first = out / "runs" / "base" / "bed_1"
    deadline = time.time() + 120
    while time.time() < deadline and runner.poll() is None:
        if len(list((first / "checkpoints").glob("step_*.ckpt"))) >= 2:
            break
        time.sleep(0.05)
    runner.send_signal(signal.SIGTERM)
    runner.wait(timeout=60)
    job = json.loads((first / "job.json").read_text())
    check(job["segments"][0]["exit_code"] == 143 and not job["done"],
          f"SIGTERM stops the running job with riffle's exit 143, not done (got {job['segments'][0]['exit_code']})")

    # 2. The next run resumes it and finishes the study, from the scenes the study copied when it first ran: the
    #    scene is changed in between (a key riffle refuses), and the jobs that start now must not see the change.
    check((out / "scenes" / "run.toml").read_text() == RUN and (out / "scenes" / "bed_bed.toml").read_text() == BED,
          "the study copied its scene and bed scene when it first ran")
    (work / "run.toml").write_text(RUN + "\n[not_a_table]\nkey = 1\n")
    finished = subprocess.run(command, capture_output=True, text=True, cwd=ROOT, timeout=300)
    check(finished.returncode == 0, f"the second runner finishes (exit {finished.returncode})")
    check("has changed since the study copied it" in (out / "study.log").read_text(),
          "the log names the scene changed since the study copied it")
    (work / "run.toml").write_text(RUN)
    job = json.loads((first / "job.json").read_text())
    check(job["done"] and len(job["segments"]) == 2 and job["segments"][1]["command"][1] == "resume",
          "the interrupted job resumed from its checkpoint (two segments, the second `riffle resume`)")
    for variant, seed in (("base", 2), ("bouncy", 1)):
        other = json.loads((out / "runs" / variant / f"bed_{seed}" / "job.json").read_text())
        check(other["done"] and len(other["segments"]) == 1, f"{variant} bed {seed} ran once to the end")

    # 3. The beds: settled once each, with different seeds, so different grains.
    start_1 = rows(out / "runs" / "base" / "bed_1" / "class_centroids.csv")[0]
    start_2 = rows(out / "runs" / "base" / "bed_2" / "class_centroids.csv")[0]
    check(start_1["class_0_centroid_m"] != start_2["class_0_centroid_m"],
          "the runs on beds 1 and 2 start from different beds (the seed override reached the bed generator)")
    check(b"contact.restitution=0.9" in (out / "runs" / "bouncy" / "bed_1" / "checkpoints" / "final.ckpt").read_bytes(),
          "the variant's override is in its checkpoint's scene")

    # 4. The resumed run equals an uninterrupted run of the same job.
    straight = work / "straight"
    args = job["segments"][0]["command"]
    args = args[:args.index("--out")] + ["--out", str(straight), "--threads", "1", "--log-level", "warn"]
    subprocess.run(args, check=True, cwd=ROOT, capture_output=True)
    check((straight / "class_centroids.csv").read_text() == (first / "class_centroids.csv").read_text(),
          "the interrupted and resumed run's class_centroids.csv equals the straight run's, byte for byte")

    # 5. A finished study is not rerun.
    again = subprocess.run(command, capture_output=True, text=True, cwd=ROOT, timeout=60)
    job_again = json.loads((first / "job.json").read_text())
    check(again.returncode == 0 and len(job_again["segments"]) == 2, "a finished study is not rerun")

    # 6. An edited variant: its old run is set aside and run again. Then the state a runner killed outright leaves
    #    (SIGKILL with its riffle, as when the machine goes away: checkpoints on disk, the segment never recorded) is
    #    made from that run, and the next `run` must resume the job from its newest checkpoint, not from t = 0.
    (work / "study.toml").write_text((work / "study.toml").read_text().replace("contact.restitution=0.9",
                                                                                "contact.restitution=0.8"))
    subprocess.run(command, capture_output=True, text=True, cwd=ROOT, timeout=300)
    bouncy = out / "runs" / "bouncy" / "bed_1"
    job = json.loads((bouncy / "job.json").read_text())
    check(len(list(out.glob("runs/bouncy/bed_1.replaced-*"))) == 1 and job["done"] and
          "contact.restitution=0.8" in job["set"], "the edited variant's old run is set aside and the variant rerun")
    checkpoints = sorted((bouncy / "checkpoints").glob("step_*.ckpt"))
    for late in checkpoints[len(checkpoints) // 2:] + [bouncy / "checkpoints" / "final.ckpt"]:
        late.unlink()
    for key in ("segments", "done", "exit_code", "wall_s"):
        job.pop(key, None)
    job["segment_started"] = time.time()
    (bouncy / "job.json").write_text(json.dumps(job))
    subprocess.run(command, capture_output=True, text=True, cwd=ROOT, timeout=300)
    job = json.loads((bouncy / "job.json").read_text())
    check(job["done"] and job["segments"][0]["command"][1] == "resume" and
          job["segments"][0]["command"][2] == str(checkpoints[len(checkpoints) // 2 - 1]),
          "a job whose runner was killed outright resumes from its newest checkpoint (not from t = 0)")

    # 7. collect: the tables, and S as defined in tools/riffle-tools seed-figures.
    collected = subprocess.run([*RIFFLE_TOOLS, "study", "collect", str(work / "study.toml"), "--out", str(out)],
                               capture_output=True, text=True, cwd=ROOT, timeout=120)
    check(collected.returncode == 0, f"collect exits 0 ({collected.stdout[-300:]} {collected.stderr[-300:]})")
    for name in ("runs.csv", "ensemble.csv", "ensemble.png", "sensitivity.csv", "sensitivity.md"):
        check((out / "collect" / name).exists(), f"collect writes {name}")
    ensemble = rows(out / "collect" / "ensemble.csv")
    centroids = [rows(out / "runs" / "base" / f"bed_{s}" / "class_centroids.csv") for s in (1, 2)]
    # S by hand at the last common sample: gap between the largest and smallest class centroids against the start's,
    # over the gap of a bed fully sorted in layers (volumes: 3 grains of 10 mm, 60 of 4 mm; 2 z_mean the height).
    volumes = [60 * 0.002 ** 3, 3 * 0.005 ** 3]
    expected = []
    for table in centroids:
        z0 = [float(table[0]["class_0_centroid_m"]), float(table[0]["class_1_centroid_m"])]
        n = len(ensemble) - 1
        z = [float(table[n]["class_0_centroid_m"]), float(table[n]["class_1_centroid_m"])]
        mean_height = (volumes[0] * z[0] + volumes[1] * z[1]) / sum(volumes)
        full_gap = 2 * mean_height * 0.5
        expected.append(((z[1] - z[0]) - (z0[1] - z0[0])) / (full_gap - (z0[1] - z0[0])))
    got = float(ensemble[-1]["S_mean"])
    check(abs(got - sum(expected) / 2) < 1e-5, f"the ensemble's mean S at the end ({got:.6f}) is the beds' mean "
          f"segregation index computed here ({sum(expected) / 2:.6f})")

    # 8. measure: any run directory at any stage. S at t/T = 2 is the mean over the period that ends there (samples
    # in (1, 2]) of the segregation index computed here.
    def s_by_hand(table, row):
        z0 = [float(table[0]["class_0_centroid_m"]), float(table[0]["class_1_centroid_m"])]
        z = [float(row["class_0_centroid_m"]), float(row["class_1_centroid_m"])]
        full_gap = 2 * (volumes[0] * z[0] + volumes[1] * z[1]) / sum(volumes) * 0.5
        return ((z[1] - z[0]) - (z0[1] - z0[0])) / (full_gap - (z0[1] - z0[0]))

    period_two = [s_by_hand(centroids[0], r) for r in centroids[0] if 1.0 < float(r["t_over_T"]) <= 2.0 + 1e-6]
    measured = subprocess.run([*RIFFLE_TOOLS, "study-collect", "measure",
                               str(out / "runs" / "base" / "bed_1"), "--stages", "2", "--drift-windows", "0-2",
                               "--rise-windows", "1-2"], capture_output=True, text=True, cwd=ROOT, timeout=120)
    values = dict(line.split(",", 1) for line in measured.stdout.split())
    check(measured.returncode == 0 and "z1_rise_1-2_mm_per_T" in values and
          "endwall_coarse_dz_0-2_mm_per_T" in values, f"measure exits 0 with its rows ({measured.stderr[-300:]})")
    check(period_two and abs(float(values.get("S_2", "nan")) - sum(period_two) / len(period_two)) < 1e-5,
          f"measure's S at t/T = 2 ({values.get('S_2')}) is the mean over the second period of the segregation "
          f"index computed here ({sum(period_two) / max(1, len(period_two)):.6f})")

    # 9. merge: the sensitivity table over the runs.csv of two studies (a variant's beds run by each), the first
    # file's row kept on a repeat, the counts rule |m_v - m_ref| > 2 s sqrt(1/n_v + 1/n_ref) with s from the base.
    first, second = work / "first_runs.csv", work / "second_runs.csv"
    first.write_text("variant,bed,threads,wall_s,S_10\nbase,1,1,10,0.30\nbase,2,1,10,0.32\nbase,3,1,10,0.34\n"
                     "moved,1,1,10,0.40\nsame,1,1,10,0.33\n")
    second.write_text("variant,bed,threads,wall_s,S_10\nmoved,2,1,10,0.42\nmoved,1,1,10,9.99\nsame,2,1,10,0.31\n")
    merged = subprocess.run([*RIFFLE_TOOLS, "study-collect", "merge", str(first),
                             str(second), "--base", "base", "--out", str(work / "merged")],
                            capture_output=True, text=True, cwd=ROOT, timeout=120)
    check(merged.returncode == 0, f"merge exits 0 ({merged.stderr[-300:]})")
    table = {r["variant"]: r for r in rows(work / "merged" / "sensitivity.csv")} if merged.returncode == 0 else {}
    # base: mean 0.32, s = 0.02 over 3 beds; moved: 0.41 over beds 1-2 (bed 1 from the first file), 0.09 > 0.0365.
    check(abs(float(table.get("moved", {}).get("S_10", "nan")) - 0.41) < 1e-9 and
          table["moved"]["beds"] == "2" and table["moved"]["S_10_counts"] == "yes",
          f"merge: moved's S at 10 is the mean of its two beds, the first file's bed 1 kept, and counts "
          f"({table.get('moved', {}).get('S_10')}, {table.get('moved', {}).get('S_10_counts')})")
    check(abs(float(table.get("same", {}).get("S_10", "nan")) - 0.32) < 1e-9 and table["same"]["S_10_counts"] == "no",
          f"merge: same's S at 10 (0.32) does not count ({table.get('same', {}).get('S_10')}, "
          f"{table.get('same', {}).get('S_10_counts')})")
    unknown = subprocess.run([*RIFFLE_TOOLS, "study-collect", "merge", str(first),
                              "--base", "nobody", "--out", str(work / "merged")],
                             capture_output=True, text=True, cwd=ROOT, timeout=120)
    check(unknown.returncode != 0 and "nobody" in unknown.stderr, "merge names a base it has no runs of")
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
