#include "components/world.hpp"

namespace riffle {

bool World::has(ComponentId id) const {
  bool present = false;
  [&]<class... Components>(TypeList<Components...>) {
    ((component_id<Components> == id ? (present = find<Components>() != nullptr) : false), ...);
  }(ComponentList{});
  return present;
}

}  // namespace riffle
