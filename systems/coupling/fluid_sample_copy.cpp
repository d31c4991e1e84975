#include "systems/coupling/fluid_sample_copy.hpp"

#include "systems/physics/mps/mps_common.hpp"

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
  context.count_items(static_cast<std::size_t>(fluid_count));
}

}  // namespace riffle
