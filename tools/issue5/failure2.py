#!/usr/bin/python3
"""Whole-bed horizontal load budget per frame (exact ramp kinematics): sums over ALL grains, / total submerged weight
(m g - Fpz - Fdz summed): pressure x, drag x, -m a (tank-frame inertia), net load = Fp + Fd - m a (what contacts with
walls/floor must supply, sign flipped); plus mean grain velocity rel. tank (volume weighted) and bed-water mean u rel tank."""
import sys, math, pathlib
import numpy as np
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
import vtp
A, f, Tr = 0.01, 1.7, 0.5882
w = 2*math.pi*f; G = 9.81
def kin(t):
    if t >= Tr: r, dr, ddr = 1.0, 0.0, 0.0
    else:
        s = t/Tr; r = s**3*(10+s*(-15+6*s)); dr = 30*s*s*(1-s)**2/Tr; ddr = 60*s*(1-s)*(1-2*s)/Tr**2
    sn, cs = math.sin(w*t), math.cos(w*t)
    return -A*r*sn, -A*(dr*sn + r*w*cs), -A*(ddr*sn + 2*dr*w*cs - r*w*w*sn)
run = sys.argv[1]; t0 = float(sys.argv[2]) if len(sys.argv) > 2 else 0; t1 = float(sys.argv[3]) if len(sys.argv) > 3 else 99
frames = vtp.read_pvd(pathlib.Path(run) / "solids.pvd")
print(f"{run}\n  t/T    a/g  | Fpx    Fdx    -ma    net  (/ submerged weight) | u_s rel tank (mm/s) mean, max|.|")
for t, path in frames:
    if not (t0 <= t*f <= t1): continue
    x, v, a = kin(t)
    s = vtp.read_vtp(path, ["radius", "mass", "drag_force", "pressure_force", "velocity"])
    m = s["mass"]; V = 4/3*math.pi*s["radius"]**3
    W = (m*G - s["pressure_force"][:, 2] - s["drag_force"][:, 2]).sum()
    Fp = s["pressure_force"][:, 0].sum()/W; Fd = s["drag_force"][:, 0].sum()/W; I = -(m.sum()*a)/W
    us = s["velocity"][:, 0] - v
    print(f"  {t*f:4.2f} {a/G:+.3f} | {Fp:+.3f} {Fd:+.3f} {I:+.3f} {Fp+Fd+I:+.3f} | {np.average(us, weights=V)*1e3:+7.1f} {np.abs(us).max()*1e3:6.1f}")
