#include "systems/solid_fluid_sampling.hpp"

#include <algorithm>
#include <cmath>

namespace riffle {

namespace {
double largest_diameter(const Model& model) {
  double largest = 0.0;
  for (const SphereSpec& sphere : model.solids.spheres) largest = std::max(largest, 2.0 * sphere.radius);
  return largest;
}
}  // namespace

SolidFluidSampling::SolidFluidSampling(const Model& model)
    : constants_(MpsConstants::from(model.fluid)), coupling_(model.coupling) {
  // numerics 5.3: R_eps >= max(3 l0, d_max); twice d_max keeps a lone grain's own volume from dominating its voidage.
  voidage_radius_ = coupling_.voidage_radius > 0.0
                        ? coupling_.voidage_radius
                        : std::max(3.0 * model.fluid.spacing, 2.0 * std::max(largest_diameter(model), 0.01));
}

void SolidFluidSampling::run(SystemContext& context) {
  const FluidParticles& fluid = context.read<FluidParticles>();
  Solids& solids = context.write<Solids>();
  const std::size_t fluid_count = fluid_slot_count(fluid);
  const double effective_radius = constants_.kernel.effective_radius;
  double largest_radius = 0.0;
  for (const double radius : solids.radius) largest_radius = std::max(largest_radius, radius);
  fluid_grid_.build(fluid.position, 0, fluid_count, std::max(largest_radius + effective_radius, voidage_radius_));
  grain_grid_.build(solids.position, 0, solids.size(), voidage_radius_);
  const WendlandKernel voidage_kernel(voidage_radius_);
  const double particle_volume = constants_.particle_volume;
  const double kPi = 3.14159265358979323846;

  for_each_particle(solids.size(), [&](std::size_t grain) {
    const Vec3 centre = solids.position[grain];
    const WendlandKernel sampling_kernel(solids.radius[grain] + effective_radius);
    double weight_sum = 0.0, fluid_space = 0.0;
    Vec3 velocity = Vec3::Zero(), gradient = Vec3::Zero();
    const double reach = std::max(sampling_kernel.effective_radius, voidage_radius_);
    fluid_grid_.for_each_within(fluid.position, centre, reach, [&](std::uint32_t j) {
      const double distance = (fluid.position[j] - centre).norm();
      const double weight = sampling_kernel.weight(distance);
      weight_sum += weight;
      velocity += weight * fluid.velocity[j];
      gradient += weight * fluid.pressure_gradient[j];
      fluid_space += particle_volume * voidage_kernel.weight(distance);
    });
    solids.fluid_weight[grain] = weight_sum;
    if (weight_sum <= 0.0) {  // out of the water: no fluid forces
      solids.fluid_velocity[grain] = Vec3::Zero();
      solids.pressure_force[grain] = Vec3::Zero();
      solids.voidage[grain] = 1.0;
      return;
    }
    const double volume = 4.0 / 3.0 * kPi * std::pow(solids.radius[grain], 3);
    solids.fluid_velocity[grain] = velocity / weight_sum;
    solids.pressure_force[grain] = coupling_.pressure_gradient ? Vec3(-volume * gradient / weight_sum) : Vec3::Zero();
    double solid_space = 0.0;
    grain_grid_.for_each_within(solids.position, centre, voidage_radius_, [&](std::uint32_t other) {
      solid_space += 4.0 / 3.0 * kPi * std::pow(solids.radius[other], 3) *
                     voidage_kernel.weight((solids.position[other] - centre).norm());
    });
    const double solid_fraction = fluid_space > 0.0 ? solid_space / fluid_space : 0.0;
    solids.voidage[grain] = std::clamp(1.0 - solid_fraction, coupling_.min_voidage, 1.0);
  });
  context.count_items(solids.size());
}

}  // namespace riffle
