"""Tables and plots of a study run by tools/riffle-tools study (`tools/riffle-tools study collect STUDY.toml` calls
collect()).

Per run (out/<study>/runs/<variant>/bed_<N>/):
- the class centroids and the segregation index S of tools/riffle-tools seed-figures (0 at the start, 1 sorted in
  layers; class volumes from the first grain frame) at t/T = 10, 20, 30, each the mean over the period that ends there
  (class_centroids.csv, ten samples a period);
- the end-wall circulation: from the drift figure of tools/riffle-tools seed-figures over t/T = 10-20 and 20-30, the
  mean vertical displacement per period of the coarse grains (medium and large) that start in the two end-wall bands
  (the outer tenths of the tank's length, 24 mm), beside the same in the middle six tenths. Convection rolls that
  carry coarse grains down the end walls make the first negative while the sorting lifts the second;
- the wall time (all of the run's segments) and the threads it ran on;
- the seed's picture (bed_state): how far the large grains that start in the bottom corners move, the small grains'
  share of the bottom 15 mm at the start and end, and each centroid's rise per period over the last 10 periods.

The first variant is the base: its beds make the ensemble (mean, standard deviation, range over the beds, against
t/T). Another variant's effect on a quantity counts ("yes" in the table) only where the difference of the means exceeds
twice its standard error estimated from the base ensemble's spread: |mean_v - mean_base| > 2 s sqrt(1/n_v + 1/n_base),
s the base's standard deviation over its beds (the variants' own spread from two beds is too uncertain to use).

Writes out/<study>/collect/: runs.csv (one row per run), ensemble.csv and ensemble.png (the base's bands),
sensitivity.csv and sensitivity.md (one row per variant), sensitivity.png (S against t/T per variant over the band).
"""
import csv
import math
import pathlib
import subprocess
import sys

import numpy as np

from . import command, seed_figures, vtp  # seed_figures sets matplotlib up, headless
from . import study_jobs  # the runner's job records
from .run_outputs import read_rows

plt = seed_figures.plt
STAGES = (10, 20, 30)
DRIFT_WINDOWS = ("10-20", "20-30")
END_BAND_COLUMNS = (0, seed_figures.DRIFT_COLUMNS - 1)
MIDDLE_COLUMNS = tuple(range(2, seed_figures.DRIFT_COLUMNS - 2))


def centroid_series(run_dir):
    """t/T and the centroid heights [m] per class (classes in size order), from class_centroids.csv."""
    rows = read_rows(run_dir / "class_centroids.csv")
    classes = sorted(int(key.split("_")[1]) for key in rows[0] if key.startswith("class_") and
                     key.endswith("_centroid_m"))
    t = np.array([float(r["t_over_T"]) for r in rows])
    z = np.array([[float(r[f"class_{k}_centroid_m"]) for k in classes] for r in rows])
    return t, z, classes


def class_volumes(run_dir, classes):
    """Total grain volume per class (any common unit), from the run's first grain frame."""
    frames = vtp.read_pvd(run_dir / "solids.pvd")
    grains = vtp.read_vtp(frames[0][1], ("radius", "size_class"))
    return [float(np.sum(grains["radius"][grains["size_class"] == k] ** 3)) for k in classes]


def segregation_series(t, z, volumes):
    return np.array([seed_figures.segregation_index(volumes, z[0], row) for row in z])


def at(t, values, stage):
    """The mean over the period that ends at t/T = stage (the samples in (stage - 1, stage]), so that the in-period
    swing of the centroids (about 1 mm, 0.01 in S) does not depend on the phase of one sample; nan if the run did not
    get within 0.2 periods of it."""
    if t[-1] < stage - 0.2:
        return math.nan
    mask = (t > stage - 1.0) & (t <= stage + 1e-6)
    return float(np.mean(values[mask])) if mask.any() else math.nan


