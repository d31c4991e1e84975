"""A lone grain's own disturbance of the water it samples: the MPS water's, the self-induced model's, and the
continuum's, from a run's solids frames (docs/COUPLING.md, "The undisturbed fluid velocity").

In still water the velocity a grain samples (`fluid_velocity`) is the water its own drag set moving; the model's
estimate of it is `fluid_velocity - undisturbed_velocity`. The continuum's is the regularised Stokeslet's unsteady
Oseen response to the force the grain put on the water (drag, added-mass and history reactions), sampled with the
kernel it was spread with: u(t) = K sum_k dF_k psi(nu (t - t_k) / R^2, Re_R), K = <1/r> / (6 pi mu), with psi the
same Fourier integral over the Wendland kernel's transform riffle tabulates (systems/physics/coupling/self_induced.*),
computed here independently in numpy, and Re_R = |v - u_undisturbed| R / nu at each frame. All three are printed
along the grain's force (downward positive for a settling grain) over the law's speed U when one is given.

    tools/riffle-tools self-disturbance out/run [--grain 0] [--speed U] [--every 2]

The kernel radius R is the dilute grain's, r + (r_e / l0) max(l0, r) (riffle's coupling_kernel_radius) with the
scene's spacing and r_e / l0 (2.4 unless the scene sets `fluid.effective_radius_ratio`); ν and ρ are the scene's.
"""
import argparse
import sys

import numpy as np

from . import vtp

_KAPPA = np.arange(0.0, 120.0, 0.05)  # kappa = k R, as riffle's table (W^2 below 1e-13 of its peak beyond)
_TIMES = np.concatenate([[0.0], np.logspace(-4, 2.5, 700)])  # nu t / R^2


def kernel_transform_squared():
    """W(kappa)^2 of the normalised Wendland kernel w(q) = (1 - q)^4 (1 + 4 q) on R = 1, and its integral."""
    q = np.linspace(0.0, 1.0, 2001)
    w = (1.0 - q) ** 4 * (1.0 + 4.0 * q)
    norm = 2.0 * np.pi / 21.0
    sinc = np.sinc(np.outer(_KAPPA, q) / np.pi)
    transform = 4.0 * np.pi * np.trapz(w * sinc * q * q, q, axis=1) / norm
    squared = transform * transform
    return squared, np.trapz(squared, _KAPPA)


_W2, _W2_INTEGRAL = kernel_transform_squared()
_BUILDUPS = {}


def inverse_distance():
    """R <1/r> over two normalised Wendland kernels on R: (2 / pi) int W^2 d kappa (riffle: 2.148)."""
    return 2.0 / np.pi * _W2_INTEGRAL


def _direction_average(b):
    """3 (sin b - b cos b) / b^3, 1 at b = 0."""
    b = np.asarray(b, dtype=float)
    small = b < 0.1
    safe = np.where(small, 1.0, b)
    return np.where(small, 1.0 - b * b / 10.0 + b ** 4 / 280.0, 3.0 * (np.sin(safe) - safe * np.cos(safe)) / safe ** 3)


def oseen_buildup(time, reynolds_r):
    """psi(T, Re_R): the sampled disturbance of a kernel-spread force switched on at T = 0 over the steady Stokes one
    (1 for ever at Re_R = 0, phi(Re_R) at Re_R > 0); its rate int W^2 kappa^2 exp(-kappa^2 T) 3 j(Re_R kappa T)
    d kappa / int W^2, integrated in T. Tabulated per Re_R rounded to 0.01."""
    key = round(float(reynolds_r), 2)
    if key not in _BUILDUPS:
        rates = np.array([np.trapz(_W2 * _KAPPA ** 2 * np.exp(-_KAPPA ** 2 * t) * _direction_average(key * _KAPPA * t),
                                   _KAPPA) / _W2_INTEGRAL for t in _TIMES])
        _BUILDUPS[key] = np.concatenate([[0.0], np.cumsum(0.5 * (rates[1:] + rates[:-1]) * np.diff(_TIMES))])
    return np.interp(time, _TIMES, _BUILDUPS[key])


