#pragma once
// The domain every particle must stay in, grains and MPS particles alike: the tank at rest, widened by the motion
// amplitude and tank.domain_margin. A particle outside it is lost (a diagnosis, never a silent drop).
#include "components/model.hpp"
#include "components/vec.hpp"

namespace riffle {

/// The box a particle centre must stay in: the tank at rest, widened by the motion amplitude and the margin.
struct DomainBox {
  Vec3 low, high;
  bool contains(const Vec3& point) const {
    return (point.array() >= low.array()).all() && (point.array() <= high.array()).all();
  }
};
DomainBox domain_box(const Model& model);

}  // namespace riffle
