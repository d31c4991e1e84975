#pragma once
// The pressure equation handed to hypre (Lawrence Livermore's scalable linear solvers, Falgout & Yang 2002):
// conjugate gradients preconditioned by one V-cycle of BoomerAMG, its algebraic multigrid (Henson & Yang 2002), the
// solver that particle and mesh codes running on many machines give their pressure equation to. A run uses it at one
// rank (MPI_COMM_SELF), so that the in-house two-level PCG (pressure_preconditioner.hpp) and the solver a distributed
// run would use can be measured on the same systems: iterations and time per solve, the same stopping rule. Over all
// the ranks (MPI_COMM_WORLD) each rank hands it its own block of rows (tests/mpi/hypre_ranks.cpp: 1, 2, 4 ranks).
//
// hypre needs MPI: the first solve initialises it (MPI_THREAD_SERIALIZED: the solve runs on whichever oneTBB worker
// the step graph gives it, one at a time) unless the process already has, and finalises what it started at exit.
// A build without hypre (CMake did not find libhypre-dev) has hypre_available() false, and the scene reader refuses
// the choice before a run starts.
#include <cstdint>
#include <vector>

#include "systems/physics/mps/pressure_preconditioner.hpp"

namespace riffle {

/// Whether this build links hypre (and MPI).
bool hypre_available();

/// What one solve did.
struct PressureSolveOutcome {
  std::int64_t iterations = 0;
  double relative_residual = 0.0;  ///< the true |b - M x| / |b| at the end (0 when b = 0)
  bool converged = false;          ///< the recursive residual met the tolerance, the true one within 10 times it
};

/// The rows of the global system one rank holds: [first_row, first_row + rows) of global_rows.
struct PressureRowBlock {
  std::size_t first_row = 0;
  std::size_t global_rows = 0;
};

/// BoomerAMG-preconditioned CG for M x = b (M symmetric positive definite: PressureMatrix), to
/// |b - M x| <= tolerance |b| in the two-norm, the in-house PCG's criterion, from x as given (the warm start).
/// The matrix changes every step (the particles move), so each solve assembles it and sets BoomerAMG up anew.
/// Over this rank alone (MPI_COMM_SELF), or over all the ranks (MPI_COMM_WORLD), each holding a block of rows.
class HyprePressureSolver {
 public:
  enum class Ranks { kThisOne, kAll };
  explicit HyprePressureSolver(Ranks ranks = Ranks::kThisOne);
  ~HyprePressureSolver();
  HyprePressureSolver(const HyprePressureSolver&) = delete;
  HyprePressureSolver& operator=(const HyprePressureSolver&) = delete;

  /// The whole system on this rank (rows 0 .. matrix.rows - 1).
  PressureSolveOutcome solve(const PressureMatrix& matrix, const std::vector<double>& rhs, std::vector<double>& solution,
                             double tolerance, std::int64_t max_iterations);
  /// This rank's block of rows: `matrix` holds them (its columns are global row indices), `rhs` and `solution`
  /// their entries. Collective over the ranks of Ranks::kAll: every rank calls it with its own block, the blocks
  /// in rank order and together all the rows.
  PressureSolveOutcome solve(const PressureMatrix& matrix, const PressureRowBlock& block, const std::vector<double>& rhs,
                             std::vector<double>& solution, double tolerance, std::int64_t max_iterations);

 private:
  [[maybe_unused]] Ranks ranks_;  // read only by the hypre build
  // hypre's index type per row and the entries' rows, reused between solves (no allocation once sized).
  std::vector<int> entries_per_row_, rows_, columns_;
  std::vector<double> values_;
};

}  // namespace riffle
