#!/usr/bin/python3
"""Bulk-failure load of a (rigid or mobile) bed: for each frame after the ramp, the cumulative horizontal load ratio
R(z) = sum_{grains above depth z} (F_px + F_dx - m a_tank) / sum (m g - F_pz - F_dz), its max over frames by depth.
Grains above depth z: centre depth below the local bed surface < z."""
import sys, math, pathlib
import numpy as np
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
import vtp
A, f, Tr = 0.01, 1.7, 0.5882
w = 2*math.pi*f
G = 9.81
depths = [0.005, 0.01, 0.02, 0.03, 0.045]
for run in sys.argv[1:]:
    out = pathlib.Path(run)
    frames = vtp.read_pvd(out / "solids.pvd")
    Rmax = np.zeros(len(depths)); rows = []
    for t, path in frames:
        if t < Tr + 1e-9: continue
        a = A*w*w*math.sin(w*t)   # x'' of x = -A sin wt
        xt = -A*math.sin(w*t)
        s = vtp.read_vtp(path, ["radius", "mass", "drag_force", "pressure_force"])
        p = s["points"].copy(); p[:, 0] -= xt; r = s["radius"]; m = s["mass"]
        edges = np.linspace(0, 0.24, 13); ib = np.clip(np.digitize(p[:, 0], edges)-1, 0, 11)
        top = p[:, 2] + r
        surf = np.array([np.percentile(top[ib == b], 90) for b in range(12)])
        depth = np.interp(p[:, 0], 0.5*(edges[1:]+edges[:-1]), surf) - p[:, 2]
        load = s["pressure_force"][:, 0] + s["drag_force"][:, 0] - m*a
        weight = m*G - s["pressure_force"][:, 2] - s["drag_force"][:, 2]
        R = np.array([load[depth < z].sum()/weight[depth < z].sum() for z in depths])
        Rmax = np.maximum(Rmax, np.abs(R)); rows.append(R)
    rows = np.array(rows)
    print(f"{run}: max over {len(rows)} frames of |cumulative horizontal load / submerged weight| above depth")
    print("   " + "  ".join(f"{z*1e3:4.0f} mm: {v:5.3f}" for z, v in zip(depths, Rmax)))
    print("   mean |R|: " + "  ".join(f"{v:5.3f}" for v in np.abs(rows).mean(axis=0)))
