"""Reading riffle's CSV outputs (engine/output/): diagnostics.csv, probe_<kind>.csv, class_centroids.csv,
bed_profile.csv and the figure tables the tools write. numpy only.

    from riffle_tools import run_outputs
    rows = run_outputs.read_rows(run / "diagnostics.csv")            # [{column: text}, ...]
    columns = run_outputs.read_columns(run_outputs.probe_path(run, "bedload_flux"))  # {column: numpy array}
    run_outputs.class_columns(columns, "moving_fraction")           # [(0, "class_0_moving_fraction"), ...]

Empty fields (an undefined value) read as NaN.
"""
import csv
import math
import os
import re

import numpy as np

DIAGNOSTICS = "diagnostics.csv"
CLASS_CENTROIDS = "class_centroids.csv"
BED_PROFILE = "bed_profile.csv"


def probe_path(run_dir, kind):
    """RUN_DIR/probe_<kind>.csv (a probe's default file name)."""
    return os.path.join(run_dir, f"probe_{kind}.csv")


def number(text):
    """A CSV field as a float; an empty, missing or unreadable field is NaN."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_rows(path, comments=False):
    """The CSV at `path` as a list of {column: text}; comments=True skips lines that start with '#'."""
    with open(path, newline="") as handle:
        lines = (line for line in handle if not line.startswith("#")) if comments else handle
        return list(csv.DictReader(lines))


def read_columns(path):
    """The CSV at `path` as {column: numpy array}; empty fields are NaN."""
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    if not rows:
        raise ValueError(f"{path}: empty file")
    header, body = rows[0], rows[1:]
    columns = {}
    for k, name in enumerate(header):
        columns[name] = np.array([float(row[k]) if k < len(row) and row[k] != "" else np.nan for row in body])
    return columns


def class_columns(columns, suffix):
    """[(class number, column name)] of the columns class_<k>_<suffix>, by class."""
    found = []
    for name in columns:
        match = re.fullmatch(r"class_(\d+)_" + re.escape(suffix), name)
        if match:
            found.append((int(match.group(1)), name))
    return sorted(found)
