#pragma once
// Contact forces on the grains (seed 000 Sec. 3.2 Eqs. 15-19 with the laws of contact_law.hpp):
//   solid_contact_forces: each candidate pair (grain-grain, grain-wall) evaluated once, into the pair arrays, and
//                         each grain's sum over the pairs where it is first (Contacts::first_force / first_torque);
//   solid_contact_gather: each grain adds its second-grain and wall pairs to that sum, in a fixed order, into
//                         contact_force / contact_torque;
// Splitting evaluation from gathering keeps every write private to one task and the sums in a fixed order, so the
// result is bit-identical for any thread count. Torque lever arm: R_i n for each grain (numerics.md Sec. 4.1: the
// seed's (1/2) xi_ij holds only for equal sizes).
#include "systems/system.hpp"

namespace riffle {

class SolidContactForces final : public System {
 public:
  std::string_view name() const override { return "solid_contact_forces"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties, Walls>(), component_ids<Contacts>()};
  }
  void run(SystemContext& context) override;
};

class SolidContactGather final : public System {
 public:
  std::string_view name() const override { return "solid_contact_gather"; }
  Access access() const override { return {component_ids<Contacts>(), component_ids<GrainContactForce>()}; }
  void run(SystemContext& context) override;
};

}  // namespace riffle
