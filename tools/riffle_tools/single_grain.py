"""One grain over a fixed bed (scenes/single_grain_channel.toml, seed 004; docs/cases/bedload.md): the regime of
each run's grain from its path (probe_grains.csv, the grain id 0), beside the seed's.

    tools/riffle-tools single-grain 25=out/single_grain/Ga25 150=out/single_grain/Ga150 ... [--out table.csv]

Per run: the distance travelled along x over the run in diameters (the path unwrapped across the periodic seam),
the mean streamwise speed over u_tau, the highest rise of the centre above its resting height and the share of
the time it spends more than a quarter diameter above it (rolling over a close-packed bed lifts a grain 0.05 D at a
saddle, 0.18 D over a sphere's top), and the regime: rest (travelled below half a diameter), rolling (moves, never clear of the bed for more than
5 % of the time), saltation (hops: clear of the bed part of the time), resuspension (clear more than half the time
and rising above one diameter). The seed's regimes: Ga 25 resuspension, 150 saltation, 250 and 310 rolling (32 D and
10.5 D by t U_b / D = 83), at rest between the turbulent sweeps that move them.
"""
import argparse
import csv
import math
import sys

from . import run_outputs

SEED_REGIME = {25: "resuspension", 150: "saltation", 250: "rolling (32 D)", 310: "rolling (10.5 D)"}


def unwrap(values, period):
    """The path across the periodic seam: each jump over half the period is a crossing."""
    out, shift = [values[0]], 0.0
    for previous, value in zip(values, values[1:]):
        step = value - previous
        if step > 0.5 * period:
            shift -= period
        elif step < -0.5 * period:
            shift += period
        out.append(value + shift)
    return out


def measure(run_dir, diameter, friction_velocity, period):
    columns = run_outputs.read_columns(run_outputs.probe_path(run_dir, "grains"))
    time, x, z = columns["time_s"], unwrap(list(columns["grain0_x_m"]), period), columns["grain0_z_m"]
    rest = z[0]
    rise = (z - rest) / diameter
    travelled = (x[-1] - x[0]) / diameter
    speed = (x[-1] - x[0]) / (time[-1] - time[0]) / friction_velocity
    clear = float((rise > 0.25).mean())
    highest = float(rise.max())
    if abs(travelled) < 0.5:
        regime = "rest"
    elif clear <= 0.05:
        regime = "rolling"
    elif clear > 0.5 and highest > 1.0:
        regime = "resuspension"
    else:
        regime = "saltation"
    return {"travelled_d": travelled, "speed_over_u_tau": speed, "highest_rise_d": highest,
            "time_clear": clear, "regime": regime}


def main(argv=None):
    parser = argparse.ArgumentParser(prog="riffle-tools single-grain", description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="GA=RUN_DIR, one per Galileo number")
    parser.add_argument("--diameter", type=float, default=0.002, help="[m] D (default 2 mm)")
    parser.add_argument("--friction-velocity", type=float, default=0.01075, help="[m/s] u_tau (21.5 nu / D)")
    parser.add_argument("--period", type=float, default=0.04, help="[m] the box's length along x")
    parser.add_argument("--out", help="also write the table as CSV")
    args = parser.parse_args(argv)
    rows = []
    for item in args.runs:
        label, _, run_dir = item.partition("=")
        if not run_dir:
            parser.error(f"{item}: expected GA=RUN_DIR")
        row = {"ga": label, **measure(run_dir, args.diameter, args.friction_velocity, args.period)}
        row["seed"] = SEED_REGIME.get(int(float(label)), "") if label.replace(".", "").isdigit() else ""
        rows.append(row)
    print("| Ga | travelled / D | u_p / u_tau | highest rise / D | time clear of the bed | regime | the seed's |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['ga']} | {r['travelled_d']:.1f} | {r['speed_over_u_tau']:.2f} | {r['highest_rise_d']:.2f} | "
              f"{100 * r['time_clear']:.0f} % | {r['regime']} | {r['seed']} |")
    if args.out:
        with open(args.out, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
