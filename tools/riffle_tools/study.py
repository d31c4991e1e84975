"""Queue a study of the seed experiment: runs of a base scene with scene-key overrides (riffle's --set), each on
one or more independently generated beds, run in the background with checkpoints, resumed after an interruption,
and collected into a table and plots at the end, so a study outlives the shell that started it.

A study is a small TOML file (tools/studies/seed_calibration.toml is the example):

    [study]
    name = "seed_study"                          # everything goes to out/<name>/ (or --out)
    scene = "scenes/oscillating_tank_quick.toml" # the run's scene, relative to the repository root
    bed_scene = "scenes/dry_bed_settle.toml"     # settles one bed per seed
    bed_seed_key = "solids.layered_beds[0].seed" # the bed generator's seed in bed_scene
    initial_state_key = "solids.initial_state"   # where the run's scene takes the settled bed
    periods = 30                                 # length of every run, in periods of the tank motion
    frequency = 1.7                              # [Hz] of the tank motion (to turn periods into --until)
    workers = 2                                  # runs at once
    order = "variants"                           # or "beds": every variant's first bed before any second one
    threads = 1                                  # riffle --threads per run
    set = ["output.vtk_interval=0.588235"]       # overrides every run takes (before its variant's own)

    [[variants]]
    name = "base"
    beds = [1, 2, 3, 4, 5]
    set = []

Layout: out/<name>/riffle (the binary the study runs, copied when it starts so a rebuild cannot mix two builds in
one study), out/<name>/scenes/ (the scene and bed scene the study runs, copied when it starts for the same reason: a
later change of a scene's defaults, such as a calibration, must not reach the runs not yet started), out/<name>/beds/seed_<N>/ (the settled beds), out/<name>/runs/<variant>/bed_<N>/ (each run, with
job.json: its command, segments, wall times and exit codes), out/<name>/study.log, out/<name>/collect/ (tables and
plots).

Commands (from the repository root):
    tools/riffle-tools study run STUDY.toml [--detach]   # run what is not done yet; --detach: in the background
    tools/riffle-tools study status STUDY.toml           # what is done, running, waiting
    tools/riffle-tools study collect STUDY.toml          # tables and plots of what is done (study_collect.py)

A run that was interrupted (a logout, SIGTERM, a crash of the machine) is resumed from its newest checkpoint by
the next `run`; a run that ended with a diagnosis (exit 3) or bad input (exit 2) is not retried. Only one runner
works on a study at a time (out/<name>/.study.lock).
"""
import argparse
import concurrent.futures
import datetime
import fcntl
import json
import pathlib
import shutil
import signal
import subprocess
import sys
import threading
import time
import tomllib

from . import ROOT, command
from .study_jobs import Study, job_matches, job_overrides, newest_checkpoint, read_job, write_job


def log(study, text):
    line = f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M:%S} {text}"
    print(line, flush=True)
    with open(study.out / "study.log", "a") as handle:
        handle.write(line + "\n")


STOPPING = threading.Event()
RUNNING = set()
RUNNING_LOCK = threading.Lock()


def run_riffle(study, directory, job, fresh_args):
    """Runs (or resumes) riffle for one job until it ends; records each segment in job.json. Returns the exit code."""
    directory.mkdir(parents=True, exist_ok=True)
    checkpoint = newest_checkpoint(directory)
    # Any checkpoint of this job resumes it, also one of a segment whose runner was killed before it could record it.
    if checkpoint is not None:
        args = [str(study.binary), "resume", str(checkpoint), "--until", f"{job['until']:.9g}",
                "--threads", str(study.threads), "--log-level", "warn"]
    else:
        for stale in ("checkpoints", "vtk"):
            shutil.rmtree(directory / stale, ignore_errors=True)
        args = [str(study.binary)] + fresh_args + ["--out", str(directory), "--threads", str(study.threads),
                                                    "--log-level", "warn"]
    start = time.time()
    job["segment_started"] = start  # for `status`; a runner killed with the machine leaves it, and resumes the job
    write_job(directory, job)
    with open(directory / "stdout.txt", "a") as output:
        output.write(f"# {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M:%S} {' '.join(args)}\n")
        output.flush()
        with RUNNING_LOCK:  # with the check: a stop() between the check and the start would miss this process
            if STOPPING.is_set():
                job.pop("segment_started", None)
                write_job(directory, job)
                return None
            process = subprocess.Popen(args, stdout=output, stderr=subprocess.STDOUT, cwd=ROOT)
            RUNNING.add(process)
        code = process.wait()
        with RUNNING_LOCK:
            RUNNING.discard(process)
    job.setdefault("segments", []).append({"command": args, "wall_s": round(time.time() - start, 1),
                                           "exit_code": code, "started": start})
    job.pop("segment_started", None)
    job["wall_s"] = round(sum(s["wall_s"] for s in job["segments"]), 1)
    job["exit_code"] = code
    job["done"] = code == 0
    write_job(directory, job)
    return code


