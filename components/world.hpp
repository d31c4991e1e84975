#pragma once
// The World owns every component of a run. Components a scene does not need are absent (std::nullopt), so
// nothing unused is allocated or scheduled. The roles of an entity table (components/solids.hpp, fluid.hpp) are
// stored together as their group and found as parts of it.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>

#include "components/component_list.hpp"
#include "components/step_lengths.hpp"

namespace riffle {

namespace detail {
template <class T>
struct unwrap_optional {
  using type = T;
};
template <class T>
struct unwrap_optional<std::optional<T>> {
  using type = T;
};
template <class MemberPointer>
struct member_of;
template <class Member, class Owner>
struct member_of<Member Owner::*> {
  using type = typename unwrap_optional<Member>::type;
};
}  // namespace detail

class World {
 public:
  double time = 0.0;       ///< [s] simulated time at the start of the next step
  std::uint64_t step = 0;  ///< engine steps completed
  /// The last step's length and sub-steps, as decide_step_lengths chose them (zero before the first step; not
  /// checkpointed: every step decides anew).
  StepLengths last_step;

  std::optional<Solids> solids;                     ///< the grains: every Grain* role
  std::optional<Walls> walls;
  std::optional<TankMotion> tank_motion;
  std::optional<Contacts> contacts;
  std::optional<FluidParticles> fluid;              ///< MPS fluid, wall and dummy particles: every Particle* role
  std::optional<FluidSummary> fluid_summary;
  std::optional<SolidSummary> solid_summary;
  std::optional<FluidNeighbours> fluid_neighbours;  ///< rebuilt from `fluid`, never persistent
  std::optional<FluidSample> fluid_sample;          ///< coupled scenes: copied from `fluid` every step, never persistent
  std::optional<MeanFlowColumn> mean_flow;          ///< the mean-flow fluid's column ([mean_flow])
  StepStatus step_status;  ///< always present: every run can fail

  /// Every stored part above, once. The checkpoint archives the persistent ones in this order (format 4: solids,
  /// walls, tank_motion, contacts, fluid, fluid_summary; format 9 adds mean_flow); find and has look components up
  /// here.
  static constexpr auto kParts =
      std::make_tuple(&World::solids, &World::walls, &World::tank_motion, &World::contacts, &World::fluid,
                      &World::fluid_summary, &World::solid_summary, &World::fluid_neighbours, &World::fluid_sample,
                      &World::step_status, &World::mean_flow);

  /// Calls visit(part) for every stored part in kParts order (a std::optional, or the always present StepStatus).
  template <class Self, class Visit>
  static void for_each_part(Self& self, Visit&& visit) {
    std::apply([&](auto... members) { (visit(self.*members), ...); }, kParts);
  }

  /// The component of type C (a role is found in its group), or nullptr if the scene does not use it.
  template <class C>
  C* find() {
    return const_cast<C*>(std::as_const(*this).template find<C>());
  }
  template <class C>
  const C* find() const {
    const C* found = nullptr;
    for_each_part(*this, [&](const auto& part) {
      using Part = std::decay_t<decltype(part)>;
      using Stored = typename detail::unwrap_optional<Part>::type;
      if constexpr (std::is_base_of_v<C, Stored>) {
        if constexpr (std::is_same_v<Part, Stored>) found = &part;
        else if (part) found = &*part;
      }
    });
    return found;
  }

  /// True if the component with this id exists in this world.
  bool has(ComponentId id) const;
};

namespace detail {
template <class C, class... MemberPointers>
constexpr std::size_t parts_holding(TypeList<MemberPointers...>) {
  return ((std::is_base_of_v<C, typename member_of<MemberPointers>::type> ? 1 : 0) + ...);
}
template <class... Components, class... MemberPointers>
constexpr bool each_stored_once(TypeList<Components...>, TypeList<MemberPointers...> parts) {
  return ((parts_holding<Components>(parts) == 1) && ...);
}
template <class... MemberPointers>
TypeList<MemberPointers...> as_type_list(std::tuple<MemberPointers...>);
}  // namespace detail

/// The component list and the World's parts agree: every component is stored in exactly one part.
static_assert(detail::each_stored_once(ComponentList{}, decltype(detail::as_type_list(World::kParts)){}),
              "every component of ComponentList must be stored in exactly one part of World::kParts");

}  // namespace riffle
