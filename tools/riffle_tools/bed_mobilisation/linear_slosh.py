"""Linear long-wave model (with a tanh dispersion correction) of the sloshing tank: clear water h1 over a porous bed
h2 in a tank of length L shaken at a = A w^2. Prints the wall elevation amplitude over a rigid bed (moving with the
tank) for the real interstitial reading and for riffle's readings of the pore flow, the natural frequencies, and the
bed-averaged horizontal load on a rigid bed over its submerged weight. Pore flow: du/dt = F - r u, flux = phi h2 u
(phi = eps for the real interstitial velocity, 1 for riffle).

Usage: tools/riffle-tools mobilisation-linear-slosh   (no arguments: the seed tank's numbers)
"""
import argparse
import sys

import numpy as np

g, L, A, f = 9.81, 0.24, 0.01, 1.7
w = 2*np.pi*f
a = A*w*w
k = np.pi/L
rho = 1000.0


def wall(h1, h2, phi, r, disp=True):
    H = h1 + h2*phi*1j*w/(1j*w + r) if h2 > 0 else h1
    gH = g*np.tanh(k*H)/k if disp else g*H
    kap = w/np.sqrt(gH)
    return abs(a/g*np.tan(kap*L/2)/kap), H


def bed_load(h1, h2, eps, beta, reading, rhos=1318.0, n=400):
    # tank frame, complex amplitudes; forcing -a on all fluid.  reading: 'real', 'seed', 'mixture'
    if reading == 'real':
        phi, r, mpore = eps, beta/(eps*rho), eps*rho          # flux = eps u_f; skeleton drags eps*rho
    elif reading == 'seed':
        phi, r, mpore = 1.0, beta/rho, rho
    else:
        phi, r, mpore = 1.0, beta/(eps*eps*rho), rho          # MPS w, drag on water (beta/eps^2) w
    H = h1 + h2*phi*1j*w/(1j*w + r)
    gH = g*np.tanh(k*H)/k
    kap = w/np.sqrt(gH)
    C = -a/(g*kap*np.cos(kap*L/2))
    x = np.linspace(0, L, n)
    px = rho*g*C*kap*np.cos(kap*(x - L/2))          # p_x = rho g eta_x
    # pore flow per unit mass: d u/dt = -p_x/rho - a - r u  -> u = (-p_x/rho - a)/(i w + r)
    u = (-px/rho - a)/(1j*w + r)
    # force from water on grains per volume: -(1-eps) p_x + drag; drag per volume on grains = mpore * r * u
    if reading == 'mixture':
        drag = eps * rho * r * u   # grains get eps x what the water gets
    else:
        drag = mpore * r * u
    load = -rhos*(1-eps)*a - (1-eps)*px + drag       # what the contacts must balance (tank frame, per volume)
    Wsub = (rhos - rho)*(1-eps)*g
    return abs(load.mean())/Wsub, abs(C*np.sin(kap*L/2))


def main(argv=None):
    argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter).parse_args(argv)
    print("f_forcing 1.7 Hz; a/g = %.3f" % (a/g))
    for beta in (5e3, 1e4, 2e4, 5e4):
        eps = 0.42
        cases = {
          "free water 6 cm": (0.06, 0.0, 1, 0),
          "rigid floor at 4.5 cm (1.5 cm water)": (0.015, 0.0, 1, 0),
          "real porous bed (interstitial, eps)": (0.015, 0.045, eps, beta/(eps*rho)),
          "riffle seed reading (u fills space)": (0.015, 0.045, 1.0, beta/rho),
          "riffle superficial reading": (0.015, 0.045, 1.0, beta/(eps*eps*rho)),
        }
        print(f"beta = {beta:.0e} kg/m3/s")
        for name, (h1, h2, phi, r) in cases.items():
            amp, H = wall(h1, h2, phi, r)
            print(f"   {name:40s} wall amplitude {amp*1e3:7.1f} mm, |H_eff| {abs(H)*1e3:5.1f} mm, "
                  f"Re H {H.real*1e3:5.1f} mm")
    # natural frequencies
    for h in (0.06, 0.015, 0.023, 0.048):
        print(f"f1(h={h*100:.1f} cm) = {np.sqrt(g*k*np.tanh(k*h))/2/np.pi:.2f} Hz")

    print("\nBed-averaged horizontal load on a rigid bed (skeleton inertia + fluid forces) / submerged weight, "
          "long-wave model")
    for beta in (1e4, 2e4):
        for reading in ('real', 'mixture', 'seed'):
            R, amp = bed_load(0.015, 0.045, 0.42, beta, reading)
            print(f"  beta {beta:.0e} {reading:8s}: bed-averaged load ratio {R:.2f}, wall amplitude {amp*1e3:.1f} mm")
    print(f"  dry bed: {a/g:.3f}; locked pore water, no pressure help: real/mixture "
          f"{(1318*0.58+1000*0.42)/(318*0.58)*a/g:.2f}, seed {(1318*0.58+1000)/(318*0.58)*a/g:.2f}; "
          f"water moving with tank: {a/g:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