def continuum_disturbance(times, forces, reynolds, kernel_radius, nu, viscosity):
    """The continuum's sampled disturbance at each time of `times` (s) from the force on the water `forces` (N, along
    one direction, each held from its time on) and Re_R at each time: K sum_k dF_k psi(nu (t - t_k) / R^2, Re_R(t)).
    Returns (Oseen, Stokes) arrays."""
    times = np.asarray(times, dtype=float)
    forces = np.asarray(forces, dtype=float)
    mobility = inverse_distance() / kernel_radius / (6.0 * np.pi * viscosity)
    steps = np.diff(np.concatenate([[0.0], forces]))
    oseen, stokes = np.zeros(len(times)), np.zeros(len(times))
    for k in range(len(times)):
        age = nu * (times[k] - times[:k + 1]) / kernel_radius ** 2
        oseen[k] = mobility * np.sum(steps[:k + 1] * oseen_buildup(age, reynolds[k]))
        stokes[k] = mobility * np.sum(steps[:k + 1] * oseen_buildup(age, 0.0))
    return oseen, stokes


def scene_numbers(run_dir):
    fluid = vtp.fluid_scene(run_dir, "self-disturbance")["fluid"]
    return (float(fluid["spacing"]), float(fluid.get("effective_radius_ratio", 2.4)),
            float(fluid["kinematic_viscosity"]), float(fluid.get("density", 1000.0)))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", help="a run's output folder with solids frames (output.vtk_interval > 0)")
    parser.add_argument("--grain", type=int, default=0, help="the grain's id")
    parser.add_argument("--speed", type=float, default=0.0, help="the law's speed U: velocities printed over it")
    parser.add_argument("--every", type=int, default=1, help="print every n-th frame")
    args = parser.parse_args(argv)
    spacing, ratio, nu, density = scene_numbers(args.run)
    frames = vtp.read_pvd(f"{args.run}/solids.pvd")
    if len(frames) < 2:
        sys.exit(f"self-disturbance: {args.run}/solids.pvd holds {len(frames)} frame(s); run with output.vtk_interval > 0")
    rows = []
    for time, path in frames:
        frame = vtp.read_vtp(path)
        index = np.nonzero(frame["id"] == args.grain)[0]
        if len(index) == 0:
            continue
        i = index[0]
        on_water = -(frame["drag_force"][i] + frame["added_mass_force"][i] + frame["history_force"][i])
        rows.append((time, frame["points"][i], frame["velocity"][i], frame["fluid_velocity"][i],
                     frame["undisturbed_velocity"][i], on_water, frame["radius"][i]))
    if not rows:
        sys.exit(f"self-disturbance: grain {args.grain} is in no frame of {args.run}")
    radius = rows[-1][6]
    kernel = radius + ratio * max(spacing, radius)
    direction = rows[-1][5] / max(np.linalg.norm(rows[-1][5]), 1e-300)  # along the last force on the water
    times = [r[0] for r in rows]
    forces = [float(np.dot(r[5], direction)) for r in rows]
    reynolds = [np.linalg.norm(r[2] - r[4]) * kernel / nu for r in rows]
    oseen, stokes = continuum_disturbance(times, forces, reynolds, kernel, nu, density * nu)
    scale = args.speed if args.speed > 0.0 else 1.0
    unit = "U" if args.speed > 0.0 else "m/s"
    print(f"grain {args.grain}: r = {radius:g} m, kernel R = {kernel:g} m, l0 = {spacing:g} m, nu = {nu:g} m^2/s; "
          f"disturbances along the force on the water, in {unit}")
    print("| t [s] | height [m] | grain speed | MPS water's | model's | continuum, Oseen | continuum, Stokes | Re_R |")
    print("|---|---|---|---|---|---|---|---|")
    for k in range(0, len(rows), max(args.every, 1)):
        t, position, velocity, sampled, undisturbed, _, _ = rows[k]
        along = lambda v: float(np.dot(v, direction)) / scale  # noqa: E731
        print(f"| {t:.3f} | {position[2]:.4f} | {along(velocity):.3f} | {along(sampled):.3f} | "
              f"{along(sampled - undisturbed):.3f} | {oseen[k] / scale:.3f} | {stokes[k] / scale:.3f} | "
              f"{reynolds[k]:.2f} |")


if __name__ == "__main__":
    main()
