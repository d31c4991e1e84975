#include "systems/solid_fluid_sampling.hpp"

#include "systems/fluid_pair_batch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace riffle {

SolidFluidSampling::SolidFluidSampling(const Model& model)
    : constants_(MpsConstants::from(model.fluid)), coupling_(model.coupling) {
  // numerics 5.3: R_eps >= max(3 l0, d_max); twice d_max keeps a lone grain's own volume from dominating its voidage.
  voidage_radius_ = coupling_.voidage_radius;  // 0: from the grains present at the first run
  spacing_ = model.fluid.spacing;
}

void SolidFluidSampling::run(SystemContext& context) {
  const FluidParticles& fluid = context.read<FluidParticles>();
  Solids& solids = context.write<Solids>();
  const std::size_t fluid_count = fluid_slot_count(fluid);
  const double effective_radius = constants_.kernel.effective_radius;
  const double kPi = 3.14159265358979323846;
  double largest_radius = 0.0, smallest_radius = std::numeric_limits<double>::infinity();
  grain_volumes_.resize(solids.size());
  for (std::size_t grain = 0; grain < solids.size(); ++grain) {
    largest_radius = std::max(largest_radius, solids.radius[grain]);
    smallest_radius = std::min(smallest_radius, solids.radius[grain]);
    grain_volumes_[grain] = 4.0 / 3.0 * kPi * std::pow(solids.radius[grain], 3);
  }
  // numerics 5.3: R_eps >= max(3 l0, d_max); twice d_max keeps a lone grain's own volume from dominating its voidage.
  if (voidage_radius_ <= 0.0) voidage_radius_ = std::max(3.0 * spacing_, 4.0 * largest_radius);
  // Cells of half the smallest sampling radius: a query scans about 5^3 cells holding about twice the sphere's
  // volume; cells of the largest radius made every small grain test ten times the particles it keeps.
  if (!solids.radius.empty()) fluid_grid_.build(fluid.position, 0, fluid_count, 0.5 * (smallest_radius + effective_radius));
  // Cells of (2 pi / 21)^(1/3) R_eps: one cell holds the volume of the Wendland kernel on R_eps (numerics 1.2),
  // so the grid averages over the same volume as the kernel form of numerics 5.3.
  voidage_grid_.build(solids.position, grain_volumes_, fluid.position, fluid_count, constants_.particle_volume,
                      0.668 * voidage_radius_);

  for_each_particle(solids.size(), [&](std::size_t grain) {
    const Vec3 centre = solids.position[grain];
    const WendlandKernel sampling_kernel(solids.radius[grain] + effective_radius);
    const double radius_squared = sampling_kernel.effective_radius * sampling_kernel.effective_radius;
    double weight_sum = 0.0;
    Vec3 velocity = Vec3::Zero(), gradient = Vec3::Zero();
    // The fluid particles within the sampling radius, in grid order, a batch at a time: each candidate is written
    // and kept by advancing the end (about half are kept, at random to a branch predictor), the distances and
    // weights of a batch are evaluated in one vectorised pass (the same operations as WendlandKernel::weight of the
    // norm), and the sums run in the same order as one candidate at a time.
    FluidPairBatch batch;
    batch.count = 0;
    const auto flush = [&] {
      evaluate_pair_geometry(batch, sampling_kernel);
      for (std::size_t k = 0; k < batch.count; ++k) {
        const double weight = batch.weight[k];
        weight_sum += weight;
        velocity += weight * fluid.velocity[batch.slot[k]];
        gradient += weight * fluid.pressure_gradient[batch.slot[k]];
      }
      batch.count = 0;
    };
    fluid_grid_.for_each_candidate_run(centre, sampling_kernel.effective_radius,
                                       [&](const std::uint32_t* first, const std::uint32_t* last) {
                                         for (const std::uint32_t* member = first; member < last; ++member) {
                                           const std::size_t k = batch.count;
                                           batch.slot[k] = *member;
                                           batch.distance_squared[k] = (fluid.position[*member] - centre).squaredNorm();
                                           batch.count += batch.distance_squared[k] < radius_squared ? 1 : 0;
                                           if (batch.count == kPairBatch) flush();
                                         }
                                       });
    if (batch.count > 0) flush();
    solids.fluid_weight[grain] = weight_sum;
    if (weight_sum <= 0.0) {  // out of the water: no fluid forces
      solids.fluid_velocity[grain] = Vec3::Zero();
      solids.pressure_force[grain] = Vec3::Zero();
      solids.voidage[grain] = 1.0;
      return;
    }
    solids.fluid_velocity[grain] = velocity / weight_sum;
    solids.pressure_force[grain] =
        coupling_.pressure_gradient ? Vec3(-grain_volumes_[grain] * gradient / weight_sum) : Vec3::Zero();
    solids.voidage[grain] = std::clamp(1.0 - voidage_grid_.solid_fraction(centre), coupling_.min_voidage, 1.0);
  });
  context.count_items(solids.size());
}

}  // namespace riffle
