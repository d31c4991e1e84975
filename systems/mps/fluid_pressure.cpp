#include "systems/mps/fluid_pressure.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "systems/physics/mps/mps_operators.hpp"

namespace riffle {

void FluidPressureSolve::run(SystemContext& context) {
  const ParticleState& particles = context.read<ParticleState>();
  const ParticlePrediction& prediction = context.read<ParticlePrediction>();
  const ParticleDensity& densities = context.read<ParticleDensity>();
  ParticlePressure& pressures = context.write<ParticlePressure>();
  const FluidNeighbours& neighbours = context.read<FluidNeighbours>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const FluidSchemes& schemes = fluid_.schemes;
  const WendlandKernel kernel = kernel_;
  const double n0 = constants_.reference_density;
  const double dt = context.dt;
  const double rho = fluid_.density;

  // Slots beyond the reals are a periodic tank's ghosts (fluid_neighbours_predicted exchanged r*, u*, kinds). The
  // unknown behind a ghost is its owner's pressure: its column is the owner's row, so M stays N x N and symmetric
  // (the pair (i, ghost of j) has the weight of (j, ghost of i), one period apart: equal to rounding of the shift).
  const Ghosted<Vec3> predicted_of =
      fluid_ghosted(prediction.predicted_position, neighbours.ghosts.predicted_position, neighbours);
  const Ghosted<Vec3> velocity_of = fluid_ghosted(particles.velocity, neighbours.ghosts.velocity, neighbours);
  const Ghosted<std::int32_t> kind_of = fluid_ghosted(particles.kind, neighbours.ghosts.kind, neighbours);
  // Over MPI ranks (the water spread over them) the columns are global rows: this rank's after the lower ranks', a
  // ghost's its owner's.
  const bool spread = neighbours.ranks.active;
  const std::uint32_t reals = static_cast<std::uint32_t>(particles.id.size());
  const auto row_of = [&](std::uint32_t j) -> std::int64_t {
    if (!spread) return row_of_[fluid_owner_of(neighbours, j)];
    if (j >= reals) return rank_rows_.ghost_row[j - reals];
    return row_of_[j] >= 0 ? static_cast<std::int64_t>(rank_rows_.first_row) + row_of_[j] : -1;
  };

  // Unknowns: fluid particles off the free surface, in slot order (so the system is the same for any thread count).
  row_of_.assign(fluid_count, -1);
  slot_of_.clear();
  for (std::size_t i = 0; i < fluid_count; ++i) {
    if (densities.free_surface[i]) continue;
    row_of_[i] = static_cast<std::int32_t>(slot_of_.size());
    slot_of_.push_back(static_cast<std::uint32_t>(i));
  }
  const std::size_t unknowns = slot_of_.size();
  if (spread) {
    local_rows_.assign(reals, -1);
    std::copy(row_of_.begin(), row_of_.end(), local_rows_.begin());
    rank_rows_ = number_rows_over_ranks(local_rows_, neighbours.ranks);
  }
  // Off-diagonal entries per row: the near neighbours (within r_e at r*) that are unknowns. Counting them first lets
  // the assembly write the compact rows in place.
  row_start_.resize(unknowns + 1);
  row_start_[0] = 0;
  for_each_particle(unknowns, [&](std::size_t row) {
    std::size_t entries = 0;
    for (const std::uint32_t j : near_neighbours_of(neighbours, slot_of_[row]))
      entries += kind_of[j] == kFluidKind && row_of(j) >= 0 ? 1 : 0;
    row_start_[row + 1] = entries;
  });
  for (std::size_t row = 0; row < unknowns; ++row) row_start_[row + 1] += row_start_[row];
  compact_columns_.resize(row_start_[unknowns]);
  compact_values_.resize(row_start_[unknowns]);
  for (auto* vector : {&diagonal_, &inverse_diagonal_, &rhs_, &solution_, &residual_, &direction_, &product_})
    vector->resize(unknowns);

  // Density term gamma (n* - n0)/(n0 dt^2) with gamma = rate dt (amendment 2); the classic source is gamma = 1.
  const double gamma = schemes.higher_order_source ? fluid_.density_relaxation_rate * dt : 1.0;
  const double compressibility_diagonal = rho * n0 * fluid_.compressibility / (dt * dt);
  // Quasi-compressible rows: n0 (p - p^k) / (c^2 dt^2) from (1/(rho c^2)) Dp/Dt = -div u^{k+1}. It leaves a
  // steady pressure field alone (p = p^k) and bounds how fast one step can build pressure where the incompressible
  // row is weak (a particle touching a wall with few fluid neighbours).
  const double acoustic_diagonal =
      fluid_.sound_speed > 0.0 ? n0 / (fluid_.sound_speed * fluid_.sound_speed * dt * dt) : 0.0;
  const double classic_coefficient = 6.0 / constants_.laplacian_lambda;  // a_ij = 2D w_ij / lambda0
  for_each_particle(unknowns, [&](std::size_t row) {
    const std::size_t i = slot_of_[row];
    const Vec3 position = prediction.predicted_position[i];
    const Vec3 velocity = particles.velocity[i];
    const std::size_t first_entry = row_start_[row];
    std::size_t entries = 0;
    std::uint32_t fluid_neighbours = 0;
    double diagonal = compressibility_diagonal + acoustic_diagonal, rate = 0.0;
    for (const std::uint32_t j : near_neighbours_of(neighbours, i)) {  // all within r_e at r* (fluid_free_surface)
      const Vec3 offset = predicted_of[j] - position;
      const double distance = std::sqrt(offset.squaredNorm());
      const double derivative_over_distance = kernel.derivative_over_distance(distance);
      const bool fluid = kind_of[j] == kFluidKind;
      if (fluid) {
        // Walls are left out of the Laplacian: zero normal pressure flux (Neumann, amendment 1).
        const double coefficient = schemes.higher_order_laplacian ? laplacian_coefficient(derivative_over_distance)
                                                                  : classic_coefficient * kernel.weight(distance);
        diagonal += coefficient;
        ++fluid_neighbours;
        if (row_of(j) >= 0) {  // surface neighbours hold p = 0: their term drops, the diagonal keeps it
          compact_columns_[first_entry + entries] = static_cast<std::uint32_t>(row_of(j));
          compact_values_[first_entry + entries] = -coefficient;
          ++entries;
        }
      }
      if (schemes.higher_order_source)
        rate += density_rate_term(fluid, derivative_over_distance, offset, velocity_of[j] - velocity);
    }
    double rhs = rho * gamma * (densities.number_density[i] - n0) / (dt * dt);
    if (schemes.higher_order_source) rhs += rho / dt * rate;
    if (schemes.error_compensating_source) rhs += rho / dt * prediction.density_rate[i];
    if (acoustic_diagonal > 0.0) rhs += acoustic_diagonal * pressures.pressure[i];
    if (fluid_neighbours == 0) {  // only walls around: nothing to couple to, hold it at zero
      diagonal = 1.0;
      rhs = 0.0;
    }
    diagonal_[row] = diagonal;
    inverse_diagonal_[row] = 1.0 / diagonal;
    rhs_[row] = rhs;
    // Warm start: p^k extrapolated linearly in time (p^{k-1} is kept per particle), clamped at zero like p.
    solution_[row] = std::max(0.0, 2.0 * pressures.pressure[i] - pressures.previous_pressure[i]);
  });

  const PressureMatrix matrix{unknowns, diagonal_.data(), row_start_.data(), compact_columns_.data(),
                              compact_values_.data()};
  // Over ranks with preconditioner = "boomeramg": hypre over all the ranks. Otherwise the in-house CG below, its
  // products reading the ghosts' entries from their owners, its sums added over the ranks in rank order, its
  // two-level preconditioner's coarse level spanning all the ranks (each rank's rows aggregated, the coarse matrix
  // gathered and factorised on every rank), so that it is one rank's preconditioner over the whole domain.
  const bool ranks_cg = spread && fluid_.preconditioner != FluidModel::Preconditioner::kBoomerAmg;
  if (spread && !ranks_cg) {
    const PressureSolveOutcome outcome =
        hypre_over_ranks_.solve(matrix, PressureRowBlock{rank_rows_.first_row, rank_rows_.global_rows}, rhs_, solution_,
                                fluid_.solver_tolerance, fluid_.solver_max_iterations);
    finish(context, outcome);
    return;
  }
  if (fluid_.preconditioner == FluidModel::Preconditioner::kBoomerAmg) {
    const PressureSolveOutcome outcome =
        hypre_.solve(matrix, rhs_, solution_, fluid_.solver_tolerance, fluid_.solver_max_iterations);
    finish(context, outcome);
    return;
  }
  if (ranks_cg) {
    const std::size_t extended = localise_columns(unknowns);
    solution_.resize(extended);
    direction_.resize(extended);
  }
  const bool two_level = fluid_.preconditioner == FluidModel::Preconditioner::kTwoLevel;
  if (two_level) {
    row_positions_.resize(unknowns);
    for_each_particle(unknowns, [&](std::size_t row) { row_positions_[row] = prediction.predicted_position[slot_of_[row]]; });
    // Coarse cells of at least 4 l0, wider for big problems so the coarse factorisation stays small (over ranks the
    // whole problem's size, so that any rank count coarsens alike).
    const double rows = static_cast<double>(ranks_cg ? rank_rows_.global_rows : unknowns);
    const double cells_per_edge = std::max(4.0, std::ceil(std::cbrt(rows / 500.0)));
    const double cell_size = cells_per_edge * constants_.spacing;
    if (ranks_cg) {
      const TwoLevelPreconditioner::RankLinks links{
          [](const std::vector<double>& values, const std::vector<std::size_t>& counts) {
            return ranks::gather_all(values, counts);
          },
          [&](std::vector<double>& x) { refresh_ghost_entries(neighbours.ranks, x); },
          static_cast<std::size_t>(ranks::rank())};
      preconditioner_.setup_over_ranks(matrix, rank_rows_.ghost_row.size(), row_positions_, context.model.tank.origin,
                                       cell_size, links);
    } else {
      preconditioner_.setup(matrix, row_positions_, context.model.tank.origin, cell_size);
    }
  }
  // Over ranks: a sum over this rank's rows becomes the sum over all the ranks' (in rank order); one rank keeps it.
  const auto over_all = [&](auto sums) {
    if (!ranks_cg) return sums;
    const std::vector<double> all = ranks::sum_in_rank_order(std::vector<double>(sums.begin(), sums.end()));
    std::copy(all.begin(), all.end(), sums.begin());
    return sums;
  };
  // z = M^-1 r = D^-1 r + P c with c = A_c^-1 P^T r is never stored: r . z = sum r^2 / diag + (P^T r) . c, the
  // first sum taken in the pass that updates r, and z is formed where the direction update needs it.
  const auto coarse_dot = [&]() { return two_level ? preconditioner_.solve_coarse(residual_) : 0.0; };
  const auto preconditioned = [&](std::size_t k) {
    return residual_[k] * inverse_diagonal_[k] + (two_level ? preconditioner_.coarse_correction(k) : 0.0);
  };
  // (M x)[row] with four partial sums: one chain of dependent additions would hold the product to the add latency.
  const auto row_product = [&](std::size_t row, const std::vector<double>& x) {
    double sum0 = diagonal_[row] * x[row], sum1 = 0.0, sum2 = 0.0, sum3 = 0.0;
    std::size_t k = row_start_[row];
    const std::size_t end = row_start_[row + 1];
    for (; k + 4 <= end; k += 4) {
      sum0 += compact_values_[k] * x[compact_columns_[k]];
      sum1 += compact_values_[k + 1] * x[compact_columns_[k + 1]];
      sum2 += compact_values_[k + 2] * x[compact_columns_[k + 2]];
      sum3 += compact_values_[k + 3] * x[compact_columns_[k + 3]];
    }
    for (; k < end; ++k) sum0 += compact_values_[k] * x[compact_columns_[k]];
    return (sum0 + sum1) + (sum2 + sum3);
  };
  // y = M x, returning x . y (CG needs the curvature d . M d right after the product).
  const auto multiply_and_dot = [&](std::vector<double>& x, std::vector<double>& y) {
    if (ranks_cg) refresh_ghost_entries(neighbours.ranks, x);
    return over_all(std::array<double, 1>{deterministic_sum(unknowns, [&](std::size_t row) {
      const double sum = row_product(row, x);
      y[row] = sum;
      return x[row] * sum;
    })})[0];
  };

  // Preconditioned conjugate gradients (numerics 3.5), |r| <= tol |b|, with the vector updates fused into the
  // passes that need them (three passes over the unknowns per iteration, plus the restriction to the coarse level).
  const double rhs_norm = std::sqrt(
      over_all(std::array<double, 1>{deterministic_sum(unknowns, [&](std::size_t k) { return rhs_[k] * rhs_[k]; })})[0]);
  const double target = fluid_.solver_tolerance * rhs_norm;
  std::int64_t iterations = 0;
  double residual_norm = 0.0;
  if (rhs_norm == 0.0) {
    std::fill(solution_.begin(), solution_.end(), 0.0);
  } else {
    // Each pass returns |r|^2 and r . D^-1 r; over ranks also each rank's coarse part, added over the ranks with
    // them (one reduction an iteration besides the curvature's, and the coarse level's gather of the restriction).
    if (ranks_cg) refresh_ghost_entries(neighbours.ranks, solution_);
    auto initial = deterministic_sums<2>(unknowns, [&](std::size_t row) {
      const double residual = rhs_[row] - row_product(row, solution_);
      residual_[row] = residual;
      return std::array<double, 2>{residual * residual, residual * residual * inverse_diagonal_[row]};
    });
    if (ranks_cg) {
      const std::array<double, 3> all = over_all(std::array<double, 3>{initial[0], initial[1], coarse_dot()});
      initial = {all[0], all[1] + all[2]};
    }
    residual_norm = std::sqrt(initial[0]);
    double residual_dot = 0.0;
    if (residual_norm > target) {
      residual_dot = ranks_cg ? initial[1] : initial[1] + coarse_dot();
      for_each_particle(unknowns, [&](std::size_t k) { direction_[k] = preconditioned(k); });
    }
    while (residual_norm > target && iterations < fluid_.solver_max_iterations && std::isfinite(residual_norm)) {
      const double curvature = multiply_and_dot(direction_, product_);
      const double step = residual_dot / curvature;
      auto updated = deterministic_sums<2>(unknowns, [&](std::size_t k) {
        solution_[k] += step * direction_[k];
        const double residual = residual_[k] - step * product_[k];
        residual_[k] = residual;
        return std::array<double, 2>{residual * residual, residual * residual * inverse_diagonal_[k]};
      });
      if (ranks_cg) {
        const std::array<double, 3> all = over_all(std::array<double, 3>{updated[0], updated[1], coarse_dot()});
        updated = {all[0], all[1] + all[2]};
      }
      residual_norm = std::sqrt(updated[0]);
      ++iterations;
      if (residual_norm <= target) break;
      const double next_dot = ranks_cg ? updated[1] : updated[1] + coarse_dot();
      const double beta = next_dot / residual_dot;
      residual_dot = next_dot;
      for_each_particle(unknowns, [&](std::size_t k) { direction_[k] = preconditioned(k) + beta * direction_[k]; });
    }
  }

  PressureSolveOutcome outcome;
  outcome.iterations = iterations;
  outcome.relative_residual = rhs_norm > 0.0 ? residual_norm / rhs_norm : 0.0;
  outcome.converged = std::isfinite(residual_norm) && residual_norm <= target;
  finish(context, outcome);
}

std::size_t FluidPressureSolve::localise_columns(std::size_t unknowns) {
  // Each ghost slot's entry: the first ghost slot of each global row (a rank's particle may reach this rank as two
  // periodic images, one row).
  std::unordered_map<std::int64_t, std::uint32_t> entry_of_row;
  entry_of_row.reserve(rank_rows_.ghost_row.size());
  for (std::size_t g = 0; g < rank_rows_.ghost_row.size(); ++g)
    if (rank_rows_.ghost_row[g] >= 0)
      entry_of_row.emplace(rank_rows_.ghost_row[g], static_cast<std::uint32_t>(unknowns + g));
  const auto first = static_cast<std::int64_t>(rank_rows_.first_row);
  const auto own = static_cast<std::int64_t>(unknowns);
  for (std::size_t row = 0; row < unknowns; ++row) {
    for (std::size_t k = row_start_[row]; k < row_start_[row + 1]; ++k) {
      const std::int64_t global = compact_columns_[k];
      compact_columns_[k] = global >= first && global < first + own ? static_cast<std::uint32_t>(global - first)
                                                                     : entry_of_row.at(global);
    }
  }
  return unknowns + rank_rows_.ghost_row.size();
}

void FluidPressureSolve::refresh_ghost_entries(const FluidRankHalo& ranks, std::vector<double>& x) {
  const std::size_t unknowns = slot_of_.size();
  send_to_fluid_ghosts<double>(
      ranks,
      [&](std::size_t r, std::size_t n) {
        const std::uint32_t slot = ranks.send_slots[r][n];
        const std::int32_t row = slot < row_of_.size() ? row_of_[slot] : -1;
        return row >= 0 ? x[static_cast<std::size_t>(row)] : 0.0;
      },
      ghost_entries_);
  std::copy(ghost_entries_.begin(), ghost_entries_.end(), x.begin() + static_cast<std::ptrdiff_t>(unknowns));
}

void FluidPressureSolve::finish(SystemContext& context, const PressureSolveOutcome& outcome) {
  const ParticleState& particles = context.read<ParticleState>();
  const ParticleDensity& densities = context.read<ParticleDensity>();
  ParticlePressure& pressures = context.write<ParticlePressure>();
  FluidSummary& summary = context.write<FluidSummary>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  std::size_t surface = 0;
  for (std::size_t i = 0; i < fluid_count; ++i) surface += densities.free_surface[i] ? 1 : 0;
  const bool spread = over_ranks_ && context.read<FluidNeighbours>().ranks.active;
  const std::size_t surface_total =
      spread ? static_cast<std::size_t>(ranks::sum_in_rank_order({static_cast<double>(surface)})[0]) : surface;
  // The clamp is a free surface's (no tension where the water meets air, numerics 2.8). Water without a free-surface
  // particle (a sealed box full of it) has no p = 0 anywhere: its pressure's level is set only by the compressibility
  // term, so a clamp at zero cuts an arbitrary level, and measured it drives still water off the lattice (a packed
  // sealed box at water's viscosity: KE from 3e-8 J up to 6e-6 J in 3 s clamped, down to 5e-10 J not; docs/FLUID.md).
  const bool clamp = fluid_.clamp_negative_pressure && surface_total > 0;
  for_each_particle(fluid_count, [&](std::size_t i) {
    pressures.previous_pressure[i] = pressures.pressure[i];
    const double pressure = row_of_[i] >= 0 ? solution_[static_cast<std::size_t>(row_of_[i])] : 0.0;
    pressures.pressure[i] = clamp && pressure < 0.0 ? 0.0 : pressure;
  });
  // The exchange of p^{k+1}: fluid_correct reads the ghosts' pressures.
  if (spread) {
    FluidNeighbours& halo_owner = context.write<FluidNeighbours>();
    exchange_fluid_ghost_field(pressures.pressure, halo_owner.ranks, halo_owner.ghosts.pressure);
    summary.solver_iterations = outcome.iterations;
    summary.solver_residual = outcome.relative_residual;
    summary.solver_unknowns = rank_rows_.global_rows;
    summary.solver_converged = outcome.converged;
    summary.surface_count = surface_total;
    context.count_items(slot_of_.size());
    return;
  }
  if (periodic_) {
    FluidNeighbours& halo_owner = context.write<FluidNeighbours>();
    halo_copy(halo_owner.halo, pressures.pressure, halo_owner.ghosts.pressure);
  }
  summary.solver_iterations = outcome.iterations;
  summary.solver_residual = outcome.relative_residual;
  summary.solver_unknowns = slot_of_.size();
  summary.solver_converged = outcome.converged;
  summary.surface_count = surface;
  context.count_items(slot_of_.size());
}

}  // namespace riffle
