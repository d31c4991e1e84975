"""Hindered settling in a closed column against Richardson & Zaki (1954) (docs/COUPLING.md, "Hindered settling").

A suspension of equal 3 mm beads (1100 kg/m^3) in a liquid of 1000 kg/m^3 and 0.2 Pa s fills z = 10-130 mm of a
60 x 60 mm column (water to 160 mm, l0 = 5 mm) by random sequential addition, at rest. The bulk speed is the
grains' mean downward velocity relative to the water's local velocity (the flux the model's continuity conserves:
zero section mean in the closed column) in the band z = 60-80 mm, averaged over t = 0.15-0.3 s by default: with the
history force (on by default) each bead is held back while its memory lasts, 13 % at phi = 0.05 over the early
window t = 0.032-0.1 s (`--window 0.032,0.1`, where the beads without it have relaxed and the suspension's top has
moved less than 0.2 mm), below 0.5 % from 0.15 s on, once the other beads' screening has cut it; the speed in the column's frame is printed too (it
carries the water's transient and a slow wall circulation: tests/verification/coupling/hindered_settling_test.cpp),
and the speed relative to the water the drag saw (the sampled velocity less the grain's own disturbance, the
self-induced correction's "undisturbed" velocity). Richardson-Zaki's hindered speed is the grains' speed in the
vessel's frame; the sampled water holds each grain's own disturbance, which grows as l0 shrinks, so the bulk speed
relative to it drifts from Richardson-Zaki with refinement by construction (docs/cases/settling.md).
Richardson-Zaki is evaluated at the suspension's solid fraction (grain centres in z = 30-110 mm), which the fill
makes 2-4 % above the nominal one. Richardson-Zaki: u = u_t eps^n with n = 4.65 (Re_t < 0.2,
d/D -> 0) and u_t the Schiller-Naumann terminal speed of a lone bead (the law riffle's drag uses as eps -> 1).
The same scene as tests/verification/coupling/hindered_settling_test.cpp (which runs phi = 0.05 and 0.1).

  tools/riffle-tools hindered-settling build/riffle [work-dir] [--phi 0.05,0.1,0.2,0.3]
      [--readings mixture,pore] [--extra 'voidage_estimate = "cloud_in_cell"'] [--window 0.15,0.3]

Prints a markdown table (phi, Re_t, RZ speed, the three speeds and their errors, band voidage) per reading.
"""
import argparse
import csv
import math
import os
import subprocess
import sys


DIAMETER, SOLID_DENSITY, DENSITY, VISCOSITY, GRAVITY = 0.003, 1100.0, 1000.0, 0.2, 9.81
COLUMN, FILL_LOW, FILL_HIGH = 0.06, 0.01, 0.13
BAND = (0.06, 0.08)
# The averaging window [s]: late enough that the suspension has screened each bead's memory (the history force's
# transient below 0.5 %), as tests/verification/coupling/hindered_settling_test.cpp's kLate.
LATE_WINDOW = (0.15, 0.3)


def terminal_speed():
    weight = (SOLID_DENSITY - DENSITY) * GRAVITY * math.pi / 6.0 * DIAMETER ** 3
    u = weight / (3.0 * math.pi * VISCOSITY * DIAMETER)
    for _ in range(100):
        reynolds = DENSITY * u * DIAMETER / VISCOSITY
        u = weight / (3.0 * math.pi * VISCOSITY * DIAMETER * (1.0 + 0.15 * reynolds ** 0.687))
    return u


def richardson_zaki_exponent(reynolds):
    """Richardson & Zaki (1954) for d/D -> 0."""
    if reynolds < 0.2:
        return 4.65
    if reynolds < 1.0:
        return 4.35 * reynolds ** -0.03
    if reynolds < 500.0:
        return 4.45 * reynolds ** -0.1
    return 2.39


def fill(count):
    """The walled column's beads: riffle's random sequential addition (whole beads inside the box)."""
    return f"""[[solids.fills]]
min = [0.0, 0.0, {FILL_LOW}]
max = [0.06, 0.06, {FILL_HIGH}]
seed = 5
[[solids.fills.classes]]
diameter = {DIAMETER}
count = {count}
material = "bead"
"""


