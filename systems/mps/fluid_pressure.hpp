#pragma once
// The pressure Poisson equation (seed 000 Eqs. 4-7; numerics 2.2-2.5, 3.5 and amendments 1-2), assembled over the
// fluid particles only (Neumann walls) and solved by CG warm-started from p^k, preconditioned by Jacobi or (default) Jacobi plus
// an aggregation coarse solve (systems/physics/mps/pressure_preconditioner.hpp), or handed to hypre's BoomerAMG-PCG
// (systems/physics/mps/hypre_pressure_solver.hpp).
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/mps/hypre_pressure_solver.hpp"
#include "systems/physics/mps/pressure_preconditioner.hpp"
#include "systems/physics/ranks/fluid_ranks.hpp"

namespace riffle {

/// The pressure Poisson equation in the symmetric positive definite form M p = b over the unknown (non-surface)
/// fluid particles: M_ii = sum_fluid a_ij + rho n0 alpha_c / dt^2, M_ij = -a_ij (j unknown), with
/// b = rho/dt [Dn/Dt* + ECS] + rho gamma (n* - n0)/dt^2 (gamma = rate dt; classic source: gamma = 1, no Dn/Dt).
class FluidPressureSolve final : public System {
 public:
  /// Whether the tank has a periodic axis comes from the model (periodic_box), as for the searches' halo and
  /// fluid_correct: the solve then exchanges the ghosts' pressures (FluidNeighbours), which fluid_correct reads.
  explicit FluidPressureSolve(const Model& model)
      : fluid_(model.fluid),
        constants_(mps_constants(model.fluid)),
        kernel_(constants_.effective_radius),
        periodic_(periodic_box(model).any()),
        over_ranks_(ranks::distributed()) {}
  std::string_view name() const override { return "fluid_pressure"; }
  Access access() const override {
    if (periodic_ || over_ranks_)
      return {component_ids<ParticleState, ParticlePrediction, ParticleDensity>(),
              component_ids<ParticlePressure, FluidSummary, FluidNeighbours>()};
    return {component_ids<FluidNeighbours, ParticleState, ParticlePrediction, ParticleDensity>(),
            component_ids<ParticlePressure, FluidSummary>()};
  }
  void run(SystemContext& context) override;

 private:
  /// p^{k+1} from the solution (clamped at zero unless the model keeps negative pressure), the ghosts' copies and
  /// the solver's summary.
  void finish(SystemContext& context, const PressureSolveOutcome& outcome);

  FluidModel fluid_;
  MpsConstants constants_;
  WendlandKernel kernel_;
  bool periodic_ = false;
  /// A run over MPI ranks (the water may be spread over them): each rank's rows after the lower ranks'
  /// (number_rows_over_ranks), solved over all the ranks by the in-house CG (its coarse level spanning the ranks) or,
  /// with preconditioner = "boomeramg", by hypre; the ghosts' pressures come from their owners.
  bool over_ranks_ = false;
  /// Over ranks, the in-house CG: rewrites the assembled global columns as this rank's rows (0 .. unknowns - 1) and,
  /// past them, one entry per ghost slot (unknowns + ghost index). Returns the length of a vector with the ghosts'
  /// entries.
  std::size_t localise_columns(std::size_t unknowns);
  /// Over ranks: the ghost entries of `x` (past its own rows) from their owners' rows, point to point. Collective.
  void refresh_ghost_entries(const FluidRankHalo& ranks, std::vector<double>& x);
  std::vector<double> ghost_entries_;                 ///< over ranks: scratch of refresh_ghost_entries
  RankRows rank_rows_;                    ///< over ranks: this rank's first row, the global count, the ghosts' rows
  std::vector<std::int32_t> local_rows_;  ///< over ranks: each particle's row on this rank (-1: none)
  HyprePressureSolver hypre_over_ranks_{HyprePressureSolver::Ranks::kAll};
  std::vector<std::int32_t> row_of_;      ///< fluid slot -> unknown index, -1 on the surface
  std::vector<std::uint32_t> slot_of_;    ///< unknown index -> fluid slot
  std::vector<double> diagonal_, inverse_diagonal_;
  // The off-diagonal entries M_ij in CSR, counted first (from the near lists) so the assembly writes them in place.
  std::vector<std::size_t> row_start_;          ///< unknowns + 1
  std::vector<std::uint32_t> compact_columns_;  ///< unknown indices
  std::vector<double> compact_values_;          ///< M_ij
  std::vector<Vec3> row_positions_;
  TwoLevelPreconditioner preconditioner_;
  HyprePressureSolver hypre_;  ///< used with preconditioner = "boomeramg" only (MPI starts at its first solve)
  std::vector<double> rhs_, solution_, residual_, direction_, product_;
};

}  // namespace riffle
