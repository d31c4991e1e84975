#pragma once
// Generic operations over structure-of-arrays components.
//
// Each component lists its per-entity fields exactly once, in a static `for_each_field(self, visit)` that calls
// `visit(FieldInfo, std::vector<T>&)` for every field. Resizing, reordering, size checks, checkpointing and VTK
// export all walk that one table, so no hand-kept field list can drift from the struct.
#include <algorithm>
#include <cstddef>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace riffle {

/// Describes one per-entity field of a component.
struct FieldInfo {
  const char* name;  ///< snake_case name, also the VTK array name
  const char* unit;  ///< SI unit, "1" for dimensionless or ids
  bool output;       ///< written to VTK frames
};

/// Number of entities, taken from the first field.
template <class Component>
std::size_t entity_count(const Component& component) {
  std::size_t count = 0;
  bool first = true;
  Component::for_each_field(component, [&](const FieldInfo&, const auto& field) {
    if (first) count = field.size();
    first = false;
  });
  return count;
}

/// Invariant of every SoA component: all fields hold one value per entity.
template <class Component>
void check_field_sizes(const Component& component, const char* component_name) {
  const std::size_t count = entity_count(component);
  Component::for_each_field(component, [&](const FieldInfo& info, const auto& field) {
    if (field.size() != count)
      throw std::logic_error(std::string(component_name) + "." + info.name + " holds " +
                             std::to_string(field.size()) + " values, expected " + std::to_string(count));
  });
}

template <class Component>
void resize_fields(Component& component, std::size_t count) {
  Component::for_each_field(component, [&](const FieldInfo&, auto& field) { field.resize(count); });
}

/// New slot k of `values` holds what slot order[k] held, for k < order.size(); `order` is a permutation of
/// 0..order.size()-1 and the slots after it stay as they are.
template <class Value>
void permute_prefix(std::vector<Value>& values, const std::vector<std::size_t>& order) {
  std::vector<Value> head(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) head[k] = values[order[k]];
  std::copy(head.begin(), head.end(), values.begin());
}

/// Reorders every field so that new slot k holds the entity that was in slot order[k].
/// `order` must be a permutation of 0..m-1 with m <= n; slots m..n-1 stay where they are. Ids travel with their data,
/// so state keyed by id stays valid.
template <class Component>
void permute_fields(Component& component, const std::vector<std::size_t>& order) {
  Component::for_each_field(component, [&](const FieldInfo&, auto& field) { permute_prefix(field, order); });
}

/// True if `order` is a permutation of 0..n-1.
inline bool is_permutation_of_indices(const std::vector<std::size_t>& order) {
  std::vector<char> seen(order.size(), 0);
  for (std::size_t index : order) {
    if (index >= order.size() || seen[index]) return false;
    seen[index] = 1;
  }
  return true;
}

}  // namespace riffle
