"""The returning wave of a dam break: riffle against Lobovsky et al. (2014), H = 300 mm.

Runs scenes/dam_break_lobovsky_gauges.toml (or analyses runs already made) at chosen spacings and settings, and
prints when the bore that comes back from the far wall passes the gauges H4 (x = 1.3625 m) and H3 (x = 1.114 m),
against tests/data/lobovsky_2014_returning_wave.csv. Extra gauges every 50 mm from 0.95 to 1.55 m trace the bore.

Usage, from the repository root:
  tools/riffle-tools returning-wave run OUT_DIR --spacing 0.01 [--slab 4] [--set KEY=VALUE ...]
      [--scheme KEY=VALUE ...] [--until 1.4] [--threads 1] [--binary build/riffle]
  tools/riffle-tools returning-wave analyse OUT_DIR [OUT_DIR ...]
--set adds or replaces a [fluid] key (e.g. courant=0.1, kinematic_viscosity=0), --scheme a [fluid.schemes] key
(e.g. ds=false). --slab is the slab thickness in spacings (the tank's y size). The tank must be a whole number of
spacings long (1.61 m: 23, 11.5, 10, 7, 5 mm ...); the height (--height, 0.6 m) is rounded up to one.
"""
import argparse
import csv
import math
import pathlib
import re
import subprocess
import sys
import time

from . import ROOT
SCENE = ROOT / "scenes" / "dam_break_lobovsky_gauges.toml"
REFERENCE = ROOT / "tests" / "data" / "lobovsky_2014_returning_wave.csv"
H = 0.3
G = 9.81
T_SCALE = math.sqrt(G / H)
GAUGES = {"H1": 0.3, "H2": 0.865, "H3": 1.114, "H4": 1.3625}
EXTRA = [round(0.95 + 0.05 * k, 3) for k in range(13)]
SEARCH_FROM_T = 4.5  # the returning bore comes after the run-up, T > 5; the first front passes H3/H4 at T ~ 2


def scene_text(spacing, slab, fluid_keys, scheme_keys, vtk_interval=0.0, tank_height=0.6):
    """The gauge scene at another spacing and slab thickness, with extra [fluid] and [fluid.schemes] keys."""
    length, column, height = 1.61, 0.6, 0.3
    cells = length / spacing
    if abs(cells - round(cells)) > 1e-6:
        raise SystemExit(f"spacing {spacing}: the tank length 1.61 m is {cells:.3f} spacings, not a whole number")
    width = slab * spacing
    tank_height = math.ceil(tank_height / spacing - 1e-9) * spacing
    text = SCENE.read_text()
    y = 0.5 * width
    gauges = ", ".join(f"[{x}, {y:.6g}]" for x in list(GAUGES.values()) + EXTRA)
    replacements = [
        (r"^size = \[1\.61, [^\]]*\]", f"size = [{length}, {width:.6g}, {tank_height:.6g}]"),
        (r"^spacing = [0-9.e-]+", f"spacing = {spacing}"),
        (r"^high = \[0\.6, [^\]]*\]", f"high = [{column}, {width:.6g}, {height}]"),
        (r"^points = \[\[0\.3, [^\n]*", f"points = [{gauges}]"),
        (r"^vtk_interval = [0-9.e-]+", f"vtk_interval = {vtk_interval}"),
    ]
    for pattern, new in replacements:
        text, count = re.subn(pattern, new, text, flags=re.M)
        if count != 1:
            raise SystemExit(f"{SCENE}: pattern {pattern!r} matched {count} times")
    # [fluid] keys: replaced inside the [fluid] table only (other tables have keys of the same names), else added.
    head = text.index("\n[fluid]\n") + len("\n[fluid]\n")
    end = text.index("\n[", head)
    table = text[head:end]
    for key, value in fluid_keys:
        table, count = re.subn(rf"^{re.escape(key)} = [^\n]*", f"{key} = {value}", table, flags=re.M)
        if count == 0:
            table = f"{key} = {value}\n" + table
    text = text[:head] + table + text[end:]
    if scheme_keys:
        block = "[fluid.schemes]\n" + "".join(f"{k} = {v}\n" for k, v in scheme_keys) + "\n"
        text = text.replace("[[fluid.boxes]]", block + "[[fluid.boxes]]", 1)
    return text


