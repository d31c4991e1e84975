"""The MPS water's response at a grain's kernel against the continuum's: what the self-induced correction leaves.

A grain spreads its drag over the water with a Wendland kernel of radius R and samples the water with the same
kernel. The continuum's response to that spread force, sampled with the kernel, is what the self-induced correction
models (systems/physics/coupling/self_induced.*): sum over k of |W(k)|^2 (1 - exp(-nu k^2 t)) / (mu k^2). The MPS
water's viscous term is the classic MPS Laplacian, (2 dim / (lambda n0)) sum_j w(r_j) (u_j - u_i) with the Wendland
weight of radius r_e (systems/mps/fluid_predict.cpp), whose symbol on the particle lattice,

    L(k) = (6 / (lambda n0)) sum_j w(r_j) (1 - cos k.r_j),

is weaker than k^2 at the kernel's scale (0.95 k^2 at k l0 = pi/4, 0.80 at pi/2 for r_e = 2.4 l0). The tool puts both
on a periodic lattice of side N l0 (the mean mode left out, as a suspension's backflow does), with the kernel sampled
on the lattice sites around a grain (averaged over four positions of the grain in its cell), and prints, at times
nu t / R^2 and at steady state, the ratio of the lattice's response to the continuum's, and its two parts: the
discrete kernel with the continuum's k^2, and the symbol L(k) alone. The continuum projector's direction average (2/3)
is common to both and cancels; so does the density.

    tools/riffle-tools lattice-response [--radii 2.55,2.7,2.9] [--effective-radius 2.4] [--times 0.1,0.3,1]
        [--lattice 64]

Radii in l0 (a dilute grain's kernel, riffle's coupling_kernel_radius: r + (r_e/l0) max(l0, r)). Measured against
lone beads (docs/cases/settling.md, "Hindered settling"): the MPS water's own disturbance 1.06-1.11 and 1.07-1.18 times
the continuum's at R = 2.7 and 2.9 l0.
"""
import argparse
import math
import sys


def wendland(q):
    import numpy as np
    q = np.clip(q, 0.0, 1.0)
    return (1.0 - q) ** 4 * (1.0 + 4.0 * q)


def wavenumbers(lattice):
    import numpy as np
    k1 = 2.0 * math.pi * np.fft.fftfreq(lattice)
    return np.meshgrid(k1, k1, k1, indexing="ij")


def lattice_neighbours(effective_radius):
    """The neighbours of a site of the cubic lattice of spacing 1 within r_e = effective_radius: their offsets x, y, z,
    distances r and Wendland weights w (whose sum is the lattice's n0: 3.2083 at r_e = 2.4)."""
    import numpy as np
    reach = int(math.ceil(effective_radius))
    offsets = np.arange(-reach, reach + 1)
    x, y, z = (a.ravel() for a in np.meshgrid(offsets, offsets, offsets, indexing="ij"))
    r = np.sqrt(x * x + y * y + z * z)
    keep = (r > 0.0) & (r < effective_radius)
    return x[keep], y[keep], z[keep], r[keep], wendland(r[keep] / effective_radius)


def laplacian_symbol(kx, ky, kz, effective_radius):
    """L(k) of the classic MPS Laplacian on the cubic lattice of spacing 1, and lambda, n0."""
    import numpy as np
    x, y, z, r, w = lattice_neighbours(effective_radius)
    n0 = w.sum()
    lam = (w * r * r).sum() / n0
    symbol = np.zeros_like(kx)
    for xj, yj, zj, wj in zip(x, y, z, w):
        symbol += wj * (1.0 - np.cos(kx * xj + ky * yj + kz * zj))
    return symbol * 6.0 / (lam * n0), lam, n0


