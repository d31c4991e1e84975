"""Numerical pieces of the seed figures 4, 7-10, 13 and 16 (riffle_tools.seed_figures draws them). numpy only.

- raster(): what a camera sees of a set of spheres, orthographic, from above or through the front wall: per pixel
  the index of the nearest sphere (a depth buffer), optionally cut by a plane (the seed's cross-sections).
- neighbour_pairs(): all pairs closer than a radius, by a cell list (no scipy needed).
- velocity_gradient(): the least-squares (MPS/SPH-style, kernel-weighted) velocity gradient at each particle.
- strain_and_q(): |S|^2 and the Q-criterion from velocity gradients (seed Eqs. 29-30).
"""
import math

import numpy as np

# The two views the seed's images use. axes: the image's (horizontal, vertical) coordinates; depth: the axis the
# camera looks along; sign: +1 when the camera is on the low side of that axis (the front wall, y < 0) and looks
# towards +depth, -1 when on the high side (above the bed) and looks down.
VIEWS = {"top": ((0, 1), 2, -1), "front": ((0, 2), 1, +1)}


def raster(centres, radii, view, pixel, extent, clip=None):
    """Depth-buffer image of spheres seen orthographically.

    centres (N, 3) and radii (N,) in the tank frame; view "top" (looking down, image x-y) or "front" (looking along
    +y from y < 0, image x-z); pixel: the pixel size [m]; extent ((a0, a1), (b0, b1)): the image's span along its
    two axes [m]. clip: an optional cut plane at this coordinate along the depth axis: what lies on the camera's
    side of it is removed (spheres cut by it show their cut disc), as in the seed's cross-sections.
    Returns (index, depth): int arrays (nb, na) of the visible sphere per pixel (-1: none) and float arrays of the
    depth of the visible surface along the viewing direction (sign * coordinate; inf where none). Row j, column i
    is the pixel centred at (a0 + (i + 1/2) pixel, b0 + (j + 1/2) pixel)."""
    (ia, ib), id_, sign = VIEWS[view]
    (a0, a1), (b0, b1) = extent
    na, nb = int(round((a1 - a0) / pixel)), int(round((b1 - b0) / pixel))
    centres = np.asarray(centres, dtype=float)
    radii = np.asarray(radii, dtype=float)
    pixels, depths, owners = [], [], []
    half = np.ceil(radii / pixel).astype(int) + 1
    for h in np.unique(half):  # grains of one window size together: one offset grid per group
        members = np.where(half == h)[0]
        offsets = np.arange(-h, h + 1)
        da, db = np.meshgrid(offsets, offsets, indexing="ij")
        da, db = da.ravel(), db.ravel()
        c = centres[members]
        r = radii[members][:, None]
        col = np.floor((c[:, ia] - a0) / pixel).astype(int)[:, None] + da[None, :]
        row = np.floor((c[:, ib] - b0) / pixel).astype(int)[:, None] + db[None, :]
        d2 = ((a0 + (col + 0.5) * pixel - c[:, ia:ia + 1]) ** 2 + (b0 + (row + 0.5) * pixel - c[:, ib:ib + 1]) ** 2)
        inside = (d2 < r * r) & (col >= 0) & (col < na) & (row >= 0) & (row < nb)
        chord = np.sqrt(np.maximum(r * r - d2, 0.0))
        near = sign * c[:, id_:id_ + 1] - chord  # the sphere's surface facing the camera, as a depth
        if clip is not None:
            far = sign * c[:, id_:id_ + 1] + chord
            inside &= far >= sign * clip      # wholly on the camera's side of the cut: removed
            near = np.maximum(near, sign * clip)  # cut: the disc on the plane is what shows
        owner = np.broadcast_to(members[:, None], inside.shape)
        pixels.append((row * na + col)[inside])
        depths.append(near[inside])
        owners.append(owner[inside])
    index = np.full(na * nb, -1, dtype=np.int64)
    depth = np.full(na * nb, np.inf)
    if pixels:
        pixels, depths, owners = np.concatenate(pixels), np.concatenate(depths), np.concatenate(owners)
        order = np.lexsort((depths, pixels))  # per pixel, the nearest first
        first = np.ones(len(order), dtype=bool)
        first[1:] = pixels[order][1:] != pixels[order][:-1]
        chosen = order[first]
        index[pixels[chosen]] = owners[chosen]
        depth[pixels[chosen]] = depths[chosen]
    return index.reshape(nb, na), depth.reshape(nb, na)


def band_fractions(labels, index, rows_per_band, bands, classes):
    """Per band of image rows (row 0 first) and per class, the fraction of the band's pixels whose visible sphere
    has that class. labels: per-sphere class; index: a raster() index image. Returns (bands, len(classes))."""
    shown = np.where(index >= 0, np.asarray(labels)[np.maximum(index, 0)], -1)
    result = np.zeros((bands, len(classes)))
    for k in range(bands):
        band = shown[k * rows_per_band:(k + 1) * rows_per_band]
        if band.size:
            for j, c in enumerate(classes):
                result[k, j] = np.count_nonzero(band == c) / band.size
    return result