def periodic_spheres(count, seed=5):
    """The periodic column's beads, listed: random sequential addition with the nearest image across x and y, so
    that the suspension is uniform across the seams too (riffle's fills keep whole beads inside the box, which would
    leave a slab one diameter wide without beads along each seam)."""
    import numpy as np
    rng = np.random.default_rng(seed)
    radius = DIAMETER / 2.0
    cells = int(COLUMN // DIAMETER)  # cells at least a diameter wide: an overlap lies in the 27 around a cell
    cell = COLUMN / cells
    grid = {}
    centres = []

    def neighbours(key):
        """The beads placed in the 27 cells around `key` (wrapped across x and y)."""
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    yield from grid.get(((key[0] + dx) % cells, (key[1] + dy) % cells, key[2] + dz), ())

    def overlaps(c, other):
        offset = c - other
        offset[:2] -= COLUMN * np.round(offset[:2] / COLUMN)  # the nearest image across the seams
        return offset @ offset < DIAMETER * DIAMETER
    tries = 0
    while len(centres) < count:
        tries += 1
        if tries > 1000 * count:
            raise RuntimeError(f"random sequential addition stalled at {len(centres)} of {count} beads")
        c = np.array([rng.uniform(0.0, COLUMN), rng.uniform(0.0, COLUMN),
                      rng.uniform(FILL_LOW + radius, FILL_HIGH - radius)])
        key = (int(c[0] // cell) % cells, int(c[1] // cell) % cells, int(c[2] // DIAMETER))
        if not any(overlaps(c, other) for other in neighbours(key)):
            grid.setdefault(key, []).append(c)
            centres.append(c)
    return "".join(f"""[[solids.spheres]]
position = [{c[0]:.9g}, {c[1]:.9g}, {c[2]:.9g}]
radius = {radius}
material = "bead"
""" for c in centres)


def scene(phi, reading, extra, spacing=0.005, window=LATE_WINDOW, periodic=False, fluid_extra=""):
    count = round(phi * COLUMN * COLUMN * (FILL_HIGH - FILL_LOW) / (math.pi / 6.0 * DIAMETER ** 3))
    # Periodic across: no side walls, so no wall layer thinner in beads and no circulation (down in the middle, up at
    # the walls) carrying the beads in the column's frame; Richardson-Zaki's d/D -> 0. A periodic box needs a contact
    # law (its rebuild wraps the grains): soft, for beads that almost never touch at these fractions.
    across = """periodic = ["x", "y"]
[contact]
law = "hertz_mindlin"
restitution = 0.5
friction = 0.3
max_impact_speed = 0.01
""" if periodic else ""
    # Soft (2e4 Pa), so that the fluid step's 8 sub-steps stay inside the contact's stability estimate.
    elastic = "young_modulus = 2.0e4\npoisson_ratio = 0.3\n" if periodic else ""
    return f"""
[run]
name = "hindered_settling"
end_time = {window[1] + 1e-3}
dt = 2.0e-3
solid_substeps = 8
[materials.bead]
density = {SOLID_DENSITY}
{elastic}[materials.glass]
density = 2500.0
{elastic}[tank]
size = [0.06, 0.06, 0.18]
open_faces = ["z_max"]
wall_material = "glass"
{across}[solids]
{periodic_spheres(count) if periodic else fill(count)}[fluid]
spacing = {spacing}
density = {DENSITY}
kinematic_viscosity = {VISCOSITY / DENSITY}
{fluid_extra}
[[fluid.boxes]]
low = [0.0, 0.0, 0.0]
high = [0.06, 0.06, 0.16]
[coupling]
fluid_velocity = "{reading}"
{extra}
[output]
vtk_interval = 0.004
"""


def bulk_speed(run_dir, window=LATE_WINDOW):
    """The band's grains: mean downward speed relative to the water's local velocity (the flux the model's
    continuity conserves, zero section mean in a closed column), mean downward speed in the column's frame, mean
    voidage, averaged over the frames in the window; and the suspension's solid fraction (centres in z = 30-110 mm
    at the window's start)."""
    import numpy as np
    from . import vtp
    relative, undisturbed, lab, voidage, truth = [], [], [], [], None
    volume = math.pi / 6.0 * DIAMETER ** 3
    for time, path in vtp.read_pvd(os.path.join(run_dir, "solids.pvd")):
        if time < window[0] - 1e-9 or time > window[1] + 1e-9:
            continue
        frame = vtp.read_vtp(path)
        z = frame["points"][:, 2]
        if truth is None:
            truth = np.count_nonzero(np.abs(z - 0.07) < 0.04) * volume / (COLUMN * COLUMN * 0.08)
        band = (z >= BAND[0]) & (z <= BAND[1])
        u_s, u = frame["velocity"][band, 2], frame["fluid_velocity"][band, 2]
        relative.append(-(u_s - u).mean())
        # The water the drag saw: the sampled velocity less the grain's own disturbance (the self-induced correction;
        # equal to the sampled one without it).
        undisturbed.append(-(u_s - frame["undisturbed_velocity"][band, 2]).mean())
        lab.append(-u_s.mean())
        voidage.append(frame["voidage"][band].mean())
    mean = lambda values: sum(values) / len(values)
    return mean(relative), mean(undisturbed), mean(lab), mean(voidage), truth


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("riffle")
    parser.add_argument("work", nargs="?", default="out/hindered_settling")
    parser.add_argument("--phi", default="0.05,0.1,0.2,0.3")
    parser.add_argument("--readings", default="mixture,pore")
    parser.add_argument("--extra", default="", help="more [coupling] lines")
    parser.add_argument("--fluid", default="", help="more [fluid] lines, e.g. 'initial_arrangement = \"packed\"'")
    parser.add_argument("--threads", default="1")
    parser.add_argument("--spacings", default="0.005",
                        help="l0 [m], comma-separated (each a divisor of the 60 x 60 x 180 mm column: 0.01, 0.0075, "
                             "0.005, 0.004, 0.003, 0.0025): the same suspension at each, for the convergence in l0")
    parser.add_argument("--periodic", action="store_true",
                        help="the column periodic along x and y (no side walls: no wall circulation, d/D -> 0)")
    parser.add_argument("--window", default=f"{LATE_WINDOW[0]},{LATE_WINDOW[1]}",
                        help="averaging window t0,t1 [s] (the run ends at t1); 0.032,0.1 is the early window, where "
                             "the history force's transient still holds the beads back")
    args = parser.parse_args(argv)
    window = tuple(float(t) for t in args.window.split(","))
    if len(window) != 2 or not 0.0 <= window[0] < window[1]:
        parser.error(f"--window wants t0,t1 with 0 <= t0 < t1, got {args.window!r}")
    u_t = terminal_speed()
    reynolds = DENSITY * u_t * DIAMETER / VISCOSITY
    n = richardson_zaki_exponent(reynolds)
    print(f"u_t = {u_t * 1e3:.4f} mm/s, Re_t = {reynolds:.4f}, n = {n}; window t = {window[0]:g}-{window[1]:g} s")
    print("| reading | l0 [mm] | phi (nominal) | phi (suspension) | Re_t | RZ speed [mm/s] | riffle bulk speed [mm/s] "
          "| error | column frame [mm/s] | error | relative to the undisturbed water [mm/s] | error | band voidage |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for spacing in (float(s) for s in args.spacings.split(",")):
        for reading in args.readings.split(","):
            for phi in (float(p) for p in args.phi.split(",")):
                suffix = ("" if spacing == 0.005 else f"_l{spacing * 1e3:g}mm") + ("_periodic" if args.periodic else "")
                out = os.path.join(args.work, f"{reading}_phi{phi}{suffix}")
                os.makedirs(out, exist_ok=True)
                scene_file = os.path.join(out, "scene.toml")
                with open(scene_file, "w") as f:
                    f.write(scene(phi, reading, args.extra, spacing, window, args.periodic, args.fluid))
                subprocess.run([args.riffle, "run", scene_file, "--out", os.path.join(out, "run"), "--threads",
                                args.threads], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                speed, undisturbed, lab, voidage, truth = bulk_speed(os.path.join(out, "run"), window)
                expected = u_t * (1.0 - truth) ** n
                print(f"| {reading} | {spacing * 1e3:g} | {phi} | {truth:.4f} | {reynolds:.3f} | {expected * 1e3:.4f} | "
                      f"{speed * 1e3:.4f} | {100.0 * (speed / expected - 1.0):+.1f} % | {lab * 1e3:.4f} | {100.0 * (lab / expected - 1.0):+.1f} % "
                      f"| {undisturbed * 1e3:.4f} | {100.0 * (undisturbed / expected - 1.0):+.1f} % | {voidage:.4f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
