"""Where a sheared bed takes the water's stress, and how fast its grains move against the water they read, from a
run's solids frames (scenes/sheared_bed_*.toml: a lid driving water over a bed in a box periodic along x and y).

Per band of grain centres (--band, default 1 mm; band k holds k * band <= z < (k + 1) * band), averaged over the frames
with --from <= t <= --to (a frame within half the frames' median interval of --from or --to counts: frame times are
those of the steps, not the output's nominal times):
  grains          the free grains' number per frame (the fixed ones, a rough floor, are listed apart);
  fluid [Pa]      the streamwise force of the water on the band's grains (drag + pressure + viscous stress + added
                  mass + history, the solids frames' fields) over the plan area: the stress the band takes;
  from top [Pa]   the same summed from the top down to the band: the stress still carried by the water and the
                  grains above its lower edge;
  contact [Pa]    the band's contact (and lubrication) forces along x over the area (negative: the band passes its
                  load down);
  u_grain, u_read the free grains' mean x velocity (at rest or not) and the mean x velocity of the water they read
                  (fluid_velocity).
Then, against the bed top: the share of the water's force on the grains taken above the top, and in the first, second
and third diameter below it, and deeper. The bed top is where the count of centres, averaged over a diameter (which
evens out a packed bed's layers), first falls below half the packed bed's, going up from the densest height; the packed
bed's count is the 90th percentile of the averaged count over the heights that hold grains. The moving grains (speed
above --moving, the seed's 0.01 m/s) are summarised apart: their number per frame, their mean x velocity, the mean x
velocity of the water they read and their mean height above the bed top; likewise the free grains above the bed top
(at rest or not: the bed-load layer). And the force on the fixed grains from the
free ones along x (their contact and lubrication forces, less those between fixed grains, which cancel) plus the
water's on them, against the water's force on all grains (1: the floor carries the whole bed shear stress).

Usage: tools/riffle-tools bed-force-profile RUN_DIR --diameter D [--from T] [--to T] [--band B] [--area A]
           [--moving V] [--summary CSV --label L]
RUN_DIR holds solids.pvd. --area: the plan area [m^2] (default: the tank's x * y from the scene the run's riffle.log
names). --summary appends one row (label, frames, window, top, shares, floor, moving grains) to CSV, with a header
when the file is new. numpy only.
"""
import argparse
import csv
import os
import sys
import tomllib

import numpy as np

from . import vtp

FLUID_FORCES = ("drag_force", "pressure_force", "viscous_force", "added_mass_force", "history_force")
CONTACT_FORCES = ("contact_force", "lubrication_force")


class ProfileError(RuntimeError):
    """Frames this tool cannot read a bed from (the message says why)."""


def plan_area(run_dir):
    scene, named = vtp.run_scene(run_dir)
    if scene is None:
        raise ProfileError(f"{run_dir}/riffle.log names no scene that exists ({named}): pass --area")
    with open(scene, "rb") as handle:
        size = tomllib.load(handle)["tank"]["size"]
    return size[0] * size[1]


def x_sum(grains, names, count):
    """The x components of the named vector fields summed per grain; a field the frame lacks counts as zero."""
    return sum((grains[name][:, 0] for name in names if name in grains), np.zeros(count))


def load(run_dir, start, end):
    """(frames, window, per-grain arrays over the frames with start <= t <= end: heights, fluid x force, contact x
    force, x velocity, speed, x velocity read, fixed flag)."""
    listed = vtp.read_pvd(os.path.join(run_dir, "solids.pvd"))
    times = np.array([time for time, _ in listed])
    slack = 0.5 * np.median(np.diff(times)) if len(times) > 1 else 0.0
    chosen = [(time, path) for time, path in listed if start - slack <= time <= end + slack]
    if not chosen:
        raise ProfileError(f"no solids frame of {run_dir} lies between t = {start} and {end} s")
    fields = {key: [] for key in ("heights", "fluid", "contact", "velocity", "speed", "read", "fixed")}
    for _, path in chosen:
        grains = vtp.read_vtp(path)
        count = len(grains["points"])
        fields["heights"].append(grains["points"][:, 2])
        fields["fluid"].append(x_sum(grains, FLUID_FORCES, count))
        fields["contact"].append(x_sum(grains, CONTACT_FORCES, count))
        fields["velocity"].append(grains["velocity"][:, 0])
        fields["speed"].append(np.linalg.norm(grains["velocity"], axis=1))
        fields["read"].append(grains["fluid_velocity"][:, 0] if "fluid_velocity" in grains else np.full(count, np.nan))
        fields["fixed"].append(grains["fixed"] if "fixed" in grains else np.zeros(count, dtype=int))
    window = (chosen[0][0], chosen[-1][0])
    return len(chosen), window, {key: np.concatenate(value) for key, value in fields.items()}


