"""Bulk-failure load of a (rigid or mobile) bed: for each grain frame after the start-up ramp, the cumulative
horizontal load ratio R(z) = sum over the grains above depth z of (F_px + F_dx - m a_tank) / sum (m g - F_pz - F_dz);
its largest |R| over the frames and its mean, by depth. A grain is above depth z when its centre lies less than z
below the local bed surface (the 90th percentile of the grain tops in 20 mm bins along the tank).

Usage: tools/riffle-tools mobilisation-load-depth OUT_DIR [OUT_DIR ...]
"""
import argparse
import pathlib
import sys

import numpy as np

from .. import vtp
from . import add_motion_arguments, motion_of

G = 9.81
DEPTHS = [0.005, 0.01, 0.02, 0.03, 0.045]
TANK_LENGTH = 0.24  # [m] the seed tank's


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", metavar="OUT_DIR", help="a coupled run's output directory (solids.pvd)")
    add_motion_arguments(parser)
    args = parser.parse_args(argv)
    motion = motion_of(args)
    depths = DEPTHS
    for run in args.runs:
        out = pathlib.Path(run)
        frames = vtp.read_pvd(out / "solids.pvd")
        Rmax = np.zeros(len(depths))
        rows = []
        for t, path in frames:
            if t < motion.ramp_time + 1e-9:
                continue
            xt, _, a = motion.at(t)
            s = vtp.read_vtp(path, ["radius", "mass", "drag_force", "pressure_force"])
            p = s["points"].copy()
            p[:, 0] -= xt
            r = s["radius"]
            m = s["mass"]
            edges = np.linspace(0, TANK_LENGTH, 13)
            ib = np.clip(np.digitize(p[:, 0], edges)-1, 0, 11)
            top = p[:, 2] + r
            surf = np.array([np.percentile(top[ib == b], 90) for b in range(12)])
            depth = np.interp(p[:, 0], 0.5*(edges[1:]+edges[:-1]), surf) - p[:, 2]
            load = s["pressure_force"][:, 0] + s["drag_force"][:, 0] - m*a
            weight = m*G - s["pressure_force"][:, 2] - s["drag_force"][:, 2]
            R = np.array([load[depth < z].sum()/weight[depth < z].sum() for z in depths])
            Rmax = np.maximum(Rmax, np.abs(R))
            rows.append(R)
        rows = np.array(rows)
        print(f"{run}: max over {len(rows)} frames of |cumulative horizontal load / submerged weight| above depth")
        print("   " + "  ".join(f"{z*1e3:4.0f} mm: {v:5.3f}" for z, v in zip(depths, Rmax)))
        print("   mean |R|: " + "  ".join(f"{v:5.3f}" for v in np.abs(rows).mean(axis=0)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
