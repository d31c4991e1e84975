#pragma once
// Every component, complete: the names of ComponentList (components/component_id.hpp) and the compile-time checks
// that each component's declarations agree with its place in the list.
#include <array>
#include <string_view>

#include "components/component_id.hpp"
#include "components/contacts.hpp"
#include "components/fluid.hpp"
#include "components/mean_flow.hpp"
#include "components/solid_summary.hpp"
#include "components/solids.hpp"
#include "components/step_status.hpp"
#include "components/tank_motion.hpp"
#include "components/walls.hpp"

namespace riffle {

namespace detail {
template <class... Components>
constexpr std::array<std::string_view, sizeof...(Components)> component_names(TypeList<Components...>) {
  return {Components::kName...};
}
template <class... Components>
constexpr bool ids_match_places(TypeList<Components...>) {
  return ((Components::kId == component_id<Components>) && ...);
}
template <std::size_t N>
constexpr bool all_distinct(const std::array<std::string_view, N>& names) {
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = i + 1; j < N; ++j)
      if (names[i] == names[j]) return false;
  return true;
}
}  // namespace detail

/// The names of ComponentList, in its order.
inline constexpr auto kComponentNames = detail::component_names(ComponentList{});

static_assert(detail::ids_match_places(ComponentList{}), "a component's kId must be component_id of itself");
static_assert(detail::all_distinct(kComponentNames), "component names must be distinct");

inline std::string_view component_name(ComponentId id) { return kComponentNames[static_cast<std::size_t>(id)]; }

/// The ids of the given components; a group (Solids, FluidParticles) stands for all its roles. For declarations:
/// `component_ids<GrainState, GrainProperties>()`.
template <class... Components>
std::vector<ComponentId> component_ids() {
  std::vector<ComponentId> ids;
  auto add = [&]<class C>() {
    if constexpr (requires { typename C::RoleList; })
      [&]<class... Roles>(TypeList<Roles...>) { (ids.push_back(component_id<Roles>), ...); }(typename C::RoleList{});
    else
      ids.push_back(component_id<C>);
  };
  (add.template operator()<Components>(), ...);
  return ids;
}

}  // namespace riffle
