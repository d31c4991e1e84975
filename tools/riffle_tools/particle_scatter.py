"""The MPS water's particle-scale velocity scatter, frame by frame: how far each particle's velocity is from the
kernel-weighted mean of its neighbours' (docs/FLUID.md, "Disordered water's particle-scale noise").

For every water particle off the free surface, u_i less the value at r_i of the kernel-weighted least-squares linear
fit to the velocities of the other water particles within r_e (w the Wendland kernel riffle uses, w(q) = (1 - q)^4
(1 + 4 q), q = r / r_e; on a complete, symmetric neighbourhood the fit's value is the kernel mean sum w u / sum w).
The fit reproduces any uniform or linear velocity field, so resolved flow (a stream, a shear) gives 0 and what is
left is the scatter at the particles' own scale, which no grain's kernel and no probe resolves. Taken over the particles whose kernel holds only water (their water
neighbours' weight sum >= 0.97 n0; next to a wall or the surface the cut biases the mean). Beside it: their RMS
speed, the scatter over sqrt(g l0), and their number density's RMS deviation from the lattice's n0.

    tools/riffle-tools particle-scatter out/run [--every 2]

l0 and r_e / l0 come from the run's scene (`fluid.spacing`, `fluid.effective_radius_ratio`, 2.4 by default).
"""
import argparse
import sys

import numpy as np

from . import vtp
from .lattice_response import lattice_neighbours, wendland as kernel

_COMPLETE = 0.97  # water weight sum / n0 above which a particle's kernel counts as wholly in water


def lattice_number_density(ratio):
    """n0 of the cubic lattice's interior for r_e / l0 = ratio (3.2083 at 2.4)."""
    return float(lattice_neighbours(ratio)[4].sum())


def neighbour_fits(points, velocity, radius):
    """For each point, the velocity at it of the kernel-weighted least-squares linear fit u ~ a + G (r - r_i) to the
    other points within `radius` (a, exact for any linear field on any neighbourhood whose moments can be inverted;
    on a complete, symmetric one it is the kernel mean), and their weight sum. A point with fewer than four
    neighbours keeps its own velocity. Cell lists of side `radius`."""
    points = np.asarray(points, dtype=float)
    velocity = np.asarray(velocity, dtype=float)
    count = len(points)
    fits = velocity.copy()
    weights = np.zeros(count)
    if count == 0:
        return fits, weights
    cells = np.floor((points - points.min(axis=0)) / radius).astype(np.int64)
    span = cells.max(axis=0) + 3
    keys = ((cells[:, 0] + 1) * span[1] + cells[:, 1] + 1) * span[2] + cells[:, 2] + 1
    order = np.argsort(keys, kind="stable")
    unique, first = np.unique(keys[order], return_index=True)
    last = np.append(first[1:], count)
    members = {int(key): order[a:b] for key, a, b in zip(unique, first, last)}
    shifts = [(dx * span[1] + dy) * span[2] + dz for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)]
    for key, own in members.items():
        candidates = np.concatenate([members[key + shift] for shift in shifts if key + shift in members])
        offset = (points[candidates][None, :, :] - points[own][:, None, :]) / radius  # scaled: a well-sized system
        distance = np.sqrt((offset ** 2).sum(axis=-1))
        weight = np.where((distance > 0.0) & (distance < 1.0), kernel(distance), 0.0)
        weights[own] = weight.sum(axis=1)
        basis = np.concatenate([np.ones(offset.shape[:2] + (1,)), offset], axis=-1)  # [1, r]
        moments = np.einsum("ij,ijk,ijl->ikl", weight, basis, basis)
        rhs = np.einsum("ij,ijk,jl->ikl", weight, basis, velocity[candidates])
        enough = (weight > 0.0).sum(axis=1) >= 4
        solvable = enough & (np.abs(np.linalg.det(moments)) > 1e-12 * np.maximum(weights[own], 1e-300) ** 4)
        if solvable.any():
            fits[own[solvable]] = np.linalg.solve(moments[solvable], rhs[solvable])[:, 0, :]
    return fits, weights


def frame_summary(frame, spacing, ratio, gravity=9.81):
    """The numbers of one fluid frame (a dict of vtp arrays) over the water particles whose kernel holds only water
    (their water neighbours' weight sum at least 0.97 n0: away from walls and the free surface, where a kernel mean
    is biased by the cut): their count, RMS speed, RMS scatter, the scatter over sqrt(g l0), and the number density's
    RMS deviation over n0."""
    water = (frame["kind"] == 0) & (frame["free_surface"] == 0)
    points, velocity = frame["points"][water], frame["velocity"][water]
    means, weights = neighbour_fits(points, velocity, ratio * spacing)
    n0 = lattice_number_density(ratio)
    inner = weights >= _COMPLETE * n0
    count = int(inner.sum())
    if count == 0:
        return {"particles": 0, "speed": float("nan"), "scatter": float("nan"), "scatter_over_wave": float("nan"),
                "density_spread": float("nan")}
    scatter = float(np.sqrt(((velocity[inner] - means[inner]) ** 2).sum(axis=1).mean()))
    speed = float(np.sqrt((velocity[inner] ** 2).sum(axis=1).mean()))
    density = frame["number_density"][water][inner] / n0
    spread = float(np.sqrt(((density - 1.0) ** 2).mean())) if density.any() else float("nan")  # none at t = 0
    return {"particles": count, "speed": speed, "scatter": scatter,
            "scatter_over_wave": scatter / float(np.sqrt(gravity * spacing)),
            "density_spread": spread}


def scene_spacing(run_dir):
    data = vtp.fluid_scene(run_dir, "particle-scatter")
    fluid = data["fluid"]
    gravity = float(np.linalg.norm(data.get("run", {}).get("gravity", [0.0, 0.0, -9.81])))
    return float(fluid["spacing"]), float(fluid.get("effective_radius_ratio", 2.4)), gravity


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", help="a run's output folder with fluid frames (output.vtk_interval > 0)")
    parser.add_argument("--every", type=int, default=1, help="every n-th frame")
    args = parser.parse_args(argv)
    spacing, ratio, gravity = scene_spacing(args.run)
    frames = vtp.read_pvd(f"{args.run}/fluid.pvd")
    if not frames:
        sys.exit(f"particle-scatter: {args.run}/fluid.pvd lists no frame; run with output.vtk_interval > 0")
    print(f"l0 = {spacing:g} m, r_e = {ratio:g} l0, sqrt(g l0) = {np.sqrt(gravity * spacing):.4f} m/s; over the "
          f"water particles whose kernel is wholly in water")
    print("| t [s] | particles | RMS speed [m/s] | RMS scatter [m/s] | scatter / sqrt(g l0) | n/n0 RMS deviation |")
    print("|---|---|---|---|---|---|")
    for time, path in frames[::max(args.every, 1)]:
        row = frame_summary(vtp.read_vtp(path), spacing, ratio, gravity)
        print(f"| {time:.3f} | {row['particles']} | {row['speed']:.4f} | {row['scatter']:.4f} | "
              f"{row['scatter_over_wave']:.3f} | {row['density_spread']:.4f} |")


if __name__ == "__main__":
    main()