def bed_top(heights, diameter):
    """The bed top (the module's text), interpolated linearly between the two heights that straddle half the packed
    count. The averaged count falls to zero a diameter above the highest centre, so there is always one."""
    if heights.size == 0:
        raise ProfileError("no grains: no bed top")
    width = diameter / 8
    edges = np.arange(heights.min() - diameter, heights.max() + diameter + width, width)  # the averaging's margins
    counts, _ = np.histogram(heights, edges)
    smooth = np.convolve(counts, np.ones(9) / 9, mode="same")  # centred: 4 bins each side, 9/8 of a diameter
    centres = 0.5 * (edges[:-1] + edges[1:])
    half = 0.5 * np.percentile(smooth[counts > 0], 90)
    densest = int(np.argmax(smooth))
    thin = np.where((np.arange(len(smooth)) > densest) & (smooth < half))[0]
    below = thin[0] - 1
    return centres[below] + width * (smooth[below] - half) / (smooth[below] - smooth[thin[0]])


def profile(run_dir, diameter, start=-np.inf, end=np.inf, band=0.001, area=None, moving_speed=0.01):
    """The bands, the bed top, the shares, the floor and the moving grains (the module's text) as a dict."""
    area = area or plan_area(run_dir)
    frames, window, g = load(run_dir, start, end)
    heights, fluid, contact, fixed = g["heights"], g["fluid"], g["contact"], g["fixed"]
    free = fixed == 0
    per = frames * area
    which = np.floor(heights / band).astype(int)
    rows = []
    for index in np.unique(which):
        inside = which == index
        mover = inside & free
        rows.append({"z_low": index * band, "grains": mover.sum() / frames, "fixed": (inside & ~free).sum() / frames,
                     "fluid": fluid[inside].sum() / per, "contact": contact[inside].sum() / per,
                     "u_grain": g["velocity"][mover].mean() if mover.any() else np.nan,
                     "u_read": g["read"][mover].mean() if mover.any() else np.nan})
    carried = np.cumsum([row["fluid"] for row in rows][::-1])[::-1]
    for row, above in zip(rows, carried):
        row["from_top"] = above
    top = bed_top(heights, diameter)
    layers = [fluid[heights > top].sum()]
    layers += [fluid[(heights <= top - k * diameter) & (heights > top - (k + 1) * diameter)].sum() for k in range(3)]
    layers += [fluid[heights <= top - 3 * diameter].sum()]
    moving = free & (g["speed"] > moving_speed)
    result = {"frames": frames, "window": window, "total": fluid.sum() / per, "rows": rows, "top": top,
              "shares": np.array(layers) / fluid.sum(), "floor": None, "floor_Pa": None,
              "moving": moving.sum() / frames,
              "moving_u": g["velocity"][moving].mean() if moving.any() else np.nan,
              "moving_read": g["read"][moving].mean() if moving.any() else np.nan,
              "moving_height": heights[moving].mean() - top if moving.any() else np.nan}
    above = free & (heights > top)
    result.update({"above": above.sum() / frames, "above_u": g["velocity"][above].mean() if above.any() else np.nan,
                   "above_read": g["read"][above].mean() if above.any() else np.nan})
    if (~free).any():
        # The fixed grains' contacts among themselves cancel in the sum; what remains is the free grains' push.
        held = (contact[~free].sum() + fluid[~free].sum()) / per
        result["floor_Pa"], result["floor"] = held, held / result["total"]
    return result


