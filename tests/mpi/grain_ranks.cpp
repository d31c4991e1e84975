// The grains over several MPI ranks (CTest runs it under mpiexec with 1, 2 and 4 ranks): a small dry bed dropped
// into a tank shaken sideways (tests/data/shaken_bed.toml), split over the ranks by systems/physics/ranks/grain_ranks.hpp, stepped, and gathered at
// rank 0 after every step, where the same scene runs whole on that rank alone (no rank exchange) beside it. The two
// evaluate the same contacts with the same laws; only the order in which a grain's contact forces are added differs
// (the ranks' slot orders, and the forces that come back from other ranks added last), so they agree to rounding at
// first and then drift apart as a granular flow amplifies any difference. Checks: every grain on exactly one rank,
// the same ids; the largest position difference below 1e-12 m over the first steps; the bed's total momentum and
// its kinetic energy after the whole run (grains fallen, collided and shaken) within 1e-6 relative of the one-rank
// run's. Rank 0 prints the largest position difference per step: how rounding differences grow in the flow.
//
//   mpiexec -n N riffle_mpi_grain_ranks [steps [scene [--expect-rebalance]]]
//     (default 120 steps of 1 ms of tests/data/shaken_bed.toml; a scene is named within tests/data/)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/run/simulation.hpp"
#include "engine/scene/scene.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/ranks/grain_ranks.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace {

