#pragma once
// Contact forces on the grains (seed 000 Sec. 3.2 Eqs. 15-19 with the laws of contact_law.hpp): each candidate pair
// (grain-grain, grain-wall) evaluated once per sub-step, its force and torques added straight to both grains'
// contact_force / contact_torque. The grains are cut into slabs along one axis (systems/physics/dem/contact_slabs.hpp);
// the tasks of slabs that write common grains run in a fixed order and the others side by side, so no two tasks write
// one grain at once and each grain's sum runs in an order that does not depend on the thread count: the result is
// bit-identical for any thread count. Torque lever arm: R_i n for
// each grain (numerics.md Sec. 4.1: the seed's (1/2) xi_ij holds only for equal sizes).
#include "systems/physics/dem/contact_slabs.hpp"
#include "systems/system.hpp"

namespace riffle {

class SolidContactForces final : public System {
 public:
  std::string_view name() const override { return "solid_contact_forces"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties, Walls>(), component_ids<Contacts, GrainContactForce>()};
  }
  void run(SystemContext& context) override;

 private:
  // The slabs' task order, a function of the slab count and periodicity alone: made when they change, not every
  // sub-step.
  ContactSlabSchedule schedule_;
  std::uint32_t schedule_slabs_ = 0;
  bool schedule_periodic_ = false;
};

}  // namespace riffle
