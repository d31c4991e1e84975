#!/usr/bin/python3
"""Where a sheared bed takes the water's stress, and how fast its grains move against the water they read, from a
run's solids frames (scenes/sheared_bed_*.toml: a lid driving water over a bed in a box periodic along x and y).

Per band of grain centres (--band, default 1 mm), averaged over the frames with --from <= t <= --to:
  grains          the free grains' number per frame (the fixed ones, a rough floor, are listed apart);
  fluid [Pa]      the streamwise force of the water on the band's grains (drag + pressure + viscous stress + added
                  mass + history, the solids frames' fields) over the plan area: the stress the band takes;
  from top [Pa]   the same summed from the top down to the band: the stress still carried by the water and the
                  grains above its lower edge;
  contact [Pa]    the band's contact forces along x over the area (negative: the band passes its load down);
  u_grain, u_read the free grains' mean x velocity and the mean x velocity of the water they read (fluid_velocity).
Then the share of the water's force on the grains taken above the bed top, and in the first, second and third
diameter below it; the bed top is the height where the number of centres, averaged over a diameter, falls below half
that of the bed one to three diameters above the lowest centre. And the fixed grains' contact force
along x over the area against the water's force on all grains (1: the floor carries the whole bed shear stress).

Usage: /usr/bin/python3 tools/bed_force_profile.py RUN_DIR --diameter D [--from T] [--to T] [--band B] [--area A]
RUN_DIR holds solids.pvd. --area: the plan area [m^2] (default: the tank's x * y from the scene the run's riffle.log
names). numpy only.
"""
import argparse
import os
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np  # noqa: E402
import vtp  # noqa: E402

FLUID_FORCES = ("drag_force", "pressure_force", "viscous_force", "added_mass_force", "history_force")


def plan_area(run_dir):
    scene, named = vtp.run_scene(run_dir)
    if scene is None:
        sys.exit(f"bed_force_profile: {run_dir}/riffle.log names no scene that exists ({named}): pass --area")
    with open(scene, "rb") as handle:
        size = tomllib.load(handle)["tank"]["size"]
    return size[0] * size[1]


def load(run_dir, start, end):
    """(frames, heights, fluid x force, contact x force, x velocity, x velocity read, fixed flag), one entry per grain
    per frame with start <= t <= end. A force field a frame lacks (older runs) counts as zero."""
    frames = [path for time, path in vtp.read_pvd(os.path.join(run_dir, "solids.pvd")) if start <= time <= end]
    if not frames:
        sys.exit(f"bed_force_profile: no solids frame of {run_dir} lies between t = {start} and {end} s")
    heights, fluid, contact, velocity, read, fixed = [], [], [], [], [], []
    for path in frames:
        grains = vtp.read_vtp(path)
        count = len(grains["points"])
        heights.append(grains["points"][:, 2])
        fluid.append(sum((grains[name][:, 0] for name in FLUID_FORCES if name in grains), np.zeros(count)))
        contact.append(grains["contact_force"][:, 0] if "contact_force" in grains else np.zeros(count))
        velocity.append(grains["velocity"][:, 0])
        read.append(grains["fluid_velocity"][:, 0] if "fluid_velocity" in grains else np.full(count, np.nan))
        fixed.append(grains["fixed"] if "fixed" in grains else np.zeros(count, dtype=int))
    return len(frames), *map(np.concatenate, (heights, fluid, contact, velocity, read, fixed))


def bed_top(heights, diameter):
    """The height where the count of centres, averaged over a diameter (which evens out the layers of a packed bed),
    falls below half that of the bed a diameter to three above the lowest centre."""
    width = diameter / 8
    edges = np.arange(heights.min(), heights.max() + width, width)
    counts, _ = np.histogram(heights, edges)
    smooth = np.convolve(counts, np.ones(8) / 8, mode="same")
    centres = 0.5 * (edges[:-1] + edges[1:])
    lowest = heights.min()
    bulk = smooth[(centres >= lowest + diameter) & (centres < lowest + 3 * diameter)].mean()
    thin = np.where((centres >= lowest + 3 * diameter) & (smooth < 0.5 * bulk))[0]
    return centres[thin[0]] if thin.size else edges[-1]


def profile(run_dir, diameter, start=-np.inf, end=np.inf, band=0.001, area=None):
    """The bands, the bed top and the shares (the module's text) as a dict."""
    area = area or plan_area(run_dir)
    frames, heights, fluid, contact, velocity, read, fixed = load(run_dir, start, end)
    free = fixed == 0
    per = frames * area
    edges = np.arange(0.0, heights.max() + band, band)
    which = np.digitize(heights, edges) - 1
    rows = []
    for index in range(len(edges) - 1):
        inside = which == index
        if not inside.any():
            continue
        moving = inside & free
        rows.append({"z_low": edges[index], "grains": moving.sum() / frames, "fixed": (inside & ~free).sum() / frames,
                     "fluid": fluid[inside].sum() / per, "contact": contact[inside].sum() / per,
                     "u_grain": velocity[moving].mean() if moving.any() else np.nan,
                     "u_read": read[moving].mean() if moving.any() else np.nan})
    carried = np.cumsum([row["fluid"] for row in rows][::-1])[::-1]
    for row, above in zip(rows, carried):
        row["from_top"] = above
    top = bed_top(heights, diameter)
    layers = [fluid[heights > top].sum()]
    layers += [fluid[(heights <= top - k * diameter) & (heights > top - (k + 1) * diameter)].sum() for k in range(3)]
    layers += [fluid[heights <= top - 3 * diameter].sum()]
    return {"frames": frames, "total": fluid.sum() / per, "rows": rows, "top": top,
            "shares": np.array(layers) / fluid.sum(),
            "floor": contact[~free].sum() / fluid.sum() if (~free).any() else None,
            "floor_Pa": contact[~free].sum() / per if (~free).any() else None}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--diameter", type=float, required=True, help="the grain diameter [m]")
    parser.add_argument("--from", dest="start", type=float, default=-np.inf)
    parser.add_argument("--to", dest="end", type=float, default=np.inf)
    parser.add_argument("--band", type=float, default=0.001)
    parser.add_argument("--area", type=float)
    args = parser.parse_args()
    result = profile(args.run_dir, args.diameter, args.start, args.end, args.band, args.area)
    print(f"# {args.run_dir}: {result['frames']} frames; the water's force on the grains over the area "
          f"{result['total']:.3f} Pa")
    print("z_low_mm grains fixed fluid_Pa from_top_Pa contact_Pa u_grain u_read")
    for row in result["rows"]:
        print(f"{row['z_low'] * 1e3:.2f} {row['grains']:.1f} {row['fixed']:.1f} {row['fluid']:.3f} "
              f"{row['from_top']:.3f} {row['contact']:.3f} {row['u_grain']:.4f} {row['u_read']:.4f}")
    shares = result["shares"]
    print(f"# bed top {result['top'] * 1e3:.2f} mm; share of the water's force: above the top {shares[0]:.3f}, "
          f"first diameter {shares[1]:.3f}, second {shares[2]:.3f}, third {shares[3]:.3f}, deeper {shares[4]:.3f}")
    if result["floor"] is not None:
        print(f"# the fixed grains' contact force over the area {result['floor_Pa']:.3f} Pa "
              f"({result['floor']:.3f} of the water's force on the grains)")


if __name__ == "__main__":
    main()