def settle_bed(study, seed):
    """Settles the bed of one seed (the bed scene with its seed key set), once; returns riffle's exit code."""
    directory = study.bed_dir(seed)
    if (directory / "checkpoints" / "final.ckpt").exists():
        return 0
    job = read_job(directory) or {"kind": "bed", "seed": seed, "set": [f"{study.bed_seed_key}={seed}"],
                                  "until": bed_end_time(study)}
    if job.get("exit_code") in (2, 3):
        return job["exit_code"]
    if STOPPING.is_set():
        return None
    log(study, f"bed {seed}: settling")
    fresh = ["run", str(study.bed_scene_copy)] + [a for s in job["set"] for a in ("--set", s)]
    code = run_riffle(study, directory, job, fresh)
    if code is not None:
        log(study, f"bed {seed}: exit {code}")
    return code


def pin_scenes(study):
    """Copies the scene and the bed scene into the study the first time it runs; later runs use those copies. A
    scene changed in the repository since then is named in the log: the study goes on with its copy."""
    for source, copy in ((study.scene, study.scene_copy), (study.bed_scene, study.bed_scene_copy)):
        if not copy.exists():
            copy.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, copy)
        elif source.read_bytes() != copy.read_bytes():
            log(study, f"{source} has changed since the study copied it; the study runs its copy {copy}")


def bed_end_time(study):
    with open(study.bed_scene_copy, "rb") as handle:
        return float(tomllib.load(handle)["run"]["end_time"])


def run_job(study, variant, seed):
    directory = study.run_dir(variant, seed)
    job = read_job(directory)
    if job and not job_matches(study, variant, seed, job):
        aside = directory.with_name(f"{directory.name}.replaced-{int(time.time())}")
        directory.rename(aside)
        log(study, f"{variant['name']} bed {seed}: the study file changed this run; the old one is kept in {aside}")
        job = None
    if job and (job.get("done") or job.get("exit_code") in (2, 3)):
        return job.get("exit_code", 0)
    if STOPPING.is_set():
        return None
    # Beds are settled once each before any run (command_run); one that failed is retried by the next `run`, never
    # here, where two jobs on the same bed would settle it twice at once.
    if not (study.bed_dir(seed) / "checkpoints" / "final.ckpt").exists():
        log(study, f"{variant['name']} bed {seed}: its bed is not settled; skipped")
        return None
    overrides = job_overrides(study, variant, seed)
    job = job or {"kind": "run", "variant": variant["name"], "seed": seed, "scene": str(study.scene),
                  "set": overrides, "until": study.until, "threads": study.threads, "periods": study.periods}
    fresh = ["run", str(study.scene_copy), "--until", f"{study.until:.9g}"] + [a for s in overrides
                                                                               for a in ("--set", s)]
    log(study, f"{variant['name']} bed {seed}: {'resuming' if job.get('segments') else 'starting'}")
    code = run_riffle(study, directory, job, fresh)
    if code is not None:
        log(study, f"{variant['name']} bed {seed}: exit {code} after {job['wall_s']} s in all")
    return code


