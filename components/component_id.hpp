#pragma once
// Names of the components a system can declare access to. The scheduler orders systems by these declarations.
#include <array>
#include <cstdint>
#include <string_view>

namespace riffle {

enum class ComponentId : std::uint8_t {
  kSolids,       ///< solid grains (components/solids.hpp)
  kWalls,        ///< wall planes (components/walls.hpp)
  kTankMotion,   ///< prescribed tank kinematics (components/tank_motion.hpp)
  kStepStatus,   ///< per-step problem flags raised by checks (components/step_status.hpp)
  kSolidSummary, ///< per-step reductions over the solids: energy, max speed (components/solid_summary.hpp)
  kContacts,     ///< contact candidates and histories (components/contacts.hpp)
  kFluid,        ///< MPS fluid, wall and dummy particles (components/fluid.hpp)
  kFluidNeighbours, ///< MPS neighbour lists within r_e, rebuilt every step (components/fluid.hpp)
  kFluidSummary,    ///< per-step reductions over the fluid and the PPE solver report (components/fluid.hpp)
  kFluidSample,     ///< the water at the step start as the grains sample it, a copy (components/fluid.hpp)
  kCount
};

inline constexpr std::array<std::string_view, static_cast<std::size_t>(ComponentId::kCount)> kComponentNames = {
    "solids", "walls", "tank_motion", "step_status", "solid_summary", "contacts", "fluid",
    "fluid_neighbours", "fluid_summary", "fluid_sample"};

constexpr std::string_view component_name(ComponentId id) { return kComponentNames[static_cast<std::size_t>(id)]; }

}  // namespace riffle
