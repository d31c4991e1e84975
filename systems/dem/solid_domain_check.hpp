#pragma once
// solid_domain_check: flags the first grain (lowest slot) whose state is not finite or whose centre left the domain
// (systems/physics/geometry/domain.hpp), so that the run stops with a diagnosis naming it.
#include "systems/system.hpp"

namespace riffle {

class SolidDomainCheck final : public System {
 public:
  std::string_view name() const override { return "solid_domain_check"; }
  Access access() const override { return {component_ids<GrainState>(), component_ids<StepStatus>()}; }
  void run(SystemContext& context) override;
};

}  // namespace riffle
