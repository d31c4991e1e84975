#pragma once
// The component list: every component a system can declare access to, named once, here. A component's id is its
// place in this list, its name is its `kName`; the World finds it, the scheduler orders systems by it, and the graph
// dump names it from this list (components/component_list.hpp checks the rest against it at compile time).
//
// The per-entity tables of the grains (components/solids.hpp) and of the MPS particles (components/fluid.hpp) are
// split into role components, one per set of fields that systems write together, so that two systems that write
// different roles of the same entities (contact and drag forces, say) need not wait for each other.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <vector>

namespace riffle {

template <class... Types>
struct TypeList {};

// Grains (components/solids.hpp): the roles of the `Solids` table.
struct GrainState;
struct GrainProperties;
struct GrainTotalForce;
struct GrainContactForce;
struct GrainDrag;
struct GrainSampledFluid;
struct GrainVoidage;
struct GrainAddedMass;
struct GrainLubrication;
// MPS particles (components/fluid.hpp): the roles of the `FluidParticles` table.
struct ParticleState;
struct ParticlePrediction;
struct ParticlePressure;
struct ParticleDensity;
struct ParticleDragReaction;
// Whole components.
struct Walls;
struct TankMotion;
struct StepStatus;
struct SolidSummary;
struct Contacts;
struct FluidNeighbours;
struct FluidSummary;
struct FluidSample;
struct MeanFlowColumn;

using ComponentList =
    TypeList<GrainState, GrainProperties, GrainTotalForce, GrainContactForce, GrainDrag, GrainSampledFluid,
             GrainVoidage, GrainAddedMass, GrainLubrication, Walls, TankMotion, StepStatus, SolidSummary, Contacts, ParticleState, ParticlePrediction,
             ParticlePressure, ParticleDensity, ParticleDragReaction, FluidNeighbours, FluidSummary, FluidSample,
             MeanFlowColumn>;

/// A component's place in ComponentList (no enumerators: every value comes from the list).
enum class ComponentId : std::uint8_t {};

namespace detail {
template <class C, class... Types>
constexpr std::size_t index_in(TypeList<Types...>) {
  constexpr bool matches[] = {std::is_same_v<C, Types>...};
  std::size_t index = 0;
  while (index < sizeof...(Types) && !matches[index]) ++index;
  return index;
}
template <class... Types>
constexpr std::size_t list_size(TypeList<Types...>) {
  return sizeof...(Types);
}
}  // namespace detail

inline constexpr std::size_t kComponentCount = detail::list_size(ComponentList{});

template <class C>
inline constexpr bool is_component = detail::index_in<C>(ComponentList{}) < kComponentCount;

/// The id of component C: `component_id<GrainState>`.
template <class C>
inline constexpr ComponentId component_id = [] {
  static_assert(is_component<C>, "not in ComponentList (components/component_id.hpp)");
  return static_cast<ComponentId>(detail::index_in<C>(ComponentList{}));
}();

/// The component's snake_case name (its kName), for messages and the graph dump.
inline std::string_view component_name(ComponentId id);  // defined in components/component_list.hpp

}  // namespace riffle
