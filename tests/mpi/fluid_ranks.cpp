// The MPS particles over several MPI ranks (systems/physics/ranks/fluid_ranks.hpp; CTest runs it under mpiexec with
// 1, 2 and 4 ranks): a tank of still water's particles (scenes/hydrostatic.toml: water filling the tank, so that every
// cut runs through it; walls and dummies) built whole on every rank, split over the
// ranks, moved, migrated, and given ghosts, checked against the whole table every rank still holds:
//   - every particle on exactly one rank, inside its box, the fluid slots first; gathered at rank 0, every field of
//     every particle equal, bit for bit, to the whole table's (after the split, and after a migration);
//   - the ghosts complete: every owned particle (fluid, wall or dummy) sees, among its rank's reals and ghosts,
//     exactly the particles the whole table has within r_e of it (the same ids), at the moved positions;
//   - the water squeezed into the domain's lower corner: the boxes cut anew by the work they hold, the particles migrated into
//     them, every box within 1.1 of the mean work;
//   - a field exchanged to the ghosts (a value of each particle's id) equal to their owners';
//   - a system with a row per fluid particle and the pressure equation's pattern, assembled per rank with global
//     columns and solved by hypre over the ranks, as the whole table's solved alone (to 1e-9).
// A periodic tank (scenes/sheared_water_block.toml, periodic along x and y) the same way, distances then taken to the
// nearest image, the ghosts including the images across the periodic faces (a rank's own particles' too).
//   mpiexec -n N riffle_mpi_fluid_ranks [scene in scenes/, default hydrostatic.toml]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/run/simulation.hpp"
#include "engine/scene/scene.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/geometry/recursive_bisection.hpp"
#include "systems/physics/mps/hypre_pressure_solver.hpp"
#include "systems/physics/ranks/fluid_ranks.hpp"
#include "systems/physics/ranks/grain_ranks.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace {

