"""Pressure drop across the fixed plug of scenes/ergun_plug.toml against Ergun's equation.

Reads a run's VTK frames (tools/riffle_tools/vtp.py) over a time window and, frame by frame:
  - the flux q through the plug: the rate at which the water right of the plug grows (a quadratic fit over the
    window), divided by the plug's cross-section;
  - the pressure drop: the mean pressure of the water just left of the plug minus that just right of it (15 mm
    wide windows, the plug's height less one spacing top and bottom, so the hydrostatic part cancels);
  - Ergun's drop at q, per bed length
        -dp/dx = 150 mu (1 - eps)^2 q / (eps^3 d^2) + 1.75 rho (1 - eps) q^2 / (eps^3 d),
    with the lattice's voidage 1 - pi/6 over the plug's length, and summed in series over the 5 mm slices with
    riffle's own voidage (which the smoothing raises in the slices at each face);
  - inside the plug, away from its faces by the voidage smoothing radius: the pressure gradient (a least-squares
    line through the water's pressures), the drag the water receives per volume (sum over the grains there of
    F/eps in the mixture reading, F in the pore reading), the water's mean x-velocity, and the velocity the grains
    sampled. Their ratios say where a departure from Ergun comes from: the water's momentum balance
    (gradient / drag), the sampling (sampled velocity / water's velocity) or the drag law (drag / Ergun).
Every ratio is the median over the frames (the pressure of a single frame carries the MPS pressure noise).

  tools/riffle-tools ergun-plug OUT_DIR [--window T0 T1] [--scene SCENE] [--check TOLERANCE]

--check makes the exit status 1 when the drop departs from Ergun's with the lattice voidage by more than the
tolerance (a fraction; docs/COUPLING.md derives 0.2). Needs numpy (Debian's python3-numpy).
"""
import argparse
import math
import pathlib
import sys

try:
    import numpy as np
    import tomllib

    from . import vtp
except ImportError as error:  # pragma: no cover
    sys.exit(f"ergun_plug: {error}; run with /usr/bin/python3 (Debian's python3-numpy)")

FACE_WINDOW = 0.015  # [m] width of the water sampled on each side of the plug for the drop


def ergun_gradient(q, eps, mu, rho, diameter):
    return (150 * mu * (1 - eps) ** 2 * q / (eps**3 * diameter**2)
            + 1.75 * rho * (1 - eps) * q * q / (eps**3 * diameter))


