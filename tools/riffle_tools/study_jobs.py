"""A study's definition and its job records, shared by the runner (study) and the collector (study_collect).

A study is a small TOML file (tools/studies/seed_calibration.toml is the example; study's help has the format). Its
runs live under out/<name>/runs/<variant>/bed_<N>/, each with job.json: the command, segments, wall times and exit
codes of the run.
"""
import json
import os
import pathlib
import tomllib

from . import ROOT


class Study:
    def __init__(self, path, out=None):
        self.path = pathlib.Path(path)
        with open(self.path, "rb") as handle:
            spec = tomllib.load(handle)
        study = spec["study"]
        self.name = study["name"]
        self.scene = ROOT / study["scene"]
        self.bed_scene = ROOT / study["bed_scene"]
        self.bed_seed_key = study.get("bed_seed_key", "solids.layered_beds[0].seed")
        self.initial_state_key = study.get("initial_state_key", "solids.initial_state")
        self.periods = float(study["periods"])
        self.frequency = float(study["frequency"])
        self.workers = int(study.get("workers", 1))
        self.threads = int(study.get("threads", 2))
        self.common_set = list(study.get("set", []))
        self.binary_source = ROOT / study.get("binary", "build/riffle")
        self.variants = spec.get("variants", [])
        self.order = study.get("order", "variants")
        if self.order not in ("variants", "beds"):
            raise SystemExit(f"{self.path}: [study] order must be \"variants\" or \"beds\", not {self.order!r}")
        names = [v["name"] for v in self.variants]
        if len(set(names)) != len(names):
            raise SystemExit(f"{self.path}: variant names repeat")
        # Absolute: the runs name their bed by path, and riffle reads a relative path against the scene's folder.
        self.out = (pathlib.Path(out) if out else ROOT / "out" / self.name).resolve()
        self.binary = self.out / "riffle"
        # The runs read these copies; self.scene and self.bed_scene stay the study's names for them (job records).
        self.scene_copy = self.out / "scenes" / self.scene.name
        self.bed_scene_copy = self.out / "scenes" / ("bed_" + self.bed_scene.name)
        self.until = self.periods / self.frequency

    def bed_dir(self, seed):
        return self.out / "beds" / f"seed_{seed}"

    def run_dir(self, variant, seed):
        return self.out / "runs" / variant["name"] / f"bed_{seed}"

    def jobs(self):
        """(variant, seed) in the order the study file lists them; with order = "beds", by round: each variant's
        first bed in file order, then each one's second, ... (a screening pass over every variant comes first)."""
        listed = [(variant, seed) for variant in self.variants for seed in variant["beds"]]
        if self.order == "variants":
            return listed
        rounds = [variant["beds"].index(seed) for variant, seed in listed]
        return [job for _, job in sorted(zip(rounds, listed), key=lambda pair: pair[0])]

    def seeds(self):
        seen = []
        for _, seed in self.jobs():
            if seed not in seen:
                seen.append(seed)
        return seen


def read_job(directory):
    path = directory / "job.json"
    return json.loads(path.read_text()) if path.exists() else None


def write_job(directory, job):
    tmp = directory / "job.json.tmp"
    tmp.write_text(json.dumps(job, indent=1))
    os.replace(tmp, directory / "job.json")


def newest_checkpoint(directory):
    checkpoints = sorted((directory / "checkpoints").glob("step_*.ckpt"))
    return checkpoints[-1] if checkpoints else None


def job_overrides(study, variant, seed):
    bed = study.bed_dir(seed) / "checkpoints" / "final.ckpt"
    return [f"{study.initial_state_key}=\"{bed}\""] + study.common_set + list(variant.get("set", []))


def job_matches(study, variant, seed, job):
    """Whether a job on disk ran what the study file asks now: the same scene, overrides and end time. A variant
    edited in the study file no longer matches its old runs: `run` sets them aside and `collect` skips them."""
    return (job.get("set") == job_overrides(study, variant, seed) and abs(job.get("until", -1) - study.until) < 1e-9
            and job.get("scene", str(study.scene)) == str(study.scene))
