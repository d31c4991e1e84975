// hypre's BoomerAMG-PCG on the pressure equation's form (PressureMatrix): the answer of a direct solve to the
// tolerance's order, the in-house criterion |b - M x| <= tol |b|, and the warm start. A build without hypre
// refuses the solve (the scene reader refuses the key before: tests/unit/engine/scene/fluid_scene_test.cpp). Over
// several MPI ranks: tests/mpi/hypre_ranks.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "systems/physics/mps/hypre_pressure_solver.hpp"
#include "tests/support/pressure_lattice.hpp"

using namespace riffle;

using test::norm;
using test::TankLattice;


TEST_CASE("BoomerAMG-PCG solves the pressure equation to the in-house criterion, and its answer is the direct one") {
  if (!hypre_available()) {
    HyprePressureSolver solver;
    const TankLattice lattice(4);
    std::vector<double> x(lattice.diagonal.size(), 0.0);
    CHECK_THROWS_AS(solver.solve(lattice.matrix(), TankLattice::varied_rhs(x.size()), x, 1e-8, 100), std::logic_error);
    return;
  }
  const TankLattice lattice(16);
  const std::vector<double> rhs = TankLattice::varied_rhs(lattice.diagonal.size());
  const std::vector<double> exact = lattice.direct_solve(rhs);
  HyprePressureSolver solver;
  for (const double tolerance : {1e-6, 1e-10}) {
    std::vector<double> x(rhs.size(), 0.0);
    const PressureSolveOutcome outcome = solver.solve(lattice.matrix(), rhs, x, tolerance, 200);
    CHECK(outcome.converged);
    // The true residual meets the criterion (the recursive one stopped it; rounding apart, they agree).
    std::vector<double> residual = lattice.product(x);
    for (std::size_t k = 0; k < residual.size(); ++k) residual[k] = rhs[k] - residual[k];
    CHECK(norm(residual) / norm(rhs) == doctest::Approx(outcome.relative_residual).epsilon(1e-6));
    CHECK(outcome.relative_residual <= 1.01 * tolerance);
    // The error is bounded by the condition number times the residual; with a multigrid the iterations stay few
    // (a 16^3 Poisson problem: Jacobi-CG needs about 50 for 1e-6).
    std::vector<double> error(x.size());
    for (std::size_t k = 0; k < x.size(); ++k) error[k] = x[k] - exact[k];
    CHECK(norm(error) / norm(exact) < 1e3 * tolerance);
    CHECK(outcome.iterations > 0);
    CHECK(outcome.iterations < 30);
  }
}

TEST_CASE("BoomerAMG-PCG starts from the given guess: the exact answer takes at most one iteration, b = 0 gives x = 0") {
  if (!hypre_available()) return;
  const TankLattice lattice(8);
  const std::vector<double> rhs = TankLattice::varied_rhs(lattice.diagonal.size());
  std::vector<double> x = lattice.direct_solve(rhs);
  HyprePressureSolver solver;
  const PressureSolveOutcome warm = solver.solve(lattice.matrix(), rhs, x, 1e-8, 100);
  CHECK(warm.converged);
  CHECK(warm.iterations <= 1);  // hypre's PCG tests convergence after its first step
  std::vector<double> cold(rhs.size(), 0.0);
  CHECK(solver.solve(lattice.matrix(), rhs, cold, 1e-8, 100).iterations > 3);
  std::vector<double> zero_rhs(rhs.size(), 0.0), y(rhs.size(), 5.0);
  const PressureSolveOutcome zero = solver.solve(lattice.matrix(), zero_rhs, y, 1e-8, 100);
  CHECK(zero.converged);
  CHECK(norm(y) == 0.0);
}

TEST_CASE("BoomerAMG-PCG reports a solve that stops at its iteration limit as not converged") {
  if (!hypre_available()) return;
  const TankLattice lattice(12);
  const std::vector<double> rhs = TankLattice::varied_rhs(lattice.diagonal.size());
  std::vector<double> x(rhs.size(), 0.0);
  HyprePressureSolver solver;
  const PressureSolveOutcome outcome = solver.solve(lattice.matrix(), rhs, x, 1e-14, 2);
  CHECK_FALSE(outcome.converged);
  CHECK(outcome.iterations == 2);
  CHECK(outcome.relative_residual > 1e-14);
}
