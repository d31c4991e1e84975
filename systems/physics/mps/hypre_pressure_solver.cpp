#include "systems/physics/mps/hypre_pressure_solver.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#if RIFFLE_WITH_HYPRE
#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <mpi.h>

#include <cstdlib>
#include <mutex>
#endif

namespace riffle {

#if RIFFLE_WITH_HYPRE

static_assert(std::is_same_v<HYPRE_BigInt, int> && std::is_same_v<HYPRE_Int, int> &&
                  std::is_same_v<HYPRE_Complex, double>,
              "riffle hands hypre int indices and double values (Debian's libhypre-dev: no BIGINT, double)");

bool hypre_available() { return true; }

namespace {
bool mpi_started_here = false;

void finalise_hypre_and_mpi() {
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (finalised) return;  // the program started MPI and has finalised it: hypre's memory goes with the process
  HYPRE_Finalize();
  if (mpi_started_here) MPI_Finalize();
}

/// MPI and hypre, once per process (see the header).
void start_hypre() {
  static std::once_flag once;
  std::call_once(once, [] {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
      int provided = 0;
      if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
        throw std::runtime_error("the hypre pressure solve could not initialise MPI");
      if (provided < MPI_THREAD_SERIALIZED)
        throw std::runtime_error("the hypre pressure solve needs MPI_THREAD_SERIALIZED (this MPI gives " +
                                 std::to_string(provided) + ")");
      mpi_started_here = true;
    }
    HYPRE_Init();
    std::atexit(finalise_hypre_and_mpi);
  });
}

/// A hypre call that must succeed; a PCG that stops at its iteration limit reports HYPRE_ERROR_CONV, which the
/// solve reads from the residual instead.
void check(HYPRE_Int code, const char* call) {
  if (code == 0) return;
  if (HYPRE_CheckError(code, HYPRE_ERROR_CONV) && !HYPRE_CheckError(code, HYPRE_ERROR_GENERIC) &&
      !HYPRE_CheckError(code, HYPRE_ERROR_MEMORY) && !HYPRE_CheckError(code, HYPRE_ERROR_ARG)) {
    HYPRE_ClearAllErrors();
    return;
  }
  char description[256] = {0};
  HYPRE_DescribeError(code, description);
  HYPRE_ClearAllErrors();
  throw std::runtime_error(std::string("hypre: ") + call + " failed: " + description);
}

/// hypre's objects of one solve, destroyed however the solve ends.
struct SolveObjects {
  HYPRE_IJMatrix matrix = nullptr;
  HYPRE_IJVector rhs = nullptr, solution = nullptr, residual = nullptr;
  HYPRE_Solver pcg = nullptr, amg = nullptr;
  ~SolveObjects() {
    if (pcg) HYPRE_ParCSRPCGDestroy(pcg);
    if (amg) HYPRE_BoomerAMGDestroy(amg);
    if (residual) HYPRE_IJVectorDestroy(residual);
    if (solution) HYPRE_IJVectorDestroy(solution);
    if (rhs) HYPRE_IJVectorDestroy(rhs);
    if (matrix) HYPRE_IJMatrixDestroy(matrix);
    HYPRE_ClearAllErrors();
  }
};

/// A vector over rows [first, last] of this rank (last = first - 1: none), holding `values`.
HYPRE_ParVector parcsr_vector(HYPRE_IJVector& vector, MPI_Comm communicator, int first, int last, const int* indices,
                              const double* values, const char* what) {
  const int rows = last - first + 1;
  check(HYPRE_IJVectorCreate(communicator, first, last, &vector), what);
  check(HYPRE_IJVectorSetObjectType(vector, HYPRE_PARCSR), what);
  check(HYPRE_IJVectorInitialize(vector), what);
  if (rows > 0) check(HYPRE_IJVectorSetValues(vector, rows, indices, values), what);
  check(HYPRE_IJVectorAssemble(vector), what);
  void* object = nullptr;
  check(HYPRE_IJVectorGetObject(vector, &object), what);
  return static_cast<HYPRE_ParVector>(object);
}
}  // namespace