def circulation(run_dir, refresh, windows=DRIFT_WINDOWS, figures=None):
    """{window: (end-band coarse dz, middle coarse dz)} [m per period] from the drift figure's table in `figures`
    (default RUN_DIR/figures), drawn when missing or asked to (`refresh`); windows the run has not reached give none."""
    figures = figures or run_dir / "figures"
    table = figures / "drift.csv"
    if refresh or not table.exists():
        subprocess.run(command("seed-figures", run_dir, "--figures", "drift", "--out", figures, "--drift-windows",
                               *windows), stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT, check=False)
    if not table.exists():
        return {}
    result = {}
    rows = read_rows(table)
    for window in windows:
        picked = [r for r in rows if r["window"] == window and r["group"] in ("1", "2")]
        if not picked:
            continue
        periods = float(picked[0]["t_over_T_end"]) - float(picked[0]["t_over_T_start"])

        def mean_dz(columns):
            cells = [r for r in picked if int(r["column"]) in columns]
            count = sum(int(r["grains"]) for r in cells)
            return sum(int(r["grains"]) * float(r["mean_dz_m"]) for r in cells) / count / periods if count else math.nan

        result[window] = (mean_dz(END_BAND_COLUMNS), mean_dz(MIDDLE_COLUMNS))
    return result


def bed_state(run_dir, period=None):
    """What the seed's picture asks of the bed, from the run's first grain frame and its last (or the one nearest
    t/T = `period`), in the tank frame:
    - the largest displacement [mm] of the large grains that start in a bottom corner (centre within 1.5 large
      diameters of the floor, of an end wall and of a side wall: the seed's two large corner grains stay put);
    - the small grains' share of the grain volume whose centres lie in the bottom 15 mm sub-layer, at the start and
      at the end (the seed's small grains gather at the floor: the share rises towards 1)."""
    run = seed_figures.Run(run_dir, verbose=False)
    times = run.solid_times()
    if len(times) < 2:
        return {}
    end = len(times) - 1 if period is None else run.nearest_frame(np.asarray(times), period)
    if end is None:  # beyond the run
        return {}
    first = run.solids(0, ("id", "radius", "size_class"))
    last = run.solids(end, ("id", "radius", "size_class"))
    large = int(first["size_class"].max())
    diameter = 2.0 * float(first["radius"][first["size_class"] == large].max())
    p0 = first["tank_frame_points"]
    size = run.size
    corner = ((first["size_class"] == large) & (p0[:, 2] < 1.5 * diameter)
              & ((p0[:, 0] < 1.5 * diameter) | (p0[:, 0] > size[0] - 1.5 * diameter))
              & ((p0[:, 1] < 1.5 * diameter) | (p0[:, 1] > size[1] - 1.5 * diameter)))
    result = {"corner_large_grains": int(corner.sum())}
    if corner.any():
        end_position = {int(i): p for i, p in zip(last["id"], last["tank_frame_points"])}
        moved = [np.linalg.norm(end_position[int(i)] - p) for i, p in zip(first["id"][corner], p0[corner])]
        result["corner_large_max_move_mm"] = 1e3 * float(max(moved))
        result["corner_large_still"] = int(sum(m < 0.005 for m in moved))  # moved less than a small grain's size

    def small_share(frame):
        volume = frame["radius"] ** 3
        bottom = frame["tank_frame_points"][:, 2] < seed_figures.DRIFT_LAYER
        small = frame["size_class"] == int(frame["size_class"].min())
        return float(np.sum(volume[bottom & small]) / np.sum(volume[bottom]))

    result["small_share_bottom_start"] = small_share(first)
    result["small_share_bottom_end"] = small_share(last)
    return result


def rise_rate(t, z, window=10.0, start=None, end=None):
    """[mm per period] least-squares slope of a centroid over the run's last `window` periods, or over t/T in
    [start, end] when given (nan where the run does not reach `end`)."""
    if start is None:
        mask = t >= t[-1] - window
    else:
        if t[-1] < end - 0.2:
            return math.nan
        mask = (t >= start) & (t <= end)
    return 1e3 * float(np.polyfit(t[mask], z[mask], 1)[0]) if mask.sum() > 2 else math.nan


