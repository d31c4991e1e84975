#include "systems/coupling/fluid_sample_copy.hpp"

#include <algorithm>

#include "systems/physics/coupling/sampling_kernel.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/ranks/coupling_ranks.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

void FluidSampleCopy::run(SystemContext& context) {
  const ParticleState& particles = context.read<ParticleState>();
  const ParticlePressure& pressures = context.read<ParticlePressure>();
  FluidSample& sample = context.write<FluidSample>();
  const auto fluid_count = static_cast<std::ptrdiff_t>(fluid_slot_count(particles));
  sample.position.assign(particles.position.begin(), particles.position.begin() + fluid_count);
  sample.velocity.assign(particles.velocity.begin(), particles.velocity.begin() + fluid_count);
  sample.pressure_gradient.assign(pressures.pressure_gradient.begin(), pressures.pressure_gradient.begin() + fluid_count);
  // nu <lap u> of the last prediction, for [coupling] viscous_stress; an empty field (a world built without it) or a
  // scene without the force copies nothing.
  if (viscous_stress_) {
    const ParticlePrediction& prediction = context.read<ParticlePrediction>();
    sample.viscous_acceleration.assign(prediction.viscous_acceleration.begin(),
                                       prediction.viscous_acceleration.begin() + fluid_count);
  } else {
    sample.viscous_acceleration.clear();
  }
  if (over_ranks_) append_other_ranks(context, sample);
  context.count_items(sample.size());
}

void FluidSampleCopy::append_other_ranks(SystemContext& context, FluidSample& sample) const {
  const GrainState& grains = context.read<GrainState>();
  const RankHalo& grain_ranks = context.read<Contacts>().ranks;
  if (!grain_ranks.active) return;
  double largest_radius = 0.0;
  for (const double radius : context.read<GrainProperties>().radius) largest_radius = std::max(largest_radius, radius);
  // A grain samples within r + r_e of its centre (a dilute grain's kernel no narrower than at l0 = r).
  const PeriodicBox box = periodic_box(context.model);
  const double kernel_radius =
      coupling_kernel_radius(ranks::max(largest_radius), effective_radius_, spacing_, dilute_kernels_);
  const CouplingBoxes boxes =
      coupling_boxes(grain_ranks.box_low, grain_ranks.box_high, grains.position, kernel_radius, box);
  const std::size_t own = sample.size();
  const std::vector<std::vector<std::uint32_t>> near =
      indices_near_other_ranks(std::span<const Vec3>(sample.position.data(), own), boxes, box);
  exchange_records(
      near,
      [&](ByteWriter& out, std::uint32_t i) {
        out.put(sample.position[i]);
        out.put(sample.velocity[i]);
        out.put(sample.pressure_gradient[i]);
        if (viscous_stress_) out.put(sample.viscous_acceleration[i]);
      },
      [&](ByteReader& in) {
        sample.position.push_back(in.get<Vec3>());
        sample.velocity.push_back(in.get<Vec3>());
        sample.pressure_gradient.push_back(in.get<Vec3>());
        if (viscous_stress_) sample.viscous_acceleration.push_back(in.get<Vec3>());
      });
}

}  // namespace riffle