PressureSolveOutcome HyprePressureSolver::solve(const PressureMatrix& matrix, const PressureRowBlock& block,
                                                const std::vector<double>& rhs, std::vector<double>& solution,
                                                double tolerance, std::int64_t max_iterations) {
  PressureSolveOutcome outcome;
  if (block.global_rows == 0) {  // every rank sees the same global size: all return here together
    outcome.converged = true;
    return outcome;
  }
  if (block.global_rows > static_cast<std::size_t>(std::numeric_limits<int>::max() / 2))
    throw std::runtime_error("the hypre pressure solve takes at most 2^30 unknowns (int indices)");
  start_hypre();
  const MPI_Comm communicator = ranks_ == Ranks::kAll ? MPI_COMM_WORLD : MPI_COMM_SELF;
  const int rows = static_cast<int>(matrix.rows);
  const int first = static_cast<int>(block.first_row);
  const int last = first + rows - 1;  // first - 1 for a rank without rows: hypre's empty range

  // Row by row (global indices), the diagonal first, then the off-diagonal entries as the CSR holds them.
  entries_per_row_.resize(matrix.rows);
  rows_.resize(matrix.rows);
  const std::size_t off_diagonal = matrix.row_start[matrix.rows];
  columns_.resize(matrix.rows + off_diagonal);
  values_.resize(matrix.rows + off_diagonal);
  std::size_t entry = 0;
  for (std::size_t row = 0; row < matrix.rows; ++row) {
    rows_[row] = first + static_cast<int>(row);
    entries_per_row_[row] = static_cast<int>(1 + matrix.row_start[row + 1] - matrix.row_start[row]);
    columns_[entry] = rows_[row];
    values_[entry++] = matrix.diagonal[row];
    for (std::size_t k = matrix.row_start[row]; k < matrix.row_start[row + 1]; ++k) {
      columns_[entry] = static_cast<int>(matrix.columns[k]);
      values_[entry++] = matrix.values[k];
    }
  }

  SolveObjects objects;
  check(HYPRE_IJMatrixCreate(communicator, first, last, first, last, &objects.matrix), "IJMatrixCreate");
  check(HYPRE_IJMatrixSetObjectType(objects.matrix, HYPRE_PARCSR), "IJMatrixSetObjectType");
  check(HYPRE_IJMatrixSetRowSizes(objects.matrix, entries_per_row_.data()), "IJMatrixSetRowSizes");
  check(HYPRE_IJMatrixInitialize(objects.matrix), "IJMatrixInitialize");
  check(HYPRE_IJMatrixSetValues(objects.matrix, rows, entries_per_row_.data(), rows_.data(), columns_.data(),
                                values_.data()),
        "IJMatrixSetValues");
  check(HYPRE_IJMatrixAssemble(objects.matrix), "IJMatrixAssemble");
  void* parcsr = nullptr;
  check(HYPRE_IJMatrixGetObject(objects.matrix, &parcsr), "IJMatrixGetObject");
  const auto system = static_cast<HYPRE_ParCSRMatrix>(parcsr);
  const HYPRE_ParVector b =
      parcsr_vector(objects.rhs, communicator, first, last, rows_.data(), rhs.data(), "the right-hand side");
  const HYPRE_ParVector x =
      parcsr_vector(objects.solution, communicator, first, last, rows_.data(), solution.data(), "the first guess");
  double rhs_squared = 0.0;
  check(HYPRE_ParVectorInnerProd(b, b, &rhs_squared), "ParVectorInnerProd");
  if (rhs_squared == 0.0) {  // as the in-house PCG: M x = 0 has x = 0
    std::fill(solution.begin(), solution.end(), 0.0);
    outcome.converged = true;
    return outcome;
  }

  // One V-cycle a CG iteration. The settings follow hypre's advice for 3D Poisson-like problems on many ranks
  // (its user manual, BoomerAMG): HMIS coarsening with extended+i interpolation truncated to 4 entries a row, a
  // strength threshold of 0.5 (3D), and aggressive coarsening on the first level, which keeps the set-up cheap
  // for the MPS stencil (up to 57 entries a row at r_e = 2.4 l0; without it the set-up took 2.5 times as
  // long). The smoother is l1-Jacobi: symmetric, as CG needs, and the same whatever the ranks' partition (hybrid
  // Gauss-Seidel is Gauss-Seidel only inside a rank). Over the first 50 steps of the seed tank at l0 = 5 mm it
  // took 7.8 iterations where l1-Gauss-Seidel took 4.8, but 74 ms a solve against 94 (docs/BENCHMARKS.md, "The
  // pressure solve on hypre's BoomerAMG").
  check(HYPRE_BoomerAMGCreate(&objects.amg), "BoomerAMGCreate");
  HYPRE_BoomerAMGSetPrintLevel(objects.amg, 0);
  HYPRE_BoomerAMGSetCoarsenType(objects.amg, 10);
  HYPRE_BoomerAMGSetInterpType(objects.amg, 6);
  HYPRE_BoomerAMGSetPMaxElmts(objects.amg, 4);
  HYPRE_BoomerAMGSetStrongThreshold(objects.amg, 0.5);
  HYPRE_BoomerAMGSetRelaxType(objects.amg, 18);
  HYPRE_BoomerAMGSetNumSweeps(objects.amg, 1);
  HYPRE_BoomerAMGSetAggNumLevels(objects.amg, 1);
  HYPRE_BoomerAMGSetMaxIter(objects.amg, 1);
  HYPRE_BoomerAMGSetTol(objects.amg, 0.0);

  check(HYPRE_ParCSRPCGCreate(communicator, &objects.pcg), "ParCSRPCGCreate");
  HYPRE_PCGSetTol(objects.pcg, tolerance);
  HYPRE_PCGSetAbsoluteTol(objects.pcg, 0.0);
  HYPRE_PCGSetTwoNorm(objects.pcg, 1);  // |r| <= tol |b| in the two-norm, as the in-house PCG
  HYPRE_PCGSetMaxIter(objects.pcg,
                      static_cast<int>(std::min<std::int64_t>(max_iterations, std::numeric_limits<int>::max())));
  HYPRE_PCGSetPrintLevel(objects.pcg, 0);
  HYPRE_PCGSetPrecond(objects.pcg, reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSolve),
                      reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSetup), objects.amg);
  check(HYPRE_ParCSRPCGSetup(objects.pcg, system, b, x), "PCG set-up (BoomerAMG)");
  check(HYPRE_ParCSRPCGSolve(objects.pcg, system, b, x), "PCG solve");

  HYPRE_Int iterations = 0;
  HYPRE_PCGGetNumIterations(objects.pcg, &iterations);
  // Converged by hypre's test (on its recursive residual, as the in-house PCG's) and by the true residual,
  // |b - M x| / |b|, recomputed here over all the ranks and reported.
  HYPRE_Int converged = 0;
  HYPRE_PCGGetConverged(objects.pcg, &converged);
  const HYPRE_ParVector residual =
      parcsr_vector(objects.residual, communicator, first, last, rows_.data(), rhs.data(), "the residual");
  check(HYPRE_ParCSRMatrixMatvec(-1.0, system, x, 1.0, residual), "ParCSRMatrixMatvec");
  double residual_squared = 0.0;
  check(HYPRE_ParVectorInnerProd(residual, residual, &residual_squared), "ParVectorInnerProd");
  if (rows > 0)
    check(HYPRE_IJVectorGetValues(objects.solution, rows, rows_.data(), solution.data()), "IJVectorGetValues");
  outcome.iterations = iterations;
  outcome.relative_residual = std::sqrt(residual_squared / rhs_squared);
  // The recursive residual drifts from the true one only by rounding, unless the iteration broke down (a
  // preconditioner that is not positive definite): then hypre may report convergence the answer does not have.
  outcome.converged = converged != 0 && outcome.relative_residual <= 10.0 * tolerance;
  return outcome;
}

#else

bool hypre_available() { return false; }

PressureSolveOutcome HyprePressureSolver::solve(const PressureMatrix&, const PressureRowBlock&,
                                                const std::vector<double>&, std::vector<double>&, double,
                                                std::int64_t) {
  // The scene reader refuses [fluid] preconditioner = "boomeramg" in such a build; a caller that reaches here
  // bypassed it.
  throw std::logic_error("this riffle was built without hypre (install libhypre-dev and configure again)");
}

#endif

HyprePressureSolver::HyprePressureSolver(Ranks ranks) : ranks_(ranks) {}
HyprePressureSolver::~HyprePressureSolver() = default;

PressureSolveOutcome HyprePressureSolver::solve(const PressureMatrix& matrix, const std::vector<double>& rhs,
                                                std::vector<double>& solution, double tolerance,
                                                std::int64_t max_iterations) {
  return solve(matrix, PressureRowBlock{0, matrix.rows}, rhs, solution, tolerance, max_iterations);
}

}  // namespace riffle
