#pragma once
// solid_summary: the grains' kinetic and potential energy and largest speed after each step, with a reduction whose
// result does not depend on the thread count (diagnostics.csv).
#include "systems/system.hpp"

namespace riffle {

class SolidSummarize final : public System {
 public:
  std::string_view name() const override { return "solid_summary"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties>(), component_ids<SolidSummary>()};
  }
  void run(SystemContext& context) override;
};

}  // namespace riffle
