#!/usr/bin/python3
"""Self-test of tools/riffle-tools self-disturbance's continuum response against numbers computed independently:
R <1/r> and the build-up psi(T, Re_R) as riffle's C++ quadrature gives them (tests/unit/systems/physics/coupling/
self_induced_test.cpp, docs/COUPLING.md: 2.148; Stokes 0.24 / 0.50 / 0.75 / 0.92 at T = 0.05 / 0.2 / 1 / 10), its
tail towards the Oseen factor, and the convolution of a force switched on once (K F psi) and switched off again.

Usage: /usr/bin/python3 tests/tools/test_self_disturbance.py   (exit 0 = pass)
"""
import math
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from riffle_tools import self_disturbance as sd  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


check(abs(sd.inverse_distance() - 2.148) < 2e-3, f"R<1/r> = {sd.inverse_distance():.4f}, not 2.148")
for t, value in [(0.05, 0.24), (0.2, 0.50), (1.0, 0.75), (10.0, 0.92)]:
    got = float(sd.oseen_buildup(t, 0.0))
    check(abs(got - value) < 0.01, f"Stokes psi({t}) = {got:.4f}, not {value}")
# The C++ quadrature's values (self_induced_test.cpp, to 3e-3 there).
for t, re, value in [(1.0, 1.0, 0.7280), (0.1, 2.9, 0.3510), (1.0, 2.9, 0.6300), (0.05, 10.0, 0.2153),
                     (0.2, 10.0, 0.3284)]:
    got = float(sd.oseen_buildup(t, re))
    check(abs(got - value) < 3e-3 * value + 1e-3, f"psi({t}, {re}) = {got:.4f}, not {value}")
# Oseen's screening: psi falls below Stokes' and levels off (phi(10) ~ 0.35 / 0.85 at Re_R 1, docs/COUPLING.md).
check(abs(float(sd.oseen_buildup(300.0, 1.0)) - 0.85) < 0.03, "phi(1) is not about 0.85")
check(abs(float(sd.oseen_buildup(300.0, 10.0)) - 0.35) < 0.03, "phi(10) is not about 0.35")
# A force F switched on at t = 0: K F psi(nu t / R^2); switched off at t1: K F (psi(T) - psi(T - T1)).
R, nu, mu, F = 0.017, 2.4e-4, 0.24, 6e-4
K = sd.inverse_distance() / R / (6.0 * math.pi * mu)
times = [0.0, 0.5, 1.0, 2.0, 3.0]
oseen, stokes = sd.continuum_disturbance(times, [F] * 5, [1.5] * 5, R, nu, mu)
for k, t in enumerate(times):
    check(abs(stokes[k] - K * F * float(sd.oseen_buildup(nu * t / R ** 2, 0.0))) < 1e-12, f"Stokes step at {t}")
    check(abs(oseen[k] - K * F * float(sd.oseen_buildup(nu * t / R ** 2, 1.5))) < 1e-12, f"Oseen step at {t}")
_, off = sd.continuum_disturbance(times, [F, F, 0.0, 0.0, 0.0], [0.0] * 5, R, nu, mu)
expected = K * F * (float(sd.oseen_buildup(nu * 3.0 / R ** 2, 0.0)) - float(sd.oseen_buildup(nu * 2.0 / R ** 2, 0.0)))
check(abs(off[4] - expected) < 1e-12 and off[4] > 0.0, "a force switched off leaves a decaying disturbance")

print("self-disturbance self-test:", "FAIL" if failures else "pass")
sys.exit(1 if failures else 0)