def run_summary(study, variant, seed, refresh):
    run_dir = study.run_dir(variant, seed)
    job = study_jobs.read_job(run_dir)
    if not job or not job.get("done"):
        return None
    if not study_jobs.job_matches(study, variant, seed, job):
        print(f"  {variant['name']} bed {seed}: ran other overrides than the study file now lists; skipped")
        return None
    row = {"variant": variant["name"], "bed": seed, "threads": job.get("threads"), "wall_s": job.get("wall_s"),
           "periods": job.get("periods")}
    measures, data = measure(run_dir, STAGES, DRIFT_WINDOWS, refresh=refresh)
    row.update(measures)
    return row, data


def measure(run_dir, stages, drift_windows, rise_windows=(), bed_periods=(), refresh=False):
    """The study's measures of one run directory at any stages and windows: S and the class centroids at each stage
    (means over the period that ends there), each centroid's rise over the last 10 periods and over each of
    `rise_windows` ((start, end) in t/T), the seed's picture (bed_state) at the last frame and at each of
    `bed_periods`, and the end-wall circulation over each of `drift_windows` ("K1-K2"). Returns (row, series)."""
    run_dir = pathlib.Path(run_dir)
    t, z, classes = centroid_series(run_dir)
    if len(t) == 0 or t[0] > 0.01:
        # S is measured from the bed at t = 0: a folder resumed into by a riffle before it carried the series (or a
        # series cut short) would give S against the bed at the resume.
        raise SystemExit(f"study_collect measure: {run_dir / 'class_centroids.csv'} starts at t/T = "
                         f"{t[0] if len(t) else float('nan'):g}, not 0: S needs the bed at t = 0 (a run resumed "
                         "into another folder by an older riffle: prepend the rows of the folder it came from)")
    volumes = class_volumes(run_dir, classes)
    s = segregation_series(t, z, volumes)
    row = {}
    for stage in stages:
        row[f"S_{stage:g}"] = at(t, s, stage)
        for j, k in enumerate(classes):
            row[f"z{k}_{stage:g}_mm"] = 1e3 * at(t, z[:, j], stage)
    for j, k in enumerate(classes):
        row[f"z{k}_rise_last10_mm_per_T"] = rise_rate(t, z[:, j])
        for start, end in rise_windows:
            row[f"z{k}_rise_{start:g}-{end:g}_mm_per_T"] = rise_rate(t, z[:, j], start=start, end=end)
    row.update(bed_state(run_dir))
    for period in bed_periods:
        row.update({f"{key}_at_{period:g}": value for key, value in bed_state(run_dir, period).items()
                    if key not in ("corner_large_grains", "small_share_bottom_start")})
    # measure draws its own drift table (RUN_DIR/figures/measure/), so the run's figures keep their windows.
    measured = run_dir / "figures" / "measure" if tuple(drift_windows) != DRIFT_WINDOWS else None
    for window, (end_band, middle) in circulation(run_dir, refresh or measured is not None, tuple(drift_windows),
                                                  measured).items():
        row[f"endwall_coarse_dz_{window}_mm_per_T"] = 1e3 * end_band
        row[f"middle_coarse_dz_{window}_mm_per_T"] = 1e3 * middle
    return row, (t, z, s, classes)


def write_csv(path, rows):
    keys = []
    for row in rows:
        keys += [k for k in row if k not in keys]
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=keys)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})


def common_grid(series):
    """The base's series on the t/T samples they share (all runs write the same bed-profile times)."""
    n = min(len(t) for t, _, _, _ in series)
    return series[0][0][:n], np.array([z[:n] for _, z, _, _ in series]), np.array([s[:n] for _, _, s, _ in series])