def neighbour_pairs(points, radius):
    """All ordered pairs (i, j), i != j, with |x_j - x_i| < radius, by a cell list of cells `radius` wide."""
    points = np.asarray(points, dtype=float)
    n = len(points)
    if n == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    cell = np.floor((points - points.min(axis=0)) / radius).astype(np.int64)
    dims = cell.max(axis=0) + 1
    key = (cell[:, 0] * dims[1] + cell[:, 1]) * dims[2] + cell[:, 2]
    order = np.argsort(key, kind="stable")
    sorted_keys = key[order]
    firsts, seconds = [], []
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dz in (-1, 0, 1):
                other = cell + np.array([dx, dy, dz])
                valid = np.all((other >= 0) & (other < dims), axis=1)
                other_key = (other[:, 0] * dims[1] + other[:, 1]) * dims[2] + other[:, 2]
                start = np.searchsorted(sorted_keys, other_key, side="left")
                stop = np.searchsorted(sorted_keys, other_key, side="right")
                counts = np.where(valid, stop - start, 0)
                total = int(counts.sum())
                if total == 0:
                    continue
                i = np.repeat(np.arange(n), counts)
                # position within each particle's run of candidates, added to that run's start
                within = np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
                j = order[np.repeat(start, counts) + within]
                firsts.append(i)
                seconds.append(j)
    i, j = np.concatenate(firsts), np.concatenate(seconds)
    d2 = np.sum((points[j] - points[i]) ** 2, axis=1)
    keep = (i != j) & (d2 < radius * radius)
    return i[keep], j[keep]


def velocity_gradient(points, velocities, re, min_conditioning=0.05):
    """The velocity gradient G[a, b] = du_a/dx_b at each particle by kernel-weighted least squares over the
    neighbours within re (the MPS weight w = re/r - 1):

        M_i = sum_j w_ij r_ij r_ij^T / r_ij^2,   B_i = sum_j w_ij (u_j - u_i) r_ij^T / r_ij^2,   G_i = B_i M_i^-1.

    It is exact for a linear velocity field whatever the neighbours' arrangement (near the free surface and the
    walls too), unlike the plain MPS gradient (d/n0) sum, which needs a full isotropic neighbourhood.
    Returns (G (N, 3, 3), valid (N,)): valid is false where M is ill-conditioned (neighbours nearly in a plane or
    line: smallest eigenvalue below min_conditioning times the mean eigenvalue); G is zero there."""
    points = np.asarray(points, dtype=float)
    velocities = np.asarray(velocities, dtype=float)
    n = len(points)
    i, j = neighbour_pairs(points, re)
    r = points[j] - points[i]
    dist2 = np.sum(r * r, axis=1)
    w = re / np.sqrt(dist2) - 1.0
    du = velocities[j] - velocities[i]
    M = np.zeros((n, 3, 3))
    B = np.zeros((n, 3, 3))
    for a in range(3):
        for b in range(3):
            M[:, a, b] = np.bincount(i, weights=w * r[:, a] * r[:, b] / dist2, minlength=n)
            B[:, a, b] = np.bincount(i, weights=w * du[:, a] * r[:, b] / dist2, minlength=n)
    eigen = np.linalg.eigvalsh(M)
    valid = eigen[:, 0] > min_conditioning * np.maximum(eigen.mean(axis=1), 1e-300)
    G = np.zeros((n, 3, 3))
    if valid.any():
        G[valid] = B[valid] @ np.linalg.inv(M[valid])
    return G, valid


def strain_and_q(G):
    """|S|^2 = S:S and Q = (|Omega|^2 - |S|^2) / 2 (seed Eqs. 29-30), S and Omega the symmetric and
    antisymmetric parts of the velocity gradient, |X|^2 the sum of the squares of X's entries (Frobenius).
    A simple shear u = (a z, 0, 0) has |S|^2 = a^2/2, Q = 0; a rigid rotation at w, |S|^2 = 0, Q = w^2."""
    G = np.asarray(G, dtype=float)
    transposed = np.swapaxes(G, -1, -2)
    S = 0.5 * (G + transposed)
    omega = 0.5 * (G - transposed)
    s2 = np.sum(S * S, axis=(-1, -2))
    return s2, 0.5 * (np.sum(omega * omega, axis=(-1, -2)) - s2)


def infer_spacing(points):
    """The particle spacing of a lattice-like set: the median nearest-neighbour distance."""
    points = np.asarray(points, dtype=float)
    if len(points) < 2:
        return math.nan
    span = np.ptp(points, axis=0).max()
    radius = span / max(len(points), 1) ** (1 / 3) * 2.0  # a few spacings: every particle finds a neighbour
    i, j = neighbour_pairs(points, radius)
    d = np.sqrt(np.sum((points[j] - points[i]) ** 2, axis=1))
    nearest = np.full(len(points), np.inf)
    np.minimum.at(nearest, i, d)
    return float(np.median(nearest[np.isfinite(nearest)]))
