"""Per period: the wall gauges' elevation range, the largest fluid speed and kinetic energy of coupled sloshing runs
(probe_gauges.csv with gauge0-2 at the left wall, centre and right wall; diagnostics.csv).

Usage: tools/riffle-tools mobilisation-gauges OUT_DIR [OUT_DIR ...]
"""
import argparse
import sys

import numpy as np

from ..tank_motion import SEED_FREQUENCY

WATER_DEPTH = 0.06  # [m] the still water level the gauge elevations are read against


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out_dirs", nargs="+", metavar="OUT_DIR", help="a coupled run's output directory")
    parser.add_argument("--frequency", type=float, default=SEED_FREQUENCY, help="f [Hz] (default %(default)g)")
    args = parser.parse_args(argv)
    T = 1 / args.frequency
    for out in args.out_dirs:
        g = np.genfromtxt(f'{out}/probe_gauges.csv', delimiter=',', names=True)
        d = np.genfromtxt(f'{out}/diagnostics.csv', delimiter=',', names=True)
        print(out)
        for k in range(int(round(g['time_s'][-1]/T + 0.49))):
            m = (g['time_s'] >= k*T) & (g['time_s'] < (k+1)*T)
            if not m.any():
                continue
            hi = [(np.nanmax(g[f'gauge{i}_z_m'][m]) - WATER_DEPTH)*1e3 for i in range(3)]
            lo = [(np.nanmin(g[f'gauge{i}_z_m'][m]) - WATER_DEPTH)*1e3 for i in range(3)]
            md = (d['time_s'] >= k*T) & (d['time_s'] < (k+1)*T)
            print(f"  period {k+1}: wall gauges L {lo[0]:+6.1f}..{hi[0]:+6.1f}  R {lo[2]:+6.1f}..{hi[2]:+6.1f}  "
                  f"C {lo[1]:+5.1f}..{hi[1]:+5.1f} mm | fluid max speed {d['fluid_max_speed_m_s'][md].max():.3f} m/s, "
                  f"KE max {d['fluid_kinetic_energy_J'][md].max()*1e3:6.2f} mJ")
    return 0


if __name__ == "__main__":
    sys.exit(main())
