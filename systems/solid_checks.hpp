#pragma once
// End-of-step checks and reductions over the grains.
//   solid_domain_check: flags the first grain (lowest slot) whose state is not finite or whose centre left the
//                       domain (the tank's swept box widened by tank.domain_margin).
//   solid_summary:      kinetic and potential energy and the largest speed, with a reduction whose result does
//                       not depend on the thread count.
#include "engine/system.hpp"

namespace riffle {

/// The box a grain centre must stay in: the tank at rest, widened by the motion amplitude and the margin.
struct DomainBox {
  Vec3 low, high;
  bool contains(const Vec3& point) const {
    return (point.array() >= low.array()).all() && (point.array() <= high.array()).all();
  }
};
DomainBox solid_domain(const Model& model);

class SolidDomainCheck final : public System {
 public:
  std::string_view name() const override { return "solid_domain_check"; }
  Access access() const override { return {{ComponentId::kSolids}, {ComponentId::kStepStatus}}; }
  void run(SystemContext& context) override;
};

class SolidSummarize final : public System {
 public:
  std::string_view name() const override { return "solid_summary"; }
  Access access() const override { return {{ComponentId::kSolids}, {ComponentId::kSolidSummary}}; }
  void run(SystemContext& context) override;
};

}  // namespace riffle
