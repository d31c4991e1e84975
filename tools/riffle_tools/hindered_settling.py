"""Hindered settling in a closed column against Richardson & Zaki (1954) (docs/COUPLING.md, "Hindered settling").

A suspension of equal 3 mm beads (1100 kg/m^3) in a liquid of 1000 kg/m^3 and 0.2 Pa s fills z = 10-130 mm of a
60 x 60 mm column (water to 160 mm, l0 = 5 mm) by random sequential addition, at rest. The bulk speed is the
grains' mean downward velocity relative to the water's local velocity (the flux the model's continuity conserves:
zero section mean in the closed column) in the band z = 60-80 mm, averaged over t = 0.032-0.1 s (the beads relax
in 3 ms, the top of the suspension moves less than 0.2 mm); the speed in the column's frame is printed too (it
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
      [--readings mixture,pore] [--extra 'voidage_estimate = "cloud_in_cell"']

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
BAND, WINDOW = (0.06, 0.08), (0.032, 0.1)


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


def scene(phi, reading, extra, spacing=0.005):
    count = round(phi * COLUMN * COLUMN * (FILL_HIGH - FILL_LOW) / (math.pi / 6.0 * DIAMETER ** 3))
    return f"""
[run]
name = "hindered_settling"
end_time = {WINDOW[1] + 1e-3}
dt = 2.0e-3
solid_substeps = 8
[materials.bead]
density = {SOLID_DENSITY}
[materials.glass]
density = 2500.0
[tank]
size = [0.06, 0.06, 0.18]
open_faces = ["z_max"]
wall_material = "glass"
[solids]
[[solids.fills]]
min = [0.0, 0.0, {FILL_LOW}]
max = [0.06, 0.06, {FILL_HIGH}]
seed = 5
[[solids.fills.classes]]
diameter = {DIAMETER}
count = {count}
material = "bead"
[fluid]
spacing = {spacing}
density = {DENSITY}
kinematic_viscosity = {VISCOSITY / DENSITY}
[[fluid.boxes]]
low = [0.0, 0.0, 0.0]
high = [0.06, 0.06, 0.16]
[coupling]
fluid_velocity = "{reading}"
{extra}
[output]
vtk_interval = 0.004
"""


def bulk_speed(run_dir):
    """The band's grains: mean downward speed relative to the water's local velocity (the flux the model's
    continuity conserves, zero section mean in a closed column), mean downward speed in the column's frame, mean
    voidage, averaged over the frames in the window; and the suspension's solid fraction (centres in z = 30-110 mm
    at the window's start)."""
    import numpy as np
    from . import vtp
    relative, undisturbed, lab, voidage, truth = [], [], [], [], None
    volume = math.pi / 6.0 * DIAMETER ** 3
    for time, path in vtp.read_pvd(os.path.join(run_dir, "solids.pvd")):
        if time < WINDOW[0] - 1e-9 or time > WINDOW[1] + 1e-9:
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
    parser.add_argument("--threads", default="1")
    parser.add_argument("--spacings", default="0.005",
                        help="l0 [m], comma-separated (each a divisor of the 60 x 60 x 180 mm column: 0.01, 0.0075, "
                             "0.005, 0.004, 0.003, 0.0025): the same suspension at each, for the convergence in l0")
    args = parser.parse_args(argv)
    u_t = terminal_speed()
    reynolds = DENSITY * u_t * DIAMETER / VISCOSITY
    n = richardson_zaki_exponent(reynolds)
    print(f"u_t = {u_t * 1e3:.4f} mm/s, Re_t = {reynolds:.4f}, n = {n}")
    print("| reading | l0 [mm] | phi (nominal) | phi (suspension) | Re_t | RZ speed [mm/s] | riffle bulk speed [mm/s] "
          "| error | column frame [mm/s] | error | relative to the undisturbed water [mm/s] | error | band voidage |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for spacing in (float(s) for s in args.spacings.split(",")):
        for reading in args.readings.split(","):
            for phi in (float(p) for p in args.phi.split(",")):
                suffix = "" if spacing == 0.005 else f"_l{spacing * 1e3:g}mm"
                out = os.path.join(args.work, f"{reading}_phi{phi}{suffix}")
                os.makedirs(out, exist_ok=True)
                scene_file = os.path.join(out, "scene.toml")
                with open(scene_file, "w") as f:
                    f.write(scene(phi, reading, args.extra, spacing))
                subprocess.run([args.riffle, "run", scene_file, "--out", os.path.join(out, "run"), "--threads",
                                args.threads], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                speed, undisturbed, lab, voidage, truth = bulk_speed(os.path.join(out, "run"))
                expected = u_t * (1.0 - truth) ** n
                print(f"| {reading} | {spacing * 1e3:g} | {phi} | {truth:.4f} | {reynolds:.3f} | {expected * 1e3:.4f} | "
                      f"{speed * 1e3:.4f} | {100.0 * (speed / expected - 1.0):+.1f} % | {lab * 1e3:.4f} | {100.0 * (lab / expected - 1.0):+.1f} % "
                      f"| {undisturbed * 1e3:.4f} | {100.0 * (undisturbed / expected - 1.0):+.1f} % | {voidage:.4f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
