"""Writes a [tank.motion] kind = "table" CSV (docs/SCENES.md) of riffle's sinusoid, sampled at a number of points
per period: x(t) = -A r(tau) sin(2 pi f tau + phase), tau = t - start_time, r the C2 quintic ramp over ramp_time
(systems/physics/tank_kinematics.cpp), so that a table run can be compared with the analytic one.

  tools/riffle-tools motion-table --amplitude 0.01 --frequency 1.7 --ramp-time 0.5882 --until 5.9 \
      --points-per-period 200 > scenes/sloshing_table.csv
"""
import argparse
import math
import sys

from .tank_motion import SinusoidalMotion


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--amplitude", type=float, required=True, help="A [m]")
    parser.add_argument("--frequency", type=float, required=True, help="f [Hz]")
    parser.add_argument("--ramp-time", type=float, default=0.0, help="[s]")
    parser.add_argument("--phase", type=float, default=0.0, help="[deg]")
    parser.add_argument("--start-time", type=float, default=0.0, help="[s]")
    parser.add_argument("--until", type=float, required=True, help="last time [s] (the table covers it)")
    parser.add_argument("--points-per-period", type=int, default=200)
    parser.add_argument("--axis", choices=["x", "y", "z"], default="x")
    args = parser.parse_args(argv)
    motion = SinusoidalMotion(args.amplitude, args.frequency, args.ramp_time, math.radians(args.phase),
                              args.start_time)
    h = 1.0 / (args.frequency * args.points_per_period)
    rows = int(math.ceil(args.until / h)) + 1
    out = sys.stdout
    out.write("# riffle sinusoid: A = %g m, f = %g Hz, ramp_time = %g s, phase = %g deg, start_time = %g s, "
              "%d points per period\n" % (args.amplitude, args.frequency, args.ramp_time, args.phase,
                                          args.start_time, args.points_per_period))
    out.write("t,%s\n" % args.axis)
    for i in range(rows):
        t = i * h
        x, _, _ = motion.at(t)
        out.write("%.17g,%.17g\n" % (t, x))


if __name__ == "__main__":
    sys.exit(main())
