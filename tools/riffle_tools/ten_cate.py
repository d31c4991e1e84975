"""ten Cate et al.'s (2002) sphere settling onto the floor of a box of oil, against the measurements: the whole fall
with the scene defaults (scenes/settling_ten_cate.toml), at several water spacings.

The experiment (Phys. Fluids 14, 4012-4025): a 15 mm nylon sphere of 1120 kg/m^3 released from rest with its lowest
point 120 mm above the floor of a 100 x 100 mm box of silicone oil; four oils, E1-E4, Re 1.5-31.9. The measured speed
and gap against time (tests/data/ten_cate_2002_settling.csv, digitised from the paper's figures) are the reference
for the start from rest (the history of the water's answer), the speed the box's walls allow, and the approach to
the floor. For each experiment and spacing the tool runs the scene with --set, reads the grain's probe and reports:
  - peak: the run's largest downward speed over the measured largest;
  - start: the RMS over the measured points until the measured speed first reaches 95 % of its peak of
    v_run(t) - v_exp(t), over the measured largest speed (the start from rest, where the water's answer builds up: the history force's part);
  - gap(t): the RMS over the measured gap points of gap_run(t) - gap_exp(t), in diameters (the fall's timing);
  - approach: the RMS over gaps of 1 to 6 diameters (every 0.05 d) of v_run(gap) - v_exp(gap), over the measured
    largest speed (v_exp(gap) pairs each measured speed with the measured gap at its time); its shape, the RMS of
    v(gap) / v(6 d) of the run minus the experiment's over the same gaps (the settling-study's approach measure,
    blind to the speed's level; E3's and E4's measured spheres are still speeding up at 6 d, at 0.92 and 0.88 of
    their peaks, so for them it holds some of the start too); and v / v_peak of the run and the experiment at gaps 1 and 0.5 d (the floor's
    slowing).

Usage:
  tools/riffle-tools ten-cate [--riffle build/riffle] [--scene scenes/settling_ten_cate.toml] [--out out/ten_cate]
      [--experiments E1,E2,E3,E4] [--spacings 0.01,0.0066667,0.005] [--set KEY=VALUE ...] [--threads 1] [--reuse]
      [--plot out/ten_cate/ten_cate.png] [--check TOL_APPROACH]
--plot draws each oil's speed against time and against gap, the runs beside the measurements (run it with
/usr/bin/python3: Debian's matplotlib). --check exits 1 when a run's approach RMS exceeds TOL_APPROACH (the issue's 5 %: 0.05).
"""
import argparse
import csv
import math
import pathlib
import shutil
import subprocess
import sys

from riffle_tools import settling_study

DIAMETER = 0.015
# ten Cate et al. 2002, Table 1: oil density [kg/m^3], dynamic viscosity [Pa s], the unbounded terminal speed [m/s];
# the end of each run (s), past the measured landing.
EXPERIMENTS = {
    "E1": dict(density=970.0, viscosity=0.373, u_inf=0.038, end=4.5),
    "E2": dict(density=965.0, viscosity=0.212, u_inf=0.060, end=3.0),
    "E3": dict(density=962.0, viscosity=0.113, u_inf=0.091, end=2.0),
    "E4": dict(density=960.0, viscosity=0.058, u_inf=0.128, end=1.5),
}
DATA = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "ten_cate_2002_settling.csv"
APPROACH_GAPS = (1.0, 6.0)  # diameters
LANDED_GAP = 0.1  # diameters: the measured points beyond this are the contact's, not the water's


def read_measurements(path=DATA):
    """{experiment: {"speed_m_s": [(t, v)], "gap_over_d": [(t, gap)]}}, each sorted by time."""
    table = {}
    with open(path) as handle:
        rows = csv.DictReader(line for line in handle if not line.startswith("#"))
        for row in rows:
            series = table.setdefault(row["experiment"], {}).setdefault(row["quantity"], [])
            series.append((float(row["t_s"]), float(row["value"])))
    for quantities in table.values():
        for series in quantities.values():
            series.sort()
    return table


def interpolate(xs, ys, x):
    """Linear interpolation in increasing xs, held at the ends."""
    if x <= xs[0]:
        return ys[0]
    if x >= xs[-1]:
        return ys[-1]
    low, high = 0, len(xs) - 1
    while high - low > 1:
        mid = (low + high) // 2
        low, high = (mid, high) if xs[mid] <= x else (low, mid)
    f = (x - xs[low]) / (xs[high] - xs[low]) if xs[high] > xs[low] else 0.0
    return ys[low] + f * (ys[high] - ys[low])