def ensemble(study, base_series, out):
    t, z, s = common_grid(base_series)
    classes = base_series[0][3]
    rows = []
    for i in range(len(t)):
        row = {"t_over_T": float(t[i])}
        for j, k in enumerate(classes):
            values = 1e3 * z[:, i, j]
            row.update({f"z{k}_mean_mm": values.mean(), f"z{k}_std_mm": values.std(ddof=1) if len(values) > 1 else 0.0,
                        f"z{k}_min_mm": values.min(), f"z{k}_max_mm": values.max()})
        row.update({"S_mean": s[:, i].mean(), "S_std": s[:, i].std(ddof=1) if len(s) > 1 else 0.0,
                    "S_min": s[:, i].min(), "S_max": s[:, i].max()})
        rows.append(row)
    write_csv(out / "ensemble.csv", rows)
    figure, (ax_z, ax_s) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    for j, k in enumerate(classes):
        values = 1e3 * z[:, :, j]
        mean, std = values.mean(axis=0), values.std(axis=0, ddof=1) if len(values) > 1 else 0 * values[0]
        colour = seed_figures.class_colour(k)
        ax_z.fill_between(t, values.min(axis=0), values.max(axis=0), color=colour, alpha=0.15, lw=0)
        ax_z.fill_between(t, mean - std, mean + std, color=colour, alpha=0.35, lw=0)
        ax_z.plot(t, mean, color=colour, label=seed_figures.class_name(k))
    ax_z.set_xlabel("t/T")
    ax_z.set_ylabel("centroid above the floor [mm]")
    ax_z.legend(fontsize=8)
    ax_z.grid(alpha=0.3)
    mean, std = s.mean(axis=0), s.std(axis=0, ddof=1) if len(s) > 1 else 0 * s[0]
    ax_s.fill_between(t, s.min(axis=0), s.max(axis=0), color="0.5", alpha=0.2, lw=0, label="range")
    ax_s.fill_between(t, mean - std, mean + std, color="0.3", alpha=0.35, lw=0, label="mean ± 1 s.d.")
    ax_s.plot(t, mean, color="k", label="mean")
    ax_s.set_xlabel("t/T")
    ax_s.set_ylabel("segregation index S")
    ax_s.legend(fontsize=8)
    ax_s.grid(alpha=0.3)
    figure.suptitle(f"{study.name}: ensemble of {len(base_series)} beds ({study.variants[0]['name']}), "
                    "band: mean ± 1 s.d. (dark) and range (light)", fontsize=9)
    seed_figures.save(figure, out / "ensemble.png")


def mean_std(values):
    values = [v for v in values if v is not None and not math.isnan(v)]
    if not values:
        return math.nan, math.nan, 0
    return float(np.mean(values)), float(np.std(values, ddof=1)) if len(values) > 1 else math.nan, len(values)


SENSITIVITY_KEYS = [f"S_{stage}" for stage in STAGES] + [f"z2_{stage}_mm" for stage in STAGES] + \
    [f"endwall_coarse_dz_{w}_mm_per_T" for w in DRIFT_WINDOWS] + \
    [f"middle_coarse_dz_{w}_mm_per_T" for w in DRIFT_WINDOWS] + \
    ["z2_rise_last10_mm_per_T", "small_share_bottom_end", "corner_large_max_move_mm", "corner_large_still"]


def sensitivity_table(variants, rows, base_name, reference_name=None):
    """One entry per variant (in the order of `variants`: (name, set text) pairs) with runs in `rows`: the mean and
    spread over its beds of each SENSITIVITY_KEYS measure, and whether its difference from the reference's mean (the
    base's by default) counts: |mean_v - mean_ref| > 2 s sqrt(1/n_v + 1/n_ref), s the base's standard deviation over
    its beds (the ensemble's noise)."""
    reference_name = reference_name or base_name
    base_rows = [r for r in rows if r["variant"] == base_name]
    reference_rows = [r for r in rows if r["variant"] == reference_name]
    table = []
    for name, set_text in variants:
        mine = [r for r in rows if r["variant"] == name]
        if not mine:
            continue
        entry = {"variant": name, "set": set_text or "(base)", "beds": len(mine),
                 "bed_list": " ".join(sorted(str(r.get("bed")) for r in mine)),
                 "wall_s_mean": mean_std([r.get("wall_s") for r in mine])[0],
                 "threads": int(float(mine[0].get("threads") or 0))}
        for key in SENSITIVITY_KEYS:
            m, sd, n = mean_std([r.get(key, math.nan) for r in mine])
            rm, _, rn = mean_std([r.get(key, math.nan) for r in reference_rows])
            _, bsd, bn = mean_std([r.get(key, math.nan) for r in base_rows])
            entry[key] = m
            entry[f"{key}_spread"] = sd
            if name != reference_name and n and rn and bn > 1 and not math.isnan(bsd):
                entry[f"{key}_delta"] = m - rm
                entry[f"{key}_counts"] = "yes" if abs(m - rm) > 2.0 * bsd * math.sqrt(1.0 / n + 1.0 / rn) else "no"
        table.append(entry)
    return table