SUMMARY_COLUMNS = ("label", "frames", "t_first_s", "t_last_s", "fluid_on_grains_Pa", "bed_top_mm", "share_above_top",
                   "share_first_d", "share_second_d", "share_third_d", "share_deeper", "floor_over_fluid",
                   "moving_per_frame", "moving_u_m_per_s", "moving_read_m_per_s", "moving_height_above_top_mm",
                   "above_top_per_frame", "above_top_u_m_per_s", "above_top_read_m_per_s")


def summary_row(label, result):
    return [label, result["frames"], f"{result['window'][0]:.6g}", f"{result['window'][1]:.6g}",
            f"{result['total']:.4f}", f"{result['top'] * 1e3:.3f}", *(f"{share:.4f}" for share in result["shares"]),
            "" if result["floor"] is None else f"{result['floor']:.4f}", f"{result['moving']:.1f}",
            f"{result['moving_u']:.4f}", f"{result['moving_read']:.4f}", f"{result['moving_height'] * 1e3:.3f}",
            f"{result['above']:.1f}", f"{result['above_u']:.4f}", f"{result['above_read']:.4f}"]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--diameter", type=float, required=True, help="the grain diameter [m]")
    parser.add_argument("--from", dest="start", type=float, default=-np.inf)
    parser.add_argument("--to", dest="end", type=float, default=np.inf)
    parser.add_argument("--band", type=float, default=0.001)
    parser.add_argument("--area", type=float)
    parser.add_argument("--moving", type=float, default=0.01, help="the moving grains' speed threshold [m/s]")
    parser.add_argument("--summary", help="append the summary row to this csv")
    parser.add_argument("--label", default="", help="the summary row's first column")
    args = parser.parse_args(argv)
    try:
        result = profile(args.run_dir, args.diameter, args.start, args.end, args.band, args.area, args.moving)
    except (ProfileError, vtp.VtpError, OSError) as error:
        sys.exit(f"bed_force_profile: {error}")
    print(f"# {args.run_dir}: {result['frames']} frames, t = {result['window'][0]:.4f} to {result['window'][1]:.4f} s;"
          f" the water's force on the grains over the area {result['total']:.3f} Pa")
    print("z_low_mm grains fixed fluid_Pa from_top_Pa contact_Pa u_grain u_read")
    for row in result["rows"]:
        print(f"{row['z_low'] * 1e3:.2f} {row['grains']:.1f} {row['fixed']:.1f} {row['fluid']:.3f} "
              f"{row['from_top']:.3f} {row['contact']:.3f} {row['u_grain']:.4f} {row['u_read']:.4f}")
    shares = result["shares"]
    print(f"# bed top {result['top'] * 1e3:.2f} mm; share of the water's force: above the top {shares[0]:.3f}, "
          f"first diameter {shares[1]:.3f}, second {shares[2]:.3f}, third {shares[3]:.3f}, deeper {shares[4]:.3f}")
    print(f"# moving grains (speed > {args.moving} m/s): {result['moving']:.1f} per frame, x velocity "
          f"{result['moving_u']:.4f} m/s, reading water at {result['moving_read']:.4f} m/s, "
          f"{result['moving_height'] * 1e3:.2f} mm above the bed top on average")
    print(f"# free grains above the bed top: {result['above']:.1f} per frame, x velocity {result['above_u']:.4f} m/s, "
          f"reading water at {result['above_read']:.4f} m/s")
    if result["floor"] is not None:
        print(f"# the fixed grains hold {result['floor_Pa']:.3f} Pa ({result['floor']:.3f} of the water's force on the "
              "grains)")
    if args.summary:
        new = not os.path.exists(args.summary) or os.path.getsize(args.summary) == 0
        with open(args.summary, "a", newline="") as handle:
            writer = csv.writer(handle)
            if new:
                writer.writerow(SUMMARY_COLUMNS)
            writer.writerow(summary_row(args.label, result))


if __name__ == "__main__":
    sys.exit(main())