def lattice_kernel_power(kx, ky, kz, radius, offset):
    """|W(k)|^2 of the kernel of radius `radius` sampled on the lattice sites around a grain at `offset`, normalised
    to unit sum."""
    import numpy as np
    reach = int(math.ceil(radius)) + 1
    sites = np.arange(-reach, reach + 1)
    x, y, z = (a.ravel() for a in np.meshgrid(sites, sites, sites, indexing="ij"))
    d = np.sqrt((x - offset[0]) ** 2 + (y - offset[1]) ** 2 + (z - offset[2]) ** 2)
    w = wendland(d / radius)
    keep = w > 0.0
    x, y, z, w = x[keep], y[keep], z[keep], w[keep] / w[keep].sum()
    transform = np.zeros(kx.shape, complex)
    for xj, yj, zj, wj in zip(x, y, z, w):
        transform += wj * np.exp(1j * (kx * xj + ky * yj + kz * zj))
    return np.abs(transform) ** 2


def continuum_kernel_power(k, radius):
    """|W(k)|^2 of the continuous kernel of radius `radius` normalised to unit integral (its radial transform)."""
    import numpy as np
    r = np.linspace(0.0, radius, 2001)
    w = wendland(r / radius)
    shell = 4.0 * math.pi * r * r * w
    norm = np.trapz(shell, r)
    grid = np.linspace(0.0, k.max() * 1.001, 2000)
    transform = np.array([np.trapz(shell * np.sinc(q * r / math.pi), r) for q in grid]) / norm
    return np.interp(k, grid, transform) ** 2


def responses(radius, effective_radius=2.4, times=(0.1, 0.3, 1.0), lattice=64):
    """{time (None: steady): (lattice / continuum, discrete kernel with k^2 / continuum, symbol alone)}."""
    import numpy as np
    kx, ky, kz = wavenumbers(lattice)
    k2 = kx * kx + ky * ky + kz * kz
    symbol, _, _ = laplacian_symbol(kx, ky, kz, effective_radius)
    offsets = [(0.0, 0.0, 0.0), (0.5, 0.0, 0.0), (0.5, 0.5, 0.5), (0.25, 0.5, 0.0)]
    discrete = np.mean([lattice_kernel_power(kx, ky, kz, radius, o) for o in offsets], axis=0)
    continuous = continuum_kernel_power(np.sqrt(k2), radius)
    mean = (0, 0, 0)
    k2[mean], symbol[mean] = 1.0, 1.0
    out = {}
    for time in list(times) + [None]:
        if time is None:
            on_lattice, on_k2 = 1.0 / symbol, 1.0 / k2
        else:
            span = time * radius * radius  # nu t in l0^2
            on_lattice, on_k2 = -np.expm1(-symbol * span) / symbol, -np.expm1(-k2 * span) / k2
        on_lattice[mean], on_k2[mean] = 0.0, 0.0
        lat, dis, con = (discrete * on_lattice).sum(), (discrete * on_k2).sum(), (continuous * on_k2).sum()
        out[time] = (lat / con, dis / con, lat / dis)
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--radii", default="2.55,2.7,2.9", help="kernel radii R in l0, comma-separated")
    parser.add_argument("--effective-radius", type=float, default=2.4, help="r_e / l0 of the MPS Laplacian")
    parser.add_argument("--times", default="0.1,0.3,1", help="nu t / R^2, comma-separated")
    parser.add_argument("--lattice", type=int, default=64, help="the periodic lattice's side in l0")
    args = parser.parse_args(argv)
    times = [float(t) for t in args.times.split(",")]
    print("| R / l0 | nu t / R^2 | lattice / continuum | discrete kernel, k^2 | symbol alone |")
    print("|---|---|---|---|---|")
    for radius in (float(r) for r in args.radii.split(",")):
        for time, (total, kernel, symbol) in responses(radius, args.effective_radius, times, args.lattice).items():
            label = "steady" if time is None else f"{time:g}"
            print(f"| {radius:g} | {label} | {total:.3f} | {kernel:.3f} | {symbol:.3f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
