#!/usr/bin/python3
"""Per-period wall-gauge range, largest fluid speed and kinetic energy of runs: gauges.py OUT_DIR [OUT_DIR ...]"""
import sys, numpy as np
T = 1/1.7
for out in sys.argv[1:]:
    g = np.genfromtxt(f'{out}/probe_gauges.csv', delimiter=',', names=True)
    d = np.genfromtxt(f'{out}/diagnostics.csv', delimiter=',', names=True)
    print(out)
    for k in range(int(round(g['time_s'][-1]/T + 0.49))):
        m = (g['time_s'] >= k*T) & (g['time_s'] < (k+1)*T)
        if not m.any(): continue
        hi = [(np.nanmax(g[f'gauge{i}_z_m'][m]) - 0.06)*1e3 for i in range(3)]
        lo = [(np.nanmin(g[f'gauge{i}_z_m'][m]) - 0.06)*1e3 for i in range(3)]
        md = (d['time_s'] >= k*T) & (d['time_s'] < (k+1)*T)
        print(f"  period {k+1}: wall gauges L {lo[0]:+6.1f}..{hi[0]:+6.1f}  R {lo[2]:+6.1f}..{hi[2]:+6.1f}  C {lo[1]:+5.1f}..{hi[1]:+5.1f} mm"
              f" | fluid max speed {d['fluid_max_speed_m_s'][md].max():.3f} m/s, KE max {d['fluid_kinetic_energy_J'][md].max()*1e3:6.2f} mJ")
