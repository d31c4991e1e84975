#include "systems/coupling/fluid_sample_copy.hpp"

#include "systems/physics/mps_common.hpp"

namespace riffle {

void FluidSampleCopy::run(SystemContext& context) {
  const FluidParticles& fluid = context.read<FluidParticles>();
  FluidSample& sample = context.write<FluidSample>();
  const auto fluid_count = static_cast<std::ptrdiff_t>(fluid_slot_count(fluid));
  sample.position.assign(fluid.position.begin(), fluid.position.begin() + fluid_count);
  sample.velocity.assign(fluid.velocity.begin(), fluid.velocity.begin() + fluid_count);
  sample.pressure_gradient.assign(fluid.pressure_gradient.begin(), fluid.pressure_gradient.begin() + fluid_count);
  context.count_items(static_cast<std::size_t>(fluid_count));
}

}  // namespace riffle
