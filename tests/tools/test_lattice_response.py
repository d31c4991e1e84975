#!/usr/bin/python3
"""Self-test of tools/riffle-tools lattice-response: the MPS Laplacian's symbol on the lattice is k^2 for long waves
(its normalisation by lambda and n0) and weaker at the kernel's scale; the kernel sampled on lattice sites transforms
as the continuous one (the discrete-kernel ratio within 1 % of 1); the lattice's response approaches the continuum's
as the kernel widens in l0.

Usage: /usr/bin/python3 tests/tools/test_lattice_response.py   (exit 0 = pass)
"""
import math
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from riffle_tools import lattice_response as lr  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def main():
    kx, ky, kz = lr.wavenumbers(32)
    symbol, lam, n0 = lr.laplacian_symbol(kx, ky, kz, 2.4)
    k2 = kx * kx + ky * ky + kz * kz
    longest = (1, 0, 0)
    check(abs(symbol[longest] / k2[longest] - 1.0) < 5e-3, f"long-wave symbol / k^2 = {symbol[longest] / k2[longest]}")
    diagonal = (1, 1, 1)
    check(abs(symbol[diagonal] / k2[diagonal] - 1.0) < 0.02, f"isotropic for long waves: {symbol[diagonal] / k2[diagonal]}")
    quarter = (8, 0, 0)  # k l0 = pi / 2
    check(0.6 < symbol[quarter] / k2[quarter] < 0.95, f"weaker at the kernel's scale: {symbol[quarter] / k2[quarter]}")
    narrow = lr.responses(2.7, 2.4, (0.3,), 32)
    wide = lr.responses(6.0, 2.4, (0.3,), 32)
    for label, result in (("R = 2.7 l0", narrow), ("R = 6 l0", wide)):
        for time, (total, kernel, alone) in result.items():
            check(abs(kernel - 1.0) < 0.01, f"{label}, t = {time}: discrete kernel ratio {kernel}")
            check(abs(total - kernel * alone) < 1e-9 * total, f"{label}, t = {time}: the parts multiply to the whole")
            check(total > 1.0, f"{label}, t = {time}: the weaker symbol answers more ({total})")
    check(wide[None][0] - 1.0 < 0.5 * (narrow[None][0] - 1.0),
          f"approaches the continuum as the kernel widens: {narrow[None][0]} at 2.7 l0, {wide[None][0]} at 6 l0")
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("lattice-response tool: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