def write_sensitivity(out, table, note=""):
    """sensitivity.csv and sensitivity.md of a sensitivity_table."""
    write_csv(out / "sensitivity.csv", table)
    with open(out / "sensitivity.md", "w") as handle:
        handle.write(f"| variant | beds | S at 10 | S at 20 | S at 30 | large at 30 [mm] | end-wall coarse dz 20-30 "
                     f"[mm/T] | middle coarse dz 20-30 [mm/T] | wall time per run [s] |\n|---|---|---|---|---|---|---|---|---|\n")

        def cell(entry, key, digits):
            value = entry.get(key, math.nan)
            if math.isnan(value):
                return "–"
            text = f"{value:.{digits}f}"
            spread = entry.get(f"{key}_spread", math.nan)
            if not math.isnan(spread):
                text += f" ± {spread:.{digits}f}"
            if entry.get(f"{key}_counts") == "yes":
                text = f"**{text}**"
            return text

        for entry in table:
            handle.write(f"| {entry['variant']} | {entry['bed_list']} | {cell(entry, 'S_10', 3)} | "
                         f"{cell(entry, 'S_20', 3)} | "
                         f"{cell(entry, 'S_30', 3)} | {cell(entry, 'z2_30_mm', 1)} | "
                         f"{cell(entry, 'endwall_coarse_dz_20-30_mm_per_T', 3)} | "
                         f"{cell(entry, 'middle_coarse_dz_20-30_mm_per_T', 3)} | {entry['wall_s_mean']:.0f} "
                         f"({entry['threads']} thread) |\n")
        handle.write("\n± is the standard deviation over the variant's beds; **bold**: the difference from the "
                     "reference exceeds twice its standard error from the base ensemble's spread "
                     f"(tools/riffle-tools study-collect).{note}\n")


def sensitivity(study, rows, series, out):
    base_name = study.variants[0]["name"]
    table = sensitivity_table([(v["name"], " ".join(v.get("set", []))) for v in study.variants], rows, base_name)
    write_sensitivity(out, table)
    # S against t/T, one mean curve per variant, over the base's band.
    figure, ax = plt.subplots(figsize=(8, 4.5), constrained_layout=True)
    base_series = series[base_name]
    t, _, s = common_grid(base_series)
    ax.fill_between(t, s.min(axis=0), s.max(axis=0), color="0.6", alpha=0.3, lw=0,
                    label=f"{base_name}: range of {len(base_series)} beds")
    ax.plot(t, s.mean(axis=0), color="k", lw=2, label=f"{base_name}: mean")
    for name, runs in series.items():
        if name == base_name:
            continue
        tv, _, sv = common_grid(runs)
        ax.plot(tv, sv.mean(axis=0), lw=1, label=f"{name} ({len(runs)} beds)")
    ax.set_xlabel("t/T")
    ax.set_ylabel("segregation index S")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    seed_figures.save(figure, out / "sensitivity.png")


def collect(study, refresh=False):
    out = study.out / "collect"
    out.mkdir(parents=True, exist_ok=True)
    rows, series = [], {}
    for variant, seed in study.jobs():
        result = run_summary(study, variant, seed, refresh)
        if result is None:
            continue
        row, data = result
        rows.append(row)
        series.setdefault(variant["name"], []).append(data)
    if not rows:
        print(f"study {study.name}: no run is done yet")
        return 1
    write_csv(out / "runs.csv", rows)
    base_name = study.variants[0]["name"]
    if base_name in series:
        ensemble(study, series[base_name], out)
        sensitivity(study, rows, series, out)
    print(f"study {study.name}: {len(rows)} runs collected into {out}")
    print((out / "sensitivity.md").read_text() if (out / "sensitivity.md").exists() else "")
    return 0


def read_runs(path):
    """A runs.csv (collect's, or one kept under docs/results/) as rows with numbers as floats."""
    rows = []
    for raw in read_rows(path):
        row = {}
        for key, value in raw.items():
            try:
                row[key] = float(value) if key not in ("variant", "bed") and value != "" else value
            except ValueError:
                row[key] = value
        rows.append(row)
    return rows


