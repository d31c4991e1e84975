"""The whole bed's horizontal load budget per grain frame, with the tank's exact kinematics (start-up ramp included):
sums over ALL grains, over the total submerged weight (m g - F_pz - F_dz summed): pressure x, drag x, -m a (the
tank-frame inertia), and the net load F_p + F_d - m a (what the contacts with the walls and the floor must supply,
sign flipped); beside it the grains' mean x-velocity relative to the tank (volume weighted) and its largest size.

Usage: tools/riffle-tools mobilisation-load-budget OUT_DIR [T0/T T1/T]   (frames with t/T in [T0/T, T1/T])
"""
import argparse
import math
import pathlib
import sys

import numpy as np

from .. import vtp
from . import add_motion_arguments, motion_of

G = 9.81


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", metavar="OUT_DIR", help="a coupled run's output directory (solids.pvd)")
    parser.add_argument("t0", type=float, nargs="?", default=0, metavar="T0/T", help="first t/T (default 0)")
    parser.add_argument("t1", type=float, nargs="?", default=99, metavar="T1/T", help="last t/T (default 99)")
    add_motion_arguments(parser)
    args = parser.parse_args(argv)
    motion = motion_of(args)
    f = motion.frequency
    run, t0, t1 = args.run, args.t0, args.t1
    frames = vtp.read_pvd(pathlib.Path(run) / "solids.pvd")
    print(f"{run}\n  t/T    a/g  | Fpx    Fdx    -ma    net  (/ submerged weight) | u_s rel tank (mm/s) mean, max|.|")
    for t, path in frames:
        if not (t0 <= t*f <= t1):
            continue
        x, v, a = motion.at(t)
        s = vtp.read_vtp(path, ["radius", "mass", "drag_force", "pressure_force", "velocity"])
        m = s["mass"]
        V = 4/3*math.pi*s["radius"]**3
        W = (m*G - s["pressure_force"][:, 2] - s["drag_force"][:, 2]).sum()
        Fp = s["pressure_force"][:, 0].sum()/W
        Fd = s["drag_force"][:, 0].sum()/W
        I = -(m.sum()*a)/W  # noqa: E741
        us = s["velocity"][:, 0] - v
        print(f"  {t*f:4.2f} {a/G:+.3f} | {Fp:+.3f} {Fd:+.3f} {I:+.3f} {Fp+Fd+I:+.3f} | "
              f"{np.average(us, weights=V)*1e3:+7.1f} {np.abs(us).max()*1e3:6.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
