"""PCG iteration counts of one dumped MPS pressure system under different preconditioners.

The engine's PCG (systems/mps/fluid_pressure.cpp, two-level additive: Jacobi plus a Galerkin coarse solve on cubic
aggregates of 4 l0) is the most expensive part of a fluid step, and each idea for a better preconditioner costs a
C++ implementation to test. This script answers the first question offline in a minute: how many iterations, and
how many matrix-vector products' worth of work, would a variant need on the very system the engine solved?

Usage (Debian's python3 with numpy and scipy):
    tools/riffle-tools ppe-preconditioner-study PREFIX

PREFIX.* are the raw arrays of one assembled system. The engine has no switch to write them (it is not a user
feature); apply this temporary patch to the start of the "z = M^-1 r" block in FluidPressureSolve::run, rebuild,
resume a checkpoint with RIFFLE_DUMP=PREFIX RIFFLE_DUMP_STEP=N, and revert:

    if (const char* dump = std::getenv("RIFFLE_DUMP"))
      if (context.step() == std::strtoull(std::getenv("RIFFLE_DUMP_STEP"), nullptr, 10)) {
        const auto write = [&](const char* name, const void* data, std::size_t bytes) {
          FILE* f = std::fopen((std::string(dump) + "." + name).c_str(), "wb");
          std::fwrite(data, 1, bytes, f);
          std::fclose(f);
        };
        std::vector<double> positions(3 * unknowns);
        for (std::size_t row = 0; row < unknowns; ++row)
          for (int a = 0; a < 3; ++a) positions[3 * row + a] = particles.predicted_position[slot_of_[row]][a];
        write("row_start", row_start_.data(), row_start_.size() * sizeof(std::size_t));
        write("columns", compact_columns_.data(), compact_columns_.size() * 4);
        write("values", compact_values_.data(), compact_values_.size() * 8);
        write("diagonal", diagonal_.data(), unknowns * 8);
        write("rhs", rhs_.data(), unknowns * 8);
        write("start", solution_.data(), unknowns * 8);
        write("positions", positions.data(), positions.size() * 8);
        const double meta[4] = {constants_.spacing, context.model.tank.origin[0], context.model.tank.origin[1],
                                context.model.tank.origin[2]};
        write("meta", meta, sizeof(meta));
      }

Cost model ("matvecs"): work per iteration in units of one product with A (its stored entries plus the diagonal),
counting the restriction and prolongation by their nonzeros and the coarse solve by the nonzeros of its LU factors.
It leaves out the set-up (aggregation, the Galerkin product, the factorisation), which the smoothed variants make
several times dearer.
"""
import argparse
import sys

import numpy as np

try:
    import scipy.sparse as sp
    import scipy.sparse.linalg as spl
except ImportError:  # pragma: no cover - depends on the machine; --help still answers
    sp = spl = None

TOLERANCE = 1.0e-8  # |r| <= tol |b|, the engine's default (fluid.solver_tolerance)


