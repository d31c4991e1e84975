#!/usr/bin/env python3
"""Pressure drop across the fixed plug of scenes/ergun_plug.toml against Ergun's equation.

Reads a run's VTK frames (tools/vtp.py): the flux q through the plug from the rate at which the water right of the
plug grows (a quadratic fit over the window, divided by the plug's cross-section), the pressure drop as the mean
pressure of the water just left of the plug minus that just right of it (same heights, so the hydrostatic part
cancels), and the grains' voidage per 5 mm slice along the plug. Ergun (per bed length):
  -dp/dx = 150 mu (1 - eps)^2 q / (eps^3 d^2) + 1.75 rho (1 - eps) q^2 / (eps^3 d)
evaluated with the lattice's voidage 1 - pi/6, and summed in series over the slices with riffle's own voidage.

  /usr/bin/python3 tools/ergun_plug.py OUT_DIR [--window T0 T1]
Needs numpy (Debian's python3-numpy).
"""
import argparse
import math
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
try:
    import numpy as np
    import vtp
except ImportError as error:  # pragma: no cover
    sys.exit(f"ergun_plug: {error}; run with /usr/bin/python3 (Debian's python3-numpy)")

# The scene's geometry and fluid (scenes/ergun_plug.toml).
PLUG_X0, PLUG_X1, PLUG_HEIGHT, WIDTH, SPACING = 0.08, 0.16, 0.04, 0.02, 0.005
RHO, MU, DIAMETER = 1000.0, 1.0e-3, 0.005


def ergun_gradient(q, eps):
    return 150 * MU * (1 - eps) ** 2 * q / (eps**3 * DIAMETER**2) + 1.75 * RHO * (1 - eps) * q * q / (eps**3 * DIAMETER)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--window", nargs=2, type=float, default=(0.1, 0.45), metavar=("T0", "T1"))
    args = parser.parse_args(argv)
    run = pathlib.Path(args.out_dir)
    grains = vtp.read_vtp(vtp.read_pvd(run / "solids.pvd")[-1][1], ["voidage"])
    x, eps = grains["points"][:, 0], grains["voidage"]
    slices = sorted(set(np.round(x, 6)))
    slice_eps = [float(eps[np.isclose(x, s)].mean()) for s in slices]
    times, right_volume, drop = [], [], []
    for time, path in vtp.read_pvd(run / "fluid.pvd"):
        frame = vtp.read_vtp(path, ["kind", "pressure"])
        fluid = frame["kind"] == 0
        px, pz = frame["points"][:, 0], frame["points"][:, 2]
        level = fluid & (pz > SPACING) & (pz < PLUG_HEIGHT - SPACING)
        left = level & (px > PLUG_X0 - 0.015) & (px < PLUG_X0)
        right = level & (px > PLUG_X1) & (px < PLUG_X1 + 0.015)
        times.append(time)
        right_volume.append(np.sum(fluid & (px > PLUG_X1)) * SPACING**3)
        drop.append(frame["pressure"][left].mean() - frame["pressure"][right].mean())
    times, right_volume, drop = map(np.array, (times, right_volume, drop))
    window = (times >= args.window[0]) & (times <= args.window[1])
    fit = np.polyfit(times[window], right_volume[window], 2)
    flux = np.polyval(np.polyder(fit), times[window]) / (PLUG_HEIGHT * WIDTH)
    series = np.array([sum(ergun_gradient(q, e) * SPACING for e in slice_eps) for q in flux])
    lattice = ergun_gradient(flux, 1 - math.pi / 6) * (PLUG_X1 - PLUG_X0)
    measured = drop[window].mean()
    print("voidage per 5 mm slice along the plug:", " ".join(f"{e:.3f}" for e in slice_eps))
    print(f"window {args.window[0]}-{args.window[1]} s: flux {flux.min()*1e3:.0f}-{flux.max()*1e3:.0f} mm/s; "
          f"pressure drop {measured:.0f} Pa; Ergun with riffle's voidage {series.mean():.0f} Pa "
          f"({measured / series.mean() - 1:+.1%}), with the lattice's {lattice.mean():.0f} Pa "
          f"({measured / lattice.mean() - 1:+.1%})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