std::string scene_text(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

/// A displacement of up to `size` in each direction, a fixed function of the id: the same on every rank.
riffle::Vec3 jiggle(riffle::EntityId id, double size) {
  const auto hash = [](std::uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return static_cast<double>(x % 2001) / 1000.0 - 1.0;
  };
  return size * riffle::Vec3(hash(3 * id + 1), hash(3 * id + 2), hash(3 * id + 3));
}

/// Every field of the gathered table equal to the whole table's (both ordered by id).
bool same_tables(const riffle::FluidParticles& a, const riffle::FluidParticles& b) {
  if (a.size() != b.size()) return false;
  bool same = true;
  std::vector<const void*> fields_a;
  riffle::FluidParticles::for_each_field(a, [&](const riffle::FieldInfo&, const auto& field) { fields_a.push_back(&field); });
  std::size_t k = 0;
  riffle::FluidParticles::for_each_field(b, [&](const riffle::FieldInfo&, const auto& field) {
    using Field = std::decay_t<decltype(field)>;
    same = same && *static_cast<const Field*>(fields_a[k++]) == field;
  });
  return same;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace riffle;
  ranks::start_mpi();
  const int rank = ranks::rank(), count = ranks::size();
  int failures = 0;
  const auto expect = [&](bool condition, const char* what, double value) {
    if (!condition) {
      std::fprintf(stderr, "rank %d of %d: FAILED %s (%g)\n", rank, count, what, value);
      ++failures;
    }
  };
  const std::string path = std::string(RIFFLE_SOURCE_DIR "/scenes/") + (argc > 1 ? argv[1] : "hydrostatic.toml");
  auto simulation = Simulation::from_model(parse_scene(scene_text(path), path));
  const Model& model = simulation->model();
  FluidParticles whole = *simulation->world().fluid;  // every rank's copy of the whole table
  const std::size_t total = whole.size();
  const double reach = model.fluid.effective_radius();
  const DomainBox domain = domain_box(model);
  const PeriodicBox box = periodic_box(model);
  // The separation from a to b, to b's nearest image along the periodic axes.
  const auto separation = [&](const Vec3& a, const Vec3& b) {
    Vec3 d = b - a;
    for (int axis = 0; axis < 3; ++axis)
      if (box.periodic[static_cast<std::size_t>(axis)]) d[axis] -= box.length[axis] * std::round(d[axis] / box.length[axis]);
    return d.norm();
  };
  std::vector<std::size_t> by_id(total);
  for (std::size_t i = 0; i < total; ++i) by_id[i] = i;
  std::sort(by_id.begin(), by_id.end(), [&](std::size_t a, std::size_t b) { return whole.id[a] < whole.id[b]; });
  permute_fields(whole, by_id);  // ordered by id, as the gathers are

  FluidParticles mine = whole;
  FluidRankHalo halo;
  split_fluid_over_ranks(mine, halo, domain.low, domain.high);
  const auto check_ownership = [&](const char* when) {
    const std::vector<double> owned = ranks::gather_all({static_cast<double>(mine.size())});
    double sum = 0.0;
    for (const double n : owned) sum += n;
    expect(sum == static_cast<double>(total), "every particle on one rank", sum);
    std::vector<PartBox> boxes;
    for (std::size_t r = 0; r < halo.box_low.size(); ++r) boxes.push_back({halo.box_low[r], halo.box_high[r]});
    std::size_t outside = 0;
    for (const Vec3& position : mine.position) outside += part_of(boxes, position) != static_cast<std::size_t>(rank);
    expect(outside == 0, "every particle inside its rank's box", static_cast<double>(outside));
    const auto fluid = static_cast<std::int32_t>(FluidKind::kFluid);
    expect(std::is_partitioned(mine.kind.begin(), mine.kind.end(), [&](std::int32_t k) { return k == fluid; }),
           "the fluid slots first", 0.0);
    const FluidParticles gathered = gather_fluid_at_root(mine);
    if (rank == 0) {
      std::printf("%s: %zu particles over %d rank(s):", when, total, count);
      for (const double n : owned) std::printf(" %g", n);
      std::printf("\n");
      expect(same_tables(gathered, whole), "gathered at rank 0: every field of every particle as the whole table's", 0.0);
    }
  };
  check_ownership("split");

  // Every particle moved by up to 2 l0 (its id decides how), on every rank's whole table and on the owned ones alike:
  // some leave their box, and the ghosts must follow the new positions.
  const double spacing = model.fluid.spacing;
  for (std::size_t i = 0; i < whole.size(); ++i) whole.position[i] = box.wrap(whole.position[i] + jiggle(whole.id[i], 2.0 * spacing));
  for (std::size_t i = 0; i < mine.size(); ++i) mine.position[i] = box.wrap(mine.position[i] + jiggle(mine.id[i], 2.0 * spacing));
  const std::size_t left = migrate_fluid_particles(mine, halo);
  const std::vector<double> moved = ranks::sum_in_rank_order({static_cast<double>(left)});
  if (rank == 0) std::printf("particles handed between ranks: %g\n", moved[0]);
  if (count > 1) expect(moved[0] > 0.0, "particles migrated between ranks", moved[0]);
  check_ownership("migrated");

  // Ghosts within r_e + a skin of 0.2 l0 of each box; every owned fluid particle's neighbours within r_e, among the
  // reals and ghosts, against the whole table's.
  FluidGhosts ghosts;
  build_fluid_rank_ghosts(mine, mine.position, reach + 0.2 * spacing, box, halo, ghosts);
  std::vector<Vec3> all_position = mine.position;
  all_position.insert(all_position.end(), ghosts.position.begin(), ghosts.position.end());
  std::vector<EntityId> all_id = mine.id;
  all_id.insert(all_id.end(), halo.ghost_id.begin(), halo.ghost_id.end());
  std::size_t checked = 0, wrong = 0, pairs = 0;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    std::vector<EntityId> seen, expected;
    for (std::size_t j = 0; j < all_position.size(); ++j)
      if (j != i && (all_position[j] - mine.position[i]).norm() < reach) seen.push_back(all_id[j]);
    for (std::size_t j = 0; j < whole.size(); ++j)  // ordered by id
      if (whole.id[j] != mine.id[i] && separation(mine.position[i], whole.position[j]) < reach)
        expected.push_back(whole.id[j]);
    std::sort(seen.begin(), seen.end());
    wrong += seen != expected;
    pairs += seen.size();
    ++checked;
  }
  expect(wrong == 0, "every owned particle's neighbours within r_e among reals and ghosts as in the whole table",
         static_cast<double>(wrong));
  const std::vector<double> counts = ranks::sum_in_rank_order(
      {static_cast<double>(checked), static_cast<double>(pairs), static_cast<double>(halo.ghost_count())});
  if (rank == 0)
    std::printf("neighbours within r_e checked for %g particles (%g pairs); ghosts on all ranks: %g\n", counts[0],
                counts[1], counts[2]);

  // A field sent to the ghosts: each particle's value a function of its id.
  std::vector<double> value(mine.size());
  for (std::size_t i = 0; i < mine.size(); ++i) value[i] = 0.5 * static_cast<double>(mine.id[i]) + 1.0;
  std::vector<double> ghost_value;
  exchange_fluid_ghost_field(value, halo, ghost_value);
  std::vector<Vec3> ghost_velocity;
  exchange_fluid_ghost_field(mine.velocity, halo, ghost_velocity);
  std::vector<Vec3> ghost_position;
  exchange_fluid_ghost_positions(mine.position, halo, ghost_position);
  std::size_t mismatched = 0;
  for (std::size_t g = 0; g < halo.ghost_count(); ++g) {
    mismatched += ghost_position[g] != ghosts.position[g];
    mismatched += ghost_value[g] != 0.5 * static_cast<double>(halo.ghost_id[g]) + 1.0;
    mismatched += ghost_velocity[g] != ghosts.velocity[g];
  }
  expect(mismatched == 0, "the exchanged ghost fields equal their owners'", static_cast<double>(mismatched));

  // A symmetric positive definite system with a row per fluid particle coupling its fluid neighbours within r_e (the
  // pressure equation's pattern: a graph Laplacian weighted by (1 - r/r_e)^2, plus one on the diagonal), assembled per
  // rank with global columns (number_rows_over_ranks: a ghost's column is its owner's row) and solved by hypre over all
  // the ranks, against the same system of the whole table solved on rank 0 alone.
  const auto fluid = static_cast<std::int32_t>(FluidKind::kFluid);
  const auto weight = [&](double distance) { return (1.0 - distance / reach) * (1.0 - distance / reach); };
  const auto source = [](EntityId id) { return 1.0 + 0.01 * static_cast<double>(id % 97); };
  std::vector<std::int32_t> local_row(mine.size(), -1);
  std::int32_t own_rows = 0;
  for (std::size_t i = 0; i < mine.size(); ++i)
    if (mine.kind[i] == fluid) local_row[i] = own_rows++;
  const RankRows rows = number_rows_over_ranks(local_row, halo);
  // Assembles the rows of the fluid particles among `position` [0, reals) against all of `position`, whose columns
  // `column_of(j)` gives (-1: not an unknown).
  struct System {
    std::vector<double> diagonal, values, rhs;
    std::vector<std::size_t> row_start{0};
    std::vector<std::uint32_t> columns;
    std::vector<EntityId> row_id;
  };
  // `nearest_image`: distances to the nearest periodic image (the whole table) or as placed (reals and ghosts).
  const auto assemble = [&](const std::vector<Vec3>& position, std::size_t reals, const std::vector<EntityId>& id,
                            const std::vector<std::int32_t>& kind, bool nearest_image, const auto& column_of) {
    System system;
    for (std::size_t i = 0; i < reals; ++i) {
      if (kind[i] != fluid) continue;
      double diagonal = 1.0;
      for (std::size_t j = 0; j < position.size(); ++j) {
        const double distance =
            nearest_image ? separation(position[i], position[j]) : (position[j] - position[i]).norm();
        if (j == i || distance >= reach || kind[j] != fluid) continue;
        const std::int64_t column = column_of(j);
        expect(column >= 0, "a fluid neighbour has a row", static_cast<double>(j));
        diagonal += weight(distance);
        system.columns.push_back(static_cast<std::uint32_t>(column));
        system.values.push_back(-weight(distance));
      }
      system.diagonal.push_back(diagonal);
      system.rhs.push_back(source(id[i]));
      system.row_id.push_back(id[i]);
      system.row_start.push_back(system.columns.size());
    }
    return system;
  };
  std::vector<std::int32_t> all_kind = mine.kind;
  all_kind.insert(all_kind.end(), ghosts.kind.begin(), ghosts.kind.end());
  const System split_system = assemble(all_position, mine.size(), all_id, all_kind, false, [&](std::size_t j) {
    return j < mine.size() ? (local_row[j] >= 0 ? static_cast<std::int64_t>(rows.first_row) + local_row[j] : -1)
                           : rows.ghost_row[j - mine.size()];
  });
  HyprePressureSolver over_ranks(HyprePressureSolver::Ranks::kAll);
  std::vector<double> solution(split_system.rhs.size(), 0.0);
  const PressureMatrix split_matrix{split_system.rhs.size(), split_system.diagonal.data(), split_system.row_start.data(),
                                    split_system.columns.data(), split_system.values.data()};
  const PressureSolveOutcome outcome = over_ranks.solve(split_matrix, PressureRowBlock{rows.first_row, rows.global_rows},
                                                        split_system.rhs, solution, 1e-12, 500);
  expect(outcome.converged, "the system over the ranks solved to 1e-12", outcome.relative_residual);
  std::vector<double> id_and_value;
  for (std::size_t k = 0; k < solution.size(); ++k)
    id_and_value.insert(id_and_value.end(), {static_cast<double>(split_system.row_id[k]), solution[k]});
  const std::vector<double> gathered_solution = ranks::gather_all(id_and_value);
  if (rank == 0) {
    // The whole table's system, its rows in slot order (the table is ordered by id).
    std::vector<std::int32_t> whole_row(whole.size(), -1);
    std::int32_t next = 0;
    for (std::size_t i = 0; i < whole.size(); ++i)
      if (whole.kind[i] == fluid) whole_row[i] = next++;
    const System whole_system =
        assemble(whole.position, whole.size(), whole.id, whole.kind, true, [&](std::size_t j) { return whole_row[j]; });
    HyprePressureSolver alone(HyprePressureSolver::Ranks::kThisOne);
    std::vector<double> reference(whole_system.rhs.size(), 0.0);
    const PressureMatrix whole_matrix{whole_system.rhs.size(), whole_system.diagonal.data(),
                                      whole_system.row_start.data(), whole_system.columns.data(),
                                      whole_system.values.data()};
    alone.solve(whole_matrix, whole_system.rhs, reference, 1e-12, 500);
    std::vector<std::pair<EntityId, double>> by_rank_id;
    for (std::size_t k = 0; k + 1 < gathered_solution.size(); k += 2)
      by_rank_id.emplace_back(static_cast<EntityId>(gathered_solution[k]), gathered_solution[k + 1]);
    std::sort(by_rank_id.begin(), by_rank_id.end());
    expect(by_rank_id.size() == reference.size(), "one unknown per fluid particle over the ranks",
           static_cast<double>(by_rank_id.size()));
    double largest = 0.0, difference = 0.0;
    for (std::size_t k = 0; k < std::min(by_rank_id.size(), reference.size()); ++k) {
      expect(by_rank_id[k].first == whole_system.row_id[k], "the same unknowns", static_cast<double>(k));
      largest = std::max(largest, std::abs(reference[k]));
      difference = std::max(difference, std::abs(by_rank_id[k].second - reference[k]));
    }
    std::printf("the system over %zu unknowns solved over the ranks in %lld iterations: largest difference from the "
                "whole table's solve %.3g of the largest value\n",
                rows.global_rows, static_cast<long long>(outcome.iterations), difference / largest);
    // Both solves stop at |r| <= 1e-12 |b|, the system's condition number is a few tens: 1e-9 is far above either's error.
    expect(difference <= 1e-9 * largest, "the solution over the ranks as the whole table's to 1e-9", difference / largest);
  }

  // The water pushed into the lower corner of the domain (every axis halved toward its low end): the boxes' work
  // grows unequal whichever way they were cut, they are cut anew (rebalance_fluid_ranks) and the particles migrate
  // into them; then every particle is on one rank again, in its box, and no box holds more than 1.1 times the mean.
  {
    const auto squeeze = [&](const Vec3& position) -> Vec3 { return domain.low + 0.5 * (position - domain.low); };
    for (Vec3& position : whole.position) position = squeeze(position);
    for (Vec3& position : mine.position) position = squeeze(position);
    const double work_reach = reach + 0.2 * spacing;
    const bool cut = rebalance_fluid_ranks(mine, halo, work_reach, kRebalanceAbove);
    if (count > 1) expect(cut, "the boxes cut anew once the water is squeezed into a corner", 0.0);
    migrate_fluid_particles(mine, halo);
    check_ownership("rebalanced");
    const std::vector<double> work = fluid_work_per_box(mine, halo, work_reach);
    double total = 0.0, largest = 0.0;
    for (const double w : work) {
      total += w;
      largest = std::max(largest, w);
    }
    const double imbalance = largest / (total / static_cast<double>(work.size()));
    if (rank == 0) std::printf("after the rebalance: the largest box's work over the mean %.4f\n", imbalance);
    // The bisection cuts at weighted medians: off by at most a few particles' weight a cut.
    expect(imbalance <= kRebalanceAbove, "the boxes' work within 1.1 of the mean after the rebalance", imbalance);
  }

  const bool failed = ranks::any(failures > 0);
  if (rank == 0) std::printf("%s\n", failed ? "FAILED" : "passed");
  return failed ? 1 : 0;
}