/// A scene of tests/data/ (its outputs unused: this test steps it itself).
std::string scene_text(const std::string& name) {
  std::ifstream file(std::string(RIFFLE_SOURCE_DIR "/tests/data/") + name);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace riffle;
  ranks::start_mpi();
  const int rank = ranks::rank(), count = ranks::size();
  const long steps = argc > 1 ? std::atol(argv[1]) : 120;
  const std::string scene = argc > 2 ? argv[2] : "shaken_bed.toml";
  // A bed that moves far from where it was split must have its boxes cut anew on several ranks.
  const bool expect_rebalance = argc > 3 && std::string(argv[3]) == "--expect-rebalance";
  int failures = 0;
  const auto expect = [&](bool condition, const char* what, double value) {
    if (!condition) {
      std::fprintf(stderr, "rank %d of %d: FAILED %s (%g)\n", rank, count, what, value);
      ++failures;
    }
  };
  auto distributed = Simulation::from_model(parse_scene(scene_text(scene), scene));
  const std::size_t total = distributed->world().solids->size();
  const DomainBox domain = grain_domain_box(distributed->model());
  split_grains_over_ranks(*distributed->world().solids, *distributed->world().contacts, domain.low, domain.high);
  distributed->world().solid_summary->over_ranks = true;
  std::unique_ptr<Simulation> whole;
  if (rank == 0) whole = Simulation::from_model(parse_scene(scene_text(scene), scene));
  const std::vector<double> local = {static_cast<double>(distributed->world().solids->size())};
  const std::vector<double> owned = ranks::gather_all(local);
  if (rank == 0) {
    std::printf("%zu grains over %d rank(s):", total, count);
    for (const double n : owned) std::printf(" %g", n);
    std::printf("\n");
  }
  double sum = 0.0;
  for (const double n : owned) sum += n;
  expect(sum == static_cast<double>(total), "grains owned over all ranks == grains", sum);

  // The boxes of the split, kept to tell how unequal the ranks would be had the boxes not followed the bed.
  const RankHalo split_boxes = distributed->world().contacts->ranks;
  double largest_early = 0.0, worst_imbalance = 1.0;
  for (long step = 1; step <= steps; ++step) {
    distributed->step();
    const std::vector<double> held = ranks::gather_all({static_cast<double>(distributed->world().solids->size())});
    const double mean = static_cast<double>(total) / count;
    const double most = *std::max_element(held.begin(), held.end());
    worst_imbalance = std::max(worst_imbalance, most / mean);
    // A migration at each rebuild leaves each rank what its box holds; a rebuild cuts anew above kRebalanceAbove.
    expect(most <= std::max(kRebalanceAbove * mean, mean + 2.0), "the ranks' grain counts within the rebalance limit",
           most / mean);
    const Solids gathered = gather_grains_at_root(*distributed->world().solids);
    double difference = 0.0;
    if (rank == 0) {
      whole->step();
      Solids reference = *whole->world().solids;
      std::vector<std::size_t> order(reference.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return reference.id[a] < reference.id[b]; });
      permute_fields(reference, order);
      expect(gathered.size() == reference.size(), "gathered grains == one rank's grains", static_cast<double>(gathered.size()));
      for (std::size_t i = 0; i < std::min(gathered.size(), reference.size()); ++i) {
        if (gathered.id[i] != reference.id[i]) {
          expect(false, "the same ids, in order", static_cast<double>(i));
          break;
        }
        difference = std::max(difference, (gathered.position[i] - reference.position[i]).norm());
      }
      if (step <= 20) largest_early = std::max(largest_early, difference);
      if (step <= 10 || step % 10 == 0) std::printf("step %ld: largest position difference %.3e m\n", step, difference);
      if (step == steps) {
        Vec3 momentum = Vec3::Zero(), momentum_ref = Vec3::Zero();
        double energy = 0.0, energy_ref = 0.0;
        for (std::size_t i = 0; i < gathered.size(); ++i) {
          momentum += gathered.mass[i] * gathered.velocity[i];
          energy += 0.5 * gathered.mass[i] * gathered.velocity[i].squaredNorm();
        }
        for (std::size_t i = 0; i < reference.size(); ++i) {
          momentum_ref += reference.mass[i] * reference.velocity[i];
          energy_ref += 0.5 * reference.mass[i] * reference.velocity[i].squaredNorm();
        }
        const double momentum_scale = std::sqrt(2.0 * energy_ref * 0.5) + 1e-300;
        std::printf("after %ld steps: momentum (%.6e, %.6e, %.6e) against (%.6e, %.6e, %.6e); kinetic energy %.6e "
                    "against %.6e J\n",
                    steps, momentum.x(), momentum.y(), momentum.z(), momentum_ref.x(), momentum_ref.y(),
                    momentum_ref.z(), energy, energy_ref);
        expect((momentum - momentum_ref).norm() < 1e-6 * momentum_scale, "momentum within 1e-6 of one rank's",
               (momentum - momentum_ref).norm());
        expect(std::abs(energy - energy_ref) < 1e-6 * energy_ref, "kinetic energy within 1e-6 of one rank's",
               std::abs(energy - energy_ref) / energy_ref);
      }
    }
  }
  if (rank == 0) expect(largest_early < 1e-12, "position difference over the first 20 steps below 1e-12 m", largest_early);
  // The shaken bed crosses the ranks' boundaries: grains migrate, with their springs.
  const std::vector<double> sent =
      ranks::sum_in_rank_order({static_cast<double>(distributed->world().contacts->ranks.grains_sent)});
  if (rank == 0) std::printf("grains handed between ranks: %g\n", sent[0]);
  if (count > 1) expect(sent[0] > 0.0, "grains migrated between ranks", sent[0]);
  // The bed fell and spread: the split's boxes would now hold unequal shares.
  const std::vector<double> in_split_boxes = grains_per_box(*distributed->world().solids, split_boxes);
  const double split_imbalance =
      *std::max_element(in_split_boxes.begin(), in_split_boxes.end()) * count / static_cast<double>(total);
  const auto rebalances = distributed->world().contacts->ranks.rebalances;
  if (rank == 0)
    std::printf("boxes cut anew %llu time(s); the largest rank's grains over the mean: at most %.3f over the run, "
                "%.3f now in the split's boxes\n",
                static_cast<unsigned long long>(rebalances), worst_imbalance, split_imbalance);
  if (count > 1 && expect_rebalance)
    expect(rebalances > 0, "the boxes followed the moving bed", static_cast<double>(rebalances));
  const bool failed = ranks::any(failures > 0);
  if (rank == 0) std::printf("%s\n", failed ? "FAILED" : "passed");
  return failed ? 1 : 0;
}