def read_gauges(run):
    """(T, {gauge name: h/H or None}) rows of OUT/probe_gauges.csv; the columns are H1-H4 then the extra gauges."""
    names = list(GAUGES) + [f"x{x:.3f}" for x in EXTRA]
    rows = []
    with open(pathlib.Path(run) / "probe_gauges.csv") as f:
        reader = csv.reader(f)
        next(reader)
        for row in reader:
            values = [float(v) / H if v else None for v in row[2:]]
            rows.append((float(row[0]) * T_SCALE, dict(zip(names, values))))
    return rows


def crossing(rows, name, threshold, after=SEARCH_FROM_T):
    """First T after `after` at which gauge `name` reaches `threshold` (h/H), linearly interpolated; None if never."""
    previous = None
    for t, values in rows:
        h = values.get(name)
        if t < after or h is None:
            previous = None if t < after else previous
            continue
        if h >= threshold:
            if previous is None:
                return t
            t0, h0 = previous
            return t0 + (threshold - h0) / (h - h0) * (t - t0)
        previous = (t, h)
    return None


def front_arrival(run, x):
    """T at which the surge front (probe_front.csv) first reaches x [m]: the first front's impact on the far wall."""
    previous = None
    with open(pathlib.Path(run) / "probe_front.csv") as f:
        reader = csv.reader(f)
        next(reader)
        for row in reader:
            if not row[2]:
                continue
            t, front = float(row[0]) * T_SCALE, float(row[2])
            if front >= x:
                return t if previous is None else previous[0] + (x - previous[1]) / (front - previous[1]) * (t - previous[0])
            previous = (t, front)
    return None


def reference():
    with open(REFERENCE) as f:
        rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
    return {(r["gauge"], float(r["threshold_h_over_H"])): 0.5 * (float(r["T_A"]) + float(r["T_B"])) for r in rows}


def fmt(value, digits=2):
    return "-" if value is None else f"{value:.{digits}f}"


def analyse(run):
    rows = read_gauges(run)
    ref = reference()
    out = {"run": str(run)}
    for threshold in (0.5, 0.4):
        for gauge in ("H4", "H3"):
            t = crossing(rows, gauge, threshold)
            out[f"{gauge}@{threshold}"] = t
            out[f"{gauge}@{threshold}_late"] = None if t is None else t - ref[(gauge, threshold)]
    # Bore speed between H4 and H3 in units of sqrt(gH) (experiment: 0.2485 m / H over dT).
    t4, t3 = out["H4@0.5"], out["H3@0.5"]
    out["speed"] = None if t4 is None or t3 is None else (GAUGES["H4"] - GAUGES["H3"]) / H / (t3 - t4)
    out["trace"] = [(x, crossing(rows, f"x{x:.3f}", 0.5)) for x in EXTRA]
    # Levels before the bore (mean over 4.5 < T < 5.5) at H3 and H4, and the run's wall time.
    for gauge in ("H3", "H4"):
        values = [v[gauge] for t, v in rows if 4.5 < t < 5.5 and v[gauge] is not None]
        out[f"{gauge}_before"] = sum(values) / len(values) if values else None
    out["impact"] = front_arrival(run, 1.6)
    wall = pathlib.Path(run) / "wall_s.txt"
    out["wall_s"] = float(wall.read_text()) if wall.exists() else None
    return out


