#pragma once
// The World owns every component of a run. Components a scene does not need are absent (std::nullopt), so
// nothing unused is allocated or scheduled.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "components/contacts.hpp"
#include "components/fluid.hpp"
#include "components/solid_summary.hpp"
#include "components/solids.hpp"
#include "components/step_status.hpp"
#include "components/tank_motion.hpp"
#include "components/walls.hpp"
#include "systems/physics/time_step.hpp"

namespace riffle {

class World {
 public:
  double time = 0.0;       ///< [s] simulated time at the start of the next step
  std::uint64_t step = 0;  ///< engine steps completed
  /// The last step's length and sub-steps, as decide_step_lengths chose them (zero before the first step; not
  /// checkpointed: every step decides anew).
  StepLengths last_step;

  std::optional<Solids> solids;
  std::optional<Walls> walls;
  std::optional<TankMotion> tank_motion;
  std::optional<SolidSummary> solid_summary;
  std::optional<Contacts> contacts;
  std::optional<FluidParticles> fluid;             ///< MPS fluid, wall and dummy particles
  std::optional<FluidSummary> fluid_summary;
  std::optional<FluidNeighbours> fluid_neighbours;  ///< rebuilt from `fluid`, never persistent
  std::optional<FluidSample> fluid_sample;          ///< coupled scenes: copied from `fluid` every step, never persistent
  StepStatus step_status;  ///< always present: every run can fail

  /// The component of type C, or nullptr if the scene does not use it.
  template <class C>
  C* find() {
    if constexpr (std::is_same_v<C, Solids>) return solids ? &*solids : nullptr;
    else if constexpr (std::is_same_v<C, Walls>) return walls ? &*walls : nullptr;
    else if constexpr (std::is_same_v<C, TankMotion>) return tank_motion ? &*tank_motion : nullptr;
    else if constexpr (std::is_same_v<C, SolidSummary>) return solid_summary ? &*solid_summary : nullptr;
    else if constexpr (std::is_same_v<C, Contacts>) return contacts ? &*contacts : nullptr;
    else if constexpr (std::is_same_v<C, FluidParticles>) return fluid ? &*fluid : nullptr;
    else if constexpr (std::is_same_v<C, FluidSummary>) return fluid_summary ? &*fluid_summary : nullptr;
    else if constexpr (std::is_same_v<C, FluidNeighbours>) return fluid_neighbours ? &*fluid_neighbours : nullptr;
    else if constexpr (std::is_same_v<C, FluidSample>) return fluid_sample ? &*fluid_sample : nullptr;
    else if constexpr (std::is_same_v<C, StepStatus>) return &step_status;
    else static_assert(sizeof(C) == 0, "unknown component type");
  }

  /// True if the component with this id exists in this world.
  bool has(ComponentId id) const;
};

}  // namespace riffle
