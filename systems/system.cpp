#include "systems/system.hpp"

#include <algorithm>

namespace riffle {

bool Access::reads_component(ComponentId id) const { return std::find(reads.begin(), reads.end(), id) != reads.end(); }

bool Access::writes_component(ComponentId id) const {
  return std::find(writes.begin(), writes.end(), id) != writes.end();
}

void SystemContext::fail(const char* verb, ComponentId id) const {
  throw UndeclaredAccess("system '" + std::string(system_.name()) + "' " + verb + " component '" +
                         std::string(component_name(id)) + "' without declaring it");
}

void SystemContext::missing(ComponentId id) const {
  throw std::logic_error("system '" + std::string(system_.name()) + "' needs component '" +
                         std::string(component_name(id)) + "', which this scene does not have");
}

}  // namespace riffle