def load(prefix):
    row_start = np.fromfile(prefix + ".row_start", dtype=np.uint64).astype(np.int64)
    columns = np.fromfile(prefix + ".columns", dtype=np.uint32).astype(np.int64)
    values = np.fromfile(prefix + ".values")
    diagonal = np.fromfile(prefix + ".diagonal")
    rhs = np.fromfile(prefix + ".rhs")
    start = np.fromfile(prefix + ".start")
    positions = np.fromfile(prefix + ".positions").reshape(-1, 3)
    spacing, *origin = np.fromfile(prefix + ".meta")
    rows = len(diagonal)
    matrix = (sp.csr_matrix((values, columns, row_start), shape=(rows, rows)) + sp.diags(diagonal)).tocsr()
    return matrix, diagonal, rhs, start, positions, spacing, np.array(origin)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("prefix", metavar="PREFIX", help="PREFIX.* hold the raw arrays of one assembled system")
    prefix = parser.parse_args(argv).prefix
    if sp is None:
        sys.exit("ppe_preconditioner_study: needs scipy (Debian's python3-scipy) for /usr/bin/python3")
    A, D, b, x0, positions, l0, origin = load(prefix)
    n = len(D)
    matvec_entries = A.nnz
    print(f"{n} unknowns, {A.nnz - n} off-diagonal entries, asymmetry {abs(A - A.T).max():.1e}")

    def pcg(apply, tolerance=TOLERANCE, limit=5000):
        x = x0.copy()
        r = b - A @ x
        target = tolerance * np.linalg.norm(b)
        z = apply(r)
        p = z.copy()
        rz = r @ z
        iterations = 0
        while np.linalg.norm(r) > target and iterations < limit:
            Ap = A @ p
            step = rz / (p @ Ap)
            x += step * p
            r -= step * Ap
            iterations += 1
            if np.linalg.norm(r) <= target:
                break
            z = apply(r)
            rz_next = r @ z
            p = z + (rz_next / rz) * p
            rz = rz_next
        return iterations, x

    _, reference = pcg(lambda r: r / D, tolerance=1.0e-13)

    def report(name, apply, cost):
        iterations, x = pcg(apply)
        error = np.linalg.norm(x - reference) / np.linalg.norm(reference)
        print(f"{name:58s} {iterations:4d} it  {cost:4.2f} matvecs/it  {iterations * cost:6.1f} matvecs  "
              f"error {error:.1e}", flush=True)

    def aggregates(size):
        cells = np.floor((positions - origin) / size).astype(np.int64)
        cells -= cells.min(axis=0)
        _, aggregate = np.unique((cells[:, 2] * 100000 + cells[:, 1]) * 1000 + cells[:, 0], return_inverse=True)
        return sp.csr_matrix((np.ones(n), (np.arange(n), aggregate)), shape=(n, aggregate.max() + 1))

    def two_level(P):
        coarse = spl.splu((P.T @ A @ P).tocsc())
        cost = 1.0 + (2 * P.nnz + coarse.L.nnz + coarse.U.nnz) / matvec_entries
        return (lambda r: r / D + P @ coarse.solve(P.T @ r)), cost, P.shape[1]

    report("Jacobi", lambda r: r / D, 1.0)
    # The engine: cells of max(4, cbrt(n / 500)) l0.
    engine_cells = max(4.0, np.ceil(np.cbrt(n / 500.0)))
    for size in sorted({2.0, 3.0, engine_cells, 5.0, 6.0}):
        apply, cost, coarse = two_level(aggregates(size * l0))
        report(f"two-level additive, {size:g} l0 aggregates ({coarse} coarse)", apply, cost)

    # Smoothed aggregation: P = (I - omega D^-1 A) P0, omega = (4/3) / rho(D^-1 A).
    scaled = sp.diags(1.0 / np.sqrt(D)) @ A @ sp.diags(1.0 / np.sqrt(D))
    rho = spl.eigsh(scaled, k=1, which="LA", return_eigenvectors=False)[0]
    for size in (3.0, 4.0, 5.0):
        P0 = aggregates(size * l0)
        P = (P0 - (4.0 / 3.0 / rho) * sp.diags(1.0 / D) @ (A @ P0)).tocsr()
        apply, cost, coarse = two_level(P)
        report(f"two-level additive, smoothed aggregation, {size:g} l0 ({coarse})", apply, cost)

    # Block Jacobi on small cells, with and without the engine's coarse level.
    P4 = aggregates(engine_cells * l0)
    coarse4 = spl.splu((P4.T @ A @ P4).tocsc())
    for size in (2.0, 3.0):
        members = aggregates(size * l0).tocsc()
        blocks = []
        for a in range(members.shape[1]):
            index = members.indices[members.indptr[a]:members.indptr[a + 1]]
            blocks.append((index, np.linalg.inv(A[index][:, index].toarray())))
        block_entries = sum(len(index) ** 2 for index, _ in blocks)

        def block_jacobi(r, blocks=blocks):
            z = np.empty_like(r)
            for index, inverse in blocks:
                z[index] = inverse @ r[index]
            return z

        cost = (matvec_entries + block_entries) / matvec_entries
        report(f"block Jacobi on {size:g} l0 cells", block_jacobi, cost)
        coarse_cost = (2 * P4.nnz + coarse4.L.nnz + coarse4.U.nnz) / matvec_entries
        report(f"block Jacobi on {size:g} l0 cells + the engine's coarse level",
               lambda r, bj=block_jacobi: bj(r) + P4 @ coarse4.solve(P4.T @ r), cost + coarse_cost)

    # Symmetric multiplicative two-level (a two-grid V-cycle): Jacobi, coarse correction, Jacobi.
    coarse_cost = (2 * P4.nnz + coarse4.L.nnz + coarse4.U.nnz) / matvec_entries
    for weight in (0.6, 0.8):
        def multiplicative(r, weight=weight):
            z = weight * r / D
            z = z + P4 @ coarse4.solve(P4.T @ (r - A @ z))
            return z + weight * (r - A @ z) / D
        report(f"multiplicative two-level, Jacobi weight {weight}", multiplicative, 3.0 + coarse_cost)


if __name__ == "__main__":
    sys.exit(main())
