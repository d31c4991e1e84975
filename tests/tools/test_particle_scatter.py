#!/usr/bin/python3
"""Self-test of tools/riffle-tools particle-scatter on synthetic frames with known answers: the lattice's n0 (riffle's
3.2083 at r_e = 2.4 l0), the cell-list neighbour means against a direct sum, zero scatter for a uniform stream plus a
linear shear (exact by the linear fit on any neighbourhood), the scatter of a known white noise
(sigma sqrt(3 (1 + sum w^2 / n0^2)) from the lattice's weights, the fit's value being the kernel mean there),
the free surface left out, and the number density's spread.

Usage: /usr/bin/python3 tests/tools/test_particle_scatter.py   (exit 0 = pass)
"""
import pathlib
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from riffle_tools import particle_scatter as ps  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


# n0 of the cubic lattice at r_e = 2.4 l0 (riffle's interior water reads 3.2082 on the lattice).
n0 = ps.lattice_number_density(2.4)
check(abs(n0 - 3.2083) < 1e-3, f"n0 = {n0:.4f}, not 3.2083")

# The cell lists against a direct sum over every pair, on scattered points; a linear field fitted exactly there.
rng = np.random.default_rng(7)
points = rng.uniform(0.0, 0.05, size=(400, 3))
velocity = rng.normal(size=(400, 3))
fits, weights = ps.neighbour_fits(points, velocity, 0.012)
offset = points[None, :, :] - points[:, None, :]
distance = np.sqrt((offset ** 2).sum(axis=-1))
w = np.where((distance > 0.0) & (distance < 0.012), ps.kernel(distance / 0.012), 0.0)
check(np.abs(weights - w.sum(1)).max() < 1e-12, "weight sums differ from the direct sum")
i = int(np.argmax((w > 0.0).sum(1)))  # one point's fit by a direct least-squares solve
basis = np.concatenate([np.ones((400, 1)), (points - points[i]) / 0.012], axis=1)
direct = np.linalg.solve((basis.T * w[i]) @ basis, (basis.T * w[i]) @ velocity)[0]
check(np.abs(fits[i] - direct).max() < 1e-9, "a point's fit differs from a direct least-squares solve")
linear = np.array([0.1, 0.2, -0.3]) + points @ np.array([[1.0, 2.0, 0.0], [0.0, -1.0, 3.0], [0.5, 0.0, 1.0]])
fits, _ = ps.neighbour_fits(points, linear, 0.012)
fitted = (w > 0.0).sum(1) >= 8
check(np.abs(fits[fitted] - linear[fitted]).max() < 1e-9, "a linear field is not fitted exactly on scattered points")

# A lattice of 14^3 water particles at l0 = 1 cm; the top layer flagged free surface.
l0 = 0.01
k = np.arange(14) * l0
lattice = np.stack(np.meshgrid(k, k, k, indexing="ij"), axis=-1).reshape(-1, 3)
count = len(lattice)
surface = (lattice[:, 2] > 12.5 * l0).astype(np.int32)
frame = {"points": lattice, "kind": np.zeros(count, dtype=np.int32), "free_surface": surface,
         "number_density": np.full(count, n0)}

# A uniform stream plus a linear shear: resolved flow, no scatter.
frame["velocity"] = np.array([0.3, -0.1, 0.05]) + lattice @ np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [4.0, 1.0, 0.0]])
row = ps.frame_summary(frame, l0, 2.4)
# Kernels wholly in water (weight sum >= 0.97 n0): all but the outermost layer, the surface layer not water: x, y
# in 1..12, z in 1..11 (one layer in, a particle misses only the neighbours 2 l0 and more beyond the face).
check(row["particles"] == 12 * 12 * 11, f"{row['particles']} particles with a kernel wholly in water, not {12 * 12 * 11}")
check(row["scatter"] < 1e-12, f"a linear field scatters by {row['scatter']:.3g} m/s")
check(row["speed"] > 0.1, "the stream's speed is lost")
check(row["density_spread"] < 1e-12, "the lattice's n has a spread")

# White noise of sigma per component on the lattice: E|u_i - mean|^2 = 3 sigma^2 (1 + sum w^2 / n0^2).
sigma = 0.01
frame["velocity"] = rng.normal(scale=sigma, size=(count, 3))
reach = np.arange(-3, 4)
offsets = np.stack(np.meshgrid(reach, reach, reach, indexing="ij"), axis=-1).reshape(-1, 3)
r = np.linalg.norm(offsets, axis=1)
lattice_weights = ps.kernel(r[(r > 0.0) & (r < 2.4)] / 2.4)
expected = sigma * np.sqrt(3.0 * (1.0 + (lattice_weights ** 2).sum() / n0 ** 2))
row = ps.frame_summary(frame, l0, 2.4)
check(abs(row["scatter"] / expected - 1.0) < 0.08, f"white noise: scatter {row['scatter']:.5f}, expected {expected:.5f}")
check(abs(row["scatter_over_wave"] - row["scatter"] / np.sqrt(9.81 * l0)) < 1e-12, "scatter over sqrt(g l0)")

# The surface particles are left out: noise only on them leaves the interior's scatter at 0 but for their
# neighbours' means, so put it on the surface layer and look at the particles more than r_e below it.
frame["velocity"] = np.where(surface[:, None] == 1, rng.normal(scale=1.0, size=(count, 3)), 0.0)
row = ps.frame_summary(frame, l0, 2.4)
check(row["scatter"] == 0.0, f"free-surface particles counted: scatter {row['scatter']:.3g}")

# The number density's spread: +-2 % alternating.
frame["number_density"] = n0 * (1.0 + 0.02 * np.where(np.arange(count) % 2 == 0, 1.0, -1.0))
row = ps.frame_summary(frame, l0, 2.4)
check(abs(row["density_spread"] - 0.02) < 1e-12, f"density spread {row['density_spread']:.4f}, not 0.02")

print("particle-scatter self-test:", "FAIL" if failures else "pass")
sys.exit(1 if failures else 0)
