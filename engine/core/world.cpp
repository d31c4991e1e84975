#include "engine/core/world.hpp"

namespace riffle {

bool World::has(ComponentId id) const {
  switch (id) {
    case ComponentId::kSolids: return solids.has_value();
    case ComponentId::kWalls: return walls.has_value();
    case ComponentId::kTankMotion: return tank_motion.has_value();
    case ComponentId::kSolidSummary: return solid_summary.has_value();
    case ComponentId::kContacts: return contacts.has_value();
    case ComponentId::kFluid: return fluid.has_value();
    case ComponentId::kFluidNeighbours: return fluid_neighbours.has_value();
    case ComponentId::kFluidSummary: return fluid_summary.has_value();
    case ComponentId::kFluidSample: return fluid_sample.has_value();
    case ComponentId::kStepStatus: return true;
    case ComponentId::kCount: break;
  }
  return false;
}

}  // namespace riffle