def speed_against_gap(times, speeds, gaps, gap_times):
    """([gap], [speed]) along the fall up to where the sphere first lands (gap below LANDED_GAP), each speed at the
    gap of its time, returned in increasing gap for interpolate; a gap met twice (a digitising wobble) keeps the
    speed met first."""
    pairs = []
    for t, v in zip(times, speeds):
        gap = interpolate(gap_times, gaps, t)
        if gap < LANDED_GAP:
            break
        pairs.append((gap, v))
    first = {}
    for gap, v in pairs:
        first.setdefault(gap, v)
    gaps_increasing = sorted(first)
    return gaps_increasing, [first[g] for g in gaps_increasing]


def read_run(path):
    """(times, gaps over d, downward speeds) of the grain's probe (settling-study's reader)."""
    times, heights, speeds = settling_study.read_probe(path)
    return times, [(z - DIAMETER / 2.0) / DIAMETER for z in heights], speeds


def compare(run, measured):
    """The measures of the docstring for one run ((times, gaps, speeds)) against one experiment's measurements."""
    times, gaps, speeds = run
    m_speed, m_gap = measured["speed_m_s"], measured["gap_over_d"]
    mt, mv = [p[0] for p in m_speed], [p[1] for p in m_speed]
    gt, gv = [p[0] for p in m_gap], [p[1] for p in m_gap]
    scale = max(mv)
    # the measured landing: the first measured gap below LANDED_GAP, else the last point
    landing = next((t for t, g in m_gap if g < LANDED_GAP), gt[-1])
    # the start: until the measured speed first reaches 95 % of its peak (the plateau is flat, and its measured
    # peak can come late in it, after a fast run has landed)
    peak_time = next(t for t, v in m_speed if v >= 0.95 * scale)
    speed_sq = [(interpolate(times, speeds, t) - v) ** 2 for t, v in m_speed if 0.0 <= t <= peak_time]
    gap_sq = [(interpolate(times, gaps, t) - g) ** 2 for t, g in m_gap if 0.0 <= t <= landing and g >= LANDED_GAP]
    # the run's speed against its gap, up to its first landing
    run_g, run_v = speed_against_gap(times, speeds, gaps, times)
    exp_g, exp_v = speed_against_gap(mt, mv, gv, gt)
    if len(run_g) < 2 or max(run_v) <= 0.0:  # the run never fell (or started landed): nothing to compare
        nan = float("nan")
        return dict(peak=max(speeds) / scale, start_rms=nan, gap_rms=nan, approach_rms=nan, shape_rms=nan,
                    run_at_1d=nan, exp_at_1d=nan, run_at_half_d=nan, exp_at_half_d=nan)
    approach_sq, shape_sq, count = 0.0, 0.0, 0
    run_top, exp_top = (interpolate(run_g, run_v, APPROACH_GAPS[1]), interpolate(exp_g, exp_v, APPROACH_GAPS[1]))
    gap = APPROACH_GAPS[0]
    while gap <= APPROACH_GAPS[1] + 1e-9:
        run_here, exp_here = interpolate(run_g, run_v, gap), interpolate(exp_g, exp_v, gap)
        approach_sq += (run_here - exp_here) ** 2
        shape_sq += (run_here / max(run_top, 1e-12) - exp_here / exp_top) ** 2
        count += 1
        gap += 0.05

    def slowing(gs, vs, at):
        return interpolate(gs, vs, at) / max(vs)

    return dict(
        peak=max(speeds) / scale,
        start_rms=math.sqrt(sum(speed_sq) / max(len(speed_sq), 1)) / scale,
        gap_rms=math.sqrt(sum(gap_sq) / max(len(gap_sq), 1)),
        approach_rms=math.sqrt(approach_sq / count) / scale,
        shape_rms=math.sqrt(shape_sq / count),
        run_at_1d=slowing(run_g, run_v, 1.0), exp_at_1d=slowing(exp_g, exp_v, 1.0),
        run_at_half_d=slowing(run_g, run_v, 0.5), exp_at_half_d=slowing(exp_g, exp_v, 0.5),
    )


def run_case(riffle, scene, out, experiment, spacing, overrides, threads, reuse):
    e = EXPERIMENTS[experiment]
    name = f"{experiment}_l0_{spacing * 1000:.4g}mm"
    run_dir = pathlib.Path(out) / name
    probe = run_dir / "probe_grains.csv"
    if not (reuse and probe.exists()):
        shutil.rmtree(run_dir, ignore_errors=True)
        command = [riffle, "run", str(scene), "--out", str(run_dir), "--threads", str(threads),
                   "--until", f"{e['end']:g}",
                   "--set", f"fluid.spacing={spacing:.10g}", "--set", f"fluid.density={e['density']:g}",
                   "--set", f"fluid.kinematic_viscosity={e['viscosity'] / e['density']:.10g}",
                   "--set", "output.vtk_interval=0"]
        for override in overrides:
            command += ["--set", override]
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return name, read_run(probe), stepping_seconds(run_dir)


