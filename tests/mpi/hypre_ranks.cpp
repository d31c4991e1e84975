// The pressure solve over several MPI ranks (CTest runs it under mpiexec with 1, 2 and 4 ranks): the tank lattice of
// tests/support/pressure_lattice.hpp split into one contiguous block of rows per rank, each rank assembling only its
// rows (columns global), solved by hypre's BoomerAMG-PCG over MPI_COMM_WORLD. Every rank gathers the solution and
// checks it against the direct solve (Eigen's sparse Cholesky), to the bound the stopping rule gives, and against
// the same solver on this rank alone (MPI_COMM_SELF), to twice that bound: the two stop at |r| <= tol |b| with
// different V-cycles (the coarsening depends on the partition), so they agree to the tolerance, not to rounding.
// Exit 0 when every rank passes; the failing checks are printed with their rank.
//
//   mpiexec -n N riffle_mpi_hypre_ranks [n]     n: the lattice's side (default 20: 8,000 rows)
// Rank 0 also prints the wall time of the N-rank solve (assembly, set-up and solve; the median of three) and of the
// one-rank solve beside it: the strong scaling of the distributed solve on this machine.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "systems/physics/mps/hypre_pressure_solver.hpp"
#include "tests/support/pressure_lattice.hpp"

int main(int argc, char** argv) {
  using namespace riffle;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  int failures = 0;
  const auto expect = [&](bool condition, const char* what, double value) {
    if (!condition) {
      std::fprintf(stderr, "rank %d of %d: FAILED %s (%g)\n", rank, ranks, what, value);
      ++failures;
    }
  };
  const double tolerance = 1e-10;
  const long side = argc > 1 ? std::atol(argv[1]) : 20;
  if (side < 2) {
    std::fprintf(stderr, "riffle_mpi_hypre_ranks: the lattice's side must be at least 2\n");
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  const test::TankLattice lattice(side);
  const std::vector<double> rhs = test::TankLattice::varied_rhs(lattice.rows());
  const std::vector<double> exact = lattice.direct_solve(rhs);

  // This rank's block: rows split as evenly as they go, the first blocks one row longer.
  const std::size_t rows = lattice.rows(), base = rows / ranks, extra = rows % ranks;
  const std::size_t urank = static_cast<std::size_t>(rank);
  const std::size_t first = urank * base + std::min(urank, extra), count = base + (urank < extra ? 1 : 0);
  std::vector<std::size_t> block_row_start;
  const PressureMatrix block = lattice.block(first, count, block_row_start);
  std::vector<double> block_rhs(rhs.begin() + static_cast<std::ptrdiff_t>(first),
                                rhs.begin() + static_cast<std::ptrdiff_t>(first + count));
  std::vector<double> block_solution(count, 0.0);
  HyprePressureSolver over_all(HyprePressureSolver::Ranks::kAll);
  // Three solves from the same start, timed; the checks read the last.
  std::vector<double> seconds;
  PressureSolveOutcome outcome;
  for (int repeat = 0; repeat < 3; ++repeat) {
    std::fill(block_solution.begin(), block_solution.end(), 0.0);
    MPI_Barrier(MPI_COMM_WORLD);
    const double start = MPI_Wtime();
    outcome = over_all.solve(block, PressureRowBlock{first, rows}, block_rhs, block_solution, tolerance, 200);
    MPI_Barrier(MPI_COMM_WORLD);
    seconds.push_back(MPI_Wtime() - start);
  }
  std::sort(seconds.begin(), seconds.end());
  expect(outcome.converged, "converged over all ranks", static_cast<double>(outcome.iterations));
  expect(outcome.relative_residual <= 1.01 * tolerance, "true residual within the tolerance", outcome.relative_residual);
  expect(outcome.iterations > 0 && outcome.iterations < 40, "iterations few (multigrid)",
         static_cast<double>(outcome.iterations));

  // Gather the whole solution on every rank.
  std::vector<int> counts(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks));
  const int my_count = static_cast<int>(count);
  MPI_Allgather(&my_count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<double> solution(rows);
  MPI_Allgatherv(block_solution.data(), my_count, MPI_DOUBLE, solution.data(), counts.data(), offsets.data(),
                 MPI_DOUBLE, MPI_COMM_WORLD);

  // The residual of the gathered solution, recomputed serially, and its error against the direct solve: bounded by
  // cond(M) times the residual; cond(M) of this lattice is below 4 n^2 / pi^2 * 12 ~ 2,000 (its extreme
  // eigenvalues about 12 and pi^2 / (4 n^2)), so 1e3 * tol leaves room.
  std::vector<double> residual = lattice.product(solution);
  for (std::size_t k = 0; k < rows; ++k) residual[k] = rhs[k] - residual[k];
  const double gathered_residual = test::norm(residual) / test::norm(rhs);
  expect(std::abs(gathered_residual - outcome.relative_residual) <= 1e-3 * tolerance,
         "the reported residual is the gathered solution's", gathered_residual);
  std::vector<double> error(rows);
  for (std::size_t k = 0; k < rows; ++k) error[k] = solution[k] - exact[k];
  const double error_norm = test::norm(error) / test::norm(exact);
  expect(error_norm < 1e4 * tolerance, "error against the direct solve", error_norm);

  // The same solver on this rank alone, from the same start.
  std::vector<double> alone(rows, 0.0);
  HyprePressureSolver this_one;
  const double alone_start = MPI_Wtime();
  const PressureSolveOutcome single = this_one.solve(lattice.matrix(), rhs, alone, tolerance, 200);
  const double alone_seconds = MPI_Wtime() - alone_start;
  for (std::size_t k = 0; k < rows; ++k) error[k] = solution[k] - alone[k];
  const double difference = test::norm(error) / test::norm(alone);
  expect(single.converged, "converged on one rank", static_cast<double>(single.iterations));
  expect(difference < 2e4 * tolerance, "the N-rank solution within the tolerance's bound of the 1-rank one", difference);

  if (rank == 0)
    std::printf("%d rank(s), %zu rows: %lld iterations (one rank alone: %lld), residual %.3g, error against the direct "
                "solve %.3g, difference from one rank %.3g; %.4f s a solve on %d rank(s), %.4f s alone\n",
                ranks, rows, static_cast<long long>(outcome.iterations), static_cast<long long>(single.iterations),
                outcome.relative_residual, error_norm, difference, seconds[1], ranks, alone_seconds);
  int all_failures = 0;
  MPI_Allreduce(&failures, &all_failures, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  MPI_Finalize();
  return all_failures == 0 ? 0 : 1;
}