def merge(paths, base_name, reference_name, out, variant_names=None):
    """The sensitivity table over the runs of several runs.csv files (the beds of one variant run by different
    studies, or machines): each (variant, bed) once, the first file's row kept where two files hold it."""
    rows, seen, order = [], set(), []
    for path in paths:
        for row in read_runs(path):
            key = (row["variant"], str(row["bed"]))
            if key in seen:
                continue
            seen.add(key)
            rows.append(row)
            if row["variant"] not in order:
                order.append(row["variant"])
    names = variant_names or order
    missing = [n for n in [base_name, reference_name or base_name] + list(names) if n not in order]
    if missing:
        raise SystemExit(f"study_collect merge: no runs of {', '.join(missing)} in {', '.join(map(str, paths))}")
    out.mkdir(parents=True, exist_ok=True)
    table = sensitivity_table([(n, "") for n in names], rows, base_name, reference_name)
    write_csv(out / "runs.csv", rows)
    write_sensitivity(out, table, f" Reference: {reference_name or base_name}; spread: {base_name}'s beds.")
    print((out / "sensitivity.md").read_text())
    return 0


def main(argv=None):
    """`tools/riffle-tools study-collect measure RUN_DIR ...`: the study's measures of any run directory (a 100-period
    run, say). `tools/riffle-tools study-collect merge RUNS.csv... --base NAME [--reference NAME] --out DIR`: the
    sensitivity table over the runs of several studies (the beds of a variant run by different studies)."""
    import argparse
    if argv is None:
        argv = sys.argv[1:]
    if argv and argv[0] == "merge":
        parser = argparse.ArgumentParser(description="The sensitivity table over the runs of several runs.csv files.")
        parser.add_argument("command", choices=["merge"])
        parser.add_argument("runs", type=pathlib.Path, nargs="+", help="runs.csv files (first wins on a repeat)")
        parser.add_argument("--base", required=True, help="the variant whose beds give the noise s (the ensemble)")
        parser.add_argument("--reference", help="the variant the others are compared with (default: the base)")
        parser.add_argument("--variants", nargs="*", help="the variants in the table, in order (default: all)")
        parser.add_argument("--out", type=pathlib.Path, required=True)
        args = parser.parse_args(argv)
        for path in args.runs:
            if not path.exists():
                parser.error(f"{path}: no such file")
        return merge(args.runs, args.base, args.reference, args.out, args.variants)
    parser = argparse.ArgumentParser(description="The study's measures of one riffle run directory (S and the class "
                                     "centroids at stages, the centroids' rise over windows, the seed's picture, "
                                     "the end-wall circulation), as name,value lines.")
    parser.add_argument("command", choices=["measure"])
    parser.add_argument("run_dir", type=pathlib.Path)
    parser.add_argument("--stages", type=float, nargs="+", default=list(STAGES), help="t/T (default 10 20 30)")
    parser.add_argument("--drift-windows", nargs="+", default=list(DRIFT_WINDOWS), metavar="K1-K2",
                        help="circulation windows in t/T (default 10-20 20-30)")
    parser.add_argument("--rise-windows", nargs="*", default=[], metavar="K1-K2",
                        help="centroid rise windows in t/T (least-squares slope)")
    parser.add_argument("--bed-periods", type=float, nargs="*", default=[],
                        help="the seed's picture (corner grains, small share at the floor) also at these t/T")
    parser.add_argument("--refresh", action="store_true", help="draw the drift table again")
    args = parser.parse_args(argv)
    if not (args.run_dir / "class_centroids.csv").exists():
        parser.error(f"{args.run_dir}: no class_centroids.csv (not a riffle run directory with grains)")
    windows = []
    for text in args.rise_windows:
        try:
            start, end = (float(v) for v in text.split("-"))
        except ValueError:
            parser.error(f"--rise-windows {text!r}: expected K1-K2, e.g. 50-70")
        windows.append((start, end))
    row, _ = measure(args.run_dir, args.stages, args.drift_windows, windows, args.bed_periods, args.refresh)
    for key, value in row.items():
        print(f"{key},{value:.6g}" if isinstance(value, float) else f"{key},{value}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