def stepping_seconds(run_dir):
    """The run's stepping wall time from its timings.csv, if written."""
    path = run_dir / "timings.csv"
    if not path.exists():
        return float("nan")
    with open(path) as handle:
        for row in csv.DictReader(handle):
            if row.get("system", "").startswith("stepping"):
                return float(row.get("total_s", "nan"))
    return float("nan")


def plot(path, results, measurements):
    """One row per experiment: the speed against time, and against the gap; each run a line, the measurements dots.
    `results` maps an experiment to [(label, (times, gaps, speeds))]."""
    from riffle_tools import plotting
    plt = plotting.pyplot("ten-cate")
    rows = len(results)
    figure, axes = plt.subplots(rows, 2, figsize=(10, 2.8 * rows), squeeze=False)
    for row, (experiment, runs) in enumerate(results.items()):
        measured = measurements[experiment]
        by_time, by_gap = axes[row]
        for label, (times, gaps, speeds) in runs:
            by_time.plot(times, speeds, label=label, linewidth=1)
            g, v = speed_against_gap(times, speeds, gaps, times)
            by_gap.plot(g, v, label=label, linewidth=1)
        mt = [t for t, _ in measured["speed_m_s"]]
        mv = [v for _, v in measured["speed_m_s"]]
        gt = [t for t, _ in measured["gap_over_d"]]
        gv = [g for _, g in measured["gap_over_d"]]
        by_time.plot(mt, mv, "ko", markersize=3, label="ten Cate et al. 2002")
        eg, ev = speed_against_gap(mt, mv, gv, gt)
        by_gap.plot(eg, ev, "ko", markersize=3, label="ten Cate et al. 2002")
        by_gap.axvspan(*APPROACH_GAPS, color="0.92", zorder=0)
        by_time.set_ylabel(f"{experiment}: speed [m/s]")
        by_gap.set_xlim(8.2, 0.0)
        if row == rows - 1:
            by_time.set_xlabel("t [s]")
            by_gap.set_xlabel("gap / d (the approach window shaded)")
        if row == 0:
            by_time.legend(fontsize=7)
    figure.tight_layout()
    plotting.write(figure, path, "ten-cate")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--riffle", default="build/riffle")
    parser.add_argument("--scene", default="scenes/settling_ten_cate.toml")
    parser.add_argument("--out", default="out/ten_cate")
    parser.add_argument("--experiments", default="E1,E2,E3,E4")
    parser.add_argument("--spacings", default="0.01,0.0066666667,0.005",
                        help="water spacings in m (the tank's 180 mm and the box's 100 mm must be multiples)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                        help="another scene override for every run (repeatable), e.g. coupling.history_force=true")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--reuse", action="store_true", help="read runs already in --out instead of running them")
    parser.add_argument("--plot", metavar="PNG", help="draw the runs beside the measurements into this file")
    parser.add_argument("--check", type=float, metavar="TOL_APPROACH",
                        help="exit 1 when a run's approach RMS (over the measured peak) exceeds this")
    args = parser.parse_args(argv)

    measurements = read_measurements()
    experiments = [e.strip() for e in args.experiments.split(",") if e.strip()]
    unknown = [e for e in experiments if e not in EXPERIMENTS]
    if unknown:
        parser.error(f"unknown experiment(s) {', '.join(unknown)}: choose among {', '.join(EXPERIMENTS)}")
    spacings = [float(s) for s in args.spacings.split(",") if s.strip()]
    print("| experiment | d/l0 | peak / measured | start RMS | gap(t) RMS [d] | approach RMS, 1-6 d | its shape | "
          "v/v_peak at 1 d, run (measured) | at 0.5 d | stepping [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    failed = []
    results = {}
    for experiment in experiments:
        for spacing in spacings:
            name, run, seconds = run_case(args.riffle, args.scene, args.out, experiment, spacing, args.overrides,
                                          args.threads, args.reuse)
            r = compare(run, measurements[experiment])
            results.setdefault(experiment, []).append((f"d/l0 = {DIAMETER / spacing:.3g}", run))
            print(f"| {experiment} | {DIAMETER / spacing:.3g} | {r['peak']:.3f} | {100 * r['start_rms']:.1f} % | "
                  f"{r['gap_rms']:.2f} | {100 * r['approach_rms']:.1f} % | {100 * r['shape_rms']:.1f} % | {r['run_at_1d']:.3f} "
                  f"({r['exp_at_1d']:.3f}) | {r['run_at_half_d']:.3f} ({r['exp_at_half_d']:.3f}) | "
                  f"{seconds:.1f} |", flush=True)
            if args.check is not None and not r["approach_rms"] <= args.check:
                failed.append(name)
    if args.plot:
        plot(args.plot, results, measurements)
    if failed:
        print(f"approach RMS above {args.check}: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