def stop(signum, frame):
    STOPPING.set()
    with RUNNING_LOCK:
        for process in RUNNING:
            process.send_signal(signal.SIGTERM)  # riffle checkpoints on SIGTERM (exit 143): resumable


def command_run(study, detach):
    study.out.mkdir(parents=True, exist_ok=True)
    if detach:
        log_path = study.out / "study.log"
        args = command("study", "run", study.path.resolve(), "--out", study.out)
        # The runner writes study.log itself; its stdout and stderr (tracebacks) go to runner.out.
        with open(study.out / "runner.out", "a") as handle:
            process = subprocess.Popen(args, stdout=handle, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                       start_new_session=True, cwd=ROOT)
        print(f"study {study.name}: running in the background (pid {process.pid}); log {log_path}")
        return 0
    lock = open(study.out / ".study.lock", "w")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        raise SystemExit(f"study {study.name}: another runner holds {study.out / '.study.lock'}")
    if not study.binary.exists():
        shutil.copy2(study.binary_source, study.binary)
        version = subprocess.run([str(study.binary), "--version"], capture_output=True, text=True).stdout.strip()
        # --dirty: a binary built from a tree with uncommitted changes says so.
        commit = subprocess.run(["git", "describe", "--always", "--dirty", "--abbrev=12"], capture_output=True,
                                text=True, cwd=ROOT).stdout.strip()
        (study.out / "binary.json").write_text(json.dumps({"source": str(study.binary_source), "version": version,
                                                           "commit": commit, "copied": time.time()}, indent=1))
    pin_scenes(study)
    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    log(study, f"runner started: {len(study.jobs())} jobs, {study.workers} at a time, {study.threads} thread(s) each")
    # Beds first, each once (two jobs on one bed must not settle it twice), then the runs.
    with concurrent.futures.ThreadPoolExecutor(study.workers) as pool:
        list(pool.map(lambda seed: settle_bed(study, seed), study.seeds()))
        futures = [pool.submit(run_job, study, variant, seed) for variant, seed in study.jobs()]
        codes = [f.result() for f in futures]
    log(study, "runner stopped" if STOPPING.is_set() else
        f"runner finished: {sum(c == 0 for c in codes)} of {len(codes)} runs done")
    return 0


def command_status(study):
    for seed in study.seeds():
        done = (study.bed_dir(seed) / "checkpoints" / "final.ckpt").exists()
        print(f"bed {seed}: {'settled' if done else 'not settled'}")
    for variant, seed in study.jobs():
        directory = study.run_dir(variant, seed)
        job = read_job(directory)
        progress = ""
        diagnostics = directory / "diagnostics.csv"
        if diagnostics.exists():
            with open(diagnostics, "rb") as handle:
                handle.seek(max(0, diagnostics.stat().st_size - 4096))
                last = handle.read().decode(errors="replace").strip().splitlines()[-1]
            try:
                progress = f"t/T = {float(last.split(',')[1]) * study.frequency:.2f} of {study.periods:g}"
            except (ValueError, IndexError):
                pass
        if job and job.get("done"):
            state = "done"
        elif job and job.get("exit_code") in (2, 3):
            state = f"failed (exit {job['exit_code']})"
        elif job and "segment_started" in job:
            state = f"running since {time.strftime('%H:%M', time.gmtime(job['segment_started']))} UTC (or killed then)"
        else:
            state = "interrupted" if job else "waiting"

        wall = f", {job['wall_s']} s" if job and "wall_s" in job else ""
        print(f"{variant['name']:28s} bed {seed}: {state}{wall} {progress}")
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("command", choices=["run", "status", "collect"])
    parser.add_argument("study", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, help="the study's folder (default out/<study.name>)")
    parser.add_argument("--detach", action="store_true", help="run: in the background, surviving this shell")
    args = parser.parse_args(argv)
    study = Study(args.study, args.out)
    if args.command == "run":
        return command_run(study, args.detach)
    if args.command == "status":
        return command_status(study)
    from . import study_collect
    return study_collect.collect(study)


if __name__ == "__main__":
    sys.exit(main())