def scene_of(out_dir, explicit):
    if explicit:
        return pathlib.Path(explicit)
    path, named = vtp.run_scene(out_dir)
    if path is None:
        sys.exit(f"ergun_plug: {out_dir / 'riffle.log'} names no scene that exists ({named}); pass --scene")
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--window", nargs=2, type=float, default=(0.1, 0.45), metavar=("T0", "T1"))
    parser.add_argument("--scene", help="the run's scene (default: the one named in OUT_DIR/riffle.log)")
    parser.add_argument("--check", type=float, metavar="TOLERANCE",
                        help="exit 1 if |drop / Ergun (lattice voidage) - 1| exceeds this fraction")
    args = parser.parse_args(argv)
    run = pathlib.Path(args.out_dir)
    with open(scene_of(run, args.scene), "rb") as handle:
        scene = tomllib.load(handle)
    width = scene["tank"]["size"][1]
    fluid = scene.get("fluid", {})
    spacing = fluid["spacing"]
    rho, mu = fluid.get("density", 1000.0), fluid.get("viscosity", 1.0e-3)
    mixture = scene.get("coupling", {}).get("fluid_velocity", "pore") == "mixture"

    grain_frames = vtp.read_pvd(run / "solids.pvd")
    first = vtp.read_vtp(grain_frames[0][1], ["radius"])
    radius = float(first["radius"][0])
    diameter = 2 * radius
    plug_x0 = first["points"][:, 0].min() - radius
    plug_x1 = first["points"][:, 0].max() + radius
    height = first["points"][:, 2].max() + radius
    # The interior starts R_eps in from each face ([coupling] voidage_radius; 0 = max(3 l0, 2 d_max)).
    smoothing = scene.get("coupling", {}).get("voidage_radius", 0.0) or max(3 * spacing, 2 * diameter)
    inner_x0, inner_x1 = plug_x0 + smoothing, plug_x1 - smoothing
    lattice_eps = 1 - math.pi / 6

    rows = []
    fluid_frames = dict(vtp.read_pvd(run / "fluid.pvd"))
    for time, grain_path in grain_frames:
        if time not in fluid_frames:
            continue
        grains = vtp.read_vtp(grain_path, ["voidage", "drag_force", "fluid_velocity"])
        water = vtp.read_vtp(fluid_frames[time], ["kind", "pressure", "velocity"])
        is_water = water["kind"] == 0
        px, pz = water["points"][:, 0], water["points"][:, 2]
        level = is_water & (pz > spacing) & (pz < height - spacing)
        left = level & (px > plug_x0 - FACE_WINDOW) & (px < plug_x0)
        right = level & (px > plug_x1) & (px < plug_x1 + FACE_WINDOW)
        inner_water = is_water & (px > inner_x0) & (px < inner_x1) & (pz < height)
        gx = grains["points"][:, 0]
        inner_grains = (gx > inner_x0) & (gx < inner_x1)
        eps = grains["voidage"]
        drag_on_water = grains["drag_force"][inner_grains, 0] / (eps[inner_grains] if mixture else 1.0)
        rows.append(dict(
            time=time,
            right_volume=np.sum(is_water & (px > plug_x1)) * spacing**3,
            drop=water["pressure"][left].mean() - water["pressure"][right].mean(),
            gradient=-np.polyfit(px[inner_water], water["pressure"][inner_water], 1)[0],
            drag_density=drag_on_water.sum() / ((inner_x1 - inner_x0) * width * height),
            water_velocity=water["velocity"][inner_water, 0].mean(),
            sampled_velocity=grains["fluid_velocity"][inner_grains, 0].mean(),
            inner_eps=eps[inner_grains].mean(),
            slice_eps=[float(eps[np.isclose(gx, s)].mean()) for s in sorted(set(np.round(gx, 6)))],
        ))
    times = np.array([row["time"] for row in rows])
    window = (times >= args.window[0]) & (times <= args.window[1])
    if window.sum() < 5:
        sys.exit(f"ergun_plug: only {window.sum()} frames in the window {args.window}; need 5 or more")
    fit = np.polyfit(times[window], np.array([row["right_volume"] for row in rows])[window], 2)
    flux = np.polyval(np.polyder(fit), times[window]) / (height * width)
    used = [row for row, keep in zip(rows, window) if keep]

    def col(key):
        return np.array([row[key] for row in used])

    drop = col("drop")
    lattice = ergun_gradient(flux, lattice_eps, mu, rho, diameter) * (plug_x1 - plug_x0)
    probe = run / "probe_plug_faces.csv"
    if probe.exists():
        # Every step, hydrostatic part removed by the probe: the mean over the window beats the frames' noise.
        table = np.genfromtxt(probe, delimiter=",", names=True)
        in_window = (table["time_s"] >= args.window[0]) & (table["time_s"] <= args.window[1])
        left_mean = sum(table[f"p{k}_Pa"] for k in range(3)) / 3
        right_mean = sum(table[f"p{k}_Pa"] for k in range(3, 6)) / 3
        probe_drop = (left_mean - right_mean)[in_window]
        probe_flux = np.polyval(np.polyder(fit), table["time_s"][in_window]) / (height * width)
        probe_ergun = ergun_gradient(probe_flux, lattice_eps, mu, rho, diameter) * (plug_x1 - plug_x0)
        ratio = probe_drop.mean() / probe_ergun.mean()
        source = f"probe {probe.name}, {in_window.sum()} steps: means {probe_drop.mean():.0f} / {probe_ergun.mean():.0f} Pa"
    else:
        ratio = np.median(drop / lattice)
        source = f"frames: medians {np.median(drop):.0f} / {np.median(lattice):.0f} Pa"
    series = np.array([sum(ergun_gradient(q, e, mu, rho, diameter) * diameter for e in row["slice_eps"])
                       for q, row in zip(flux, used)])
    inner_ergun = ergun_gradient(col("water_velocity"), col("inner_eps"), mu, rho, diameter)
    print(f"plug x {plug_x0:.4f}-{plug_x1:.4f} m, {height * 1e3:.0f} mm high, {width * 1e3:.0f} mm across, "
          f"d = {diameter * 1e3:.1f} mm; reading: {'mixture' if mixture else 'pore'}")
    print("voidage per slice along the plug (last frame):", " ".join(f"{e:.3f}" for e in used[-1]["slice_eps"]))
    print(f"window {args.window[0]}-{args.window[1]} s ({len(used)} frames): flux {flux.min() * 1e3:.0f}-"
          f"{flux.max() * 1e3:.0f} mm/s")
    print(f"drop across the plug / Ergun, lattice voidage {lattice_eps:.3f}: {ratio:.3f} ({source}; "
          f"frame by frame, median {np.median(drop / lattice):.3f})")
    print(f"drop across the plug / Ergun, riffle's voidage per slice: {np.median(drop / series):.3f} "
          f"(Ergun {np.median(series):.0f} Pa)")
    print(f"inside (x {inner_x0:.3f}-{inner_x1:.3f}, voidage {col('inner_eps').mean():.3f}): "
          f"gradient / Ergun at the water's velocity {np.median(col('gradient') / inner_ergun):.3f} = "
          f"gradient / drag on the water {np.median(col('gradient') / col('drag_density')):.3f} x "
          f"drag / Ergun {np.median(col('drag_density') / inner_ergun):.3f}; "
          f"sampled / water velocity {np.median(col('sampled_velocity') / col('water_velocity')):.3f}")
    if args.check is not None:
        if abs(ratio - 1) > args.check:
            print(f"FAIL: the drop departs from Ergun's by {ratio - 1:+.1%}, more than {args.check:.0%}")
            return 1
        print(f"ok: the drop is within {args.check:.0%} of Ergun's ({ratio - 1:+.1%})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