def print_table(results):
    ref = reference()
    speed_ref = (GAUGES["H4"] - GAUGES["H3"]) / H / (ref[("H3", 0.5)] - ref[("H4", 0.5)])
    print("T = t sqrt(g/H) at which the returning bore raises the level to h/H = 0.5 (0.4); late = riffle - experiment")
    print(f"{'run':40s} {'H4 0.5':>7s} {'late':>6s} {'H3 0.5':>7s} {'late':>6s} {'H4 0.4':>7s} {'H3 0.4':>7s} "
          f"{'speed':>6s} {'h3 pre':>6s} {'h4 pre':>6s} {'impact':>6s} {'wall s':>7s}")
    print(f"{'experiment (Lobovsky et al. 2014)':40s} {ref[('H4', 0.5)]:7.2f} {'':6s} {ref[('H3', 0.5)]:7.2f} "
          f"{'':6s} {ref[('H4', 0.4)]:7.2f} {ref[('H3', 0.4)]:7.2f} {speed_ref:6.2f} {0.24:6.2f} {'.13-.4':>6s} {'':>6s}")
    for r in results:
        print(f"{pathlib.Path(r['run']).name[:40]:40s} {fmt(r['H4@0.5']):>7s} {fmt(r['H4@0.5_late']):>6s} "
              f"{fmt(r['H3@0.5']):>7s} {fmt(r['H3@0.5_late']):>6s} {fmt(r['H4@0.4']):>7s} {fmt(r['H3@0.4']):>7s} "
              f"{fmt(r['speed']):>6s} {fmt(r['H3_before']):>6s} {fmt(r['H4_before']):>6s} {fmt(r['impact']):>6s} "
              f"{fmt(r['wall_s'], 0):>7s}")
    print("speed: (x_H4 - x_H3) / H over the T between the two 0.5 crossings, in sqrt(gH); h3/h4 pre: mean level over")
    print("4.5 < T < 5.5; impact: T at which the first surge front reaches x = 1.6 m (riffle's, for the time origin)")
    print("bore trace, T of the 0.5 crossing at x [m]:")
    for r in results:
        print(f"  {pathlib.Path(r['run']).name[:38]:38s} " +
              " ".join(f"{x:.2f}:{fmt(t)}" for x, t in r["trace"]))


def key_values(items):
    pairs = []
    for item in items or []:
        if "=" not in item:
            raise SystemExit(f"expected KEY=VALUE, got {item!r}")
        key, value = item.split("=", 1)
        pairs.append((key.strip(), value.strip()))
    return pairs


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run")
    run.add_argument("out")
    run.add_argument("--spacing", type=float, default=0.01)
    run.add_argument("--slab", type=int, default=4)
    run.add_argument("--set", action="append")
    run.add_argument("--scheme", action="append")
    run.add_argument("--until", type=float, default=1.4)
    run.add_argument("--vtk", type=float, default=0.0, help="ParaView frame interval [s] (0 = none)")
    run.add_argument("--height", type=float, default=0.6,
                     help="tank height [m], the walls' height (the top is open); spray may fly over 0.6 m walls")
    run.add_argument("--threads", type=int, default=1)
    run.add_argument("--binary", default=str(ROOT / "build" / "riffle"))
    analyse_parser = sub.add_parser("analyse")
    analyse_parser.add_argument("runs", nargs="+")
    args = parser.parse_args(argv)
    if args.command == "analyse":
        print_table([analyse(r) for r in args.runs])
        return
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    scene = out / "scene.toml"
    scene.write_text(scene_text(args.spacing, args.slab, key_values(args.set), key_values(args.scheme), args.vtk,
                                      args.height))
    start = time.time()
    command = [args.binary, "run", str(scene), "--out", str(out), "--threads", str(args.threads),
               "--until", str(args.until), "--log-level", "warn"]
    result = subprocess.run(command)
    (out / "wall_s.txt").write_text(f"{time.time() - start:.1f}\n")
    if result.returncode != 0:  # e.g. a particle that leaks through a side wall late in the run: analyse what is there
        print(f"riffle exited with {result.returncode}; analysing the rows written", file=sys.stderr)
        (out / "exit_code.txt").write_text(f"{result.returncode}\n")
    print_table([analyse(out)])


if __name__ == "__main__":
    sys.exit(main())
