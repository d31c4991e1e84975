#pragma once
// Generic operations over structure-of-arrays components.
//
// Each component lists its per-entity fields exactly once, in a static `for_each_field(self, visit)` that calls
// `visit(FieldInfo, std::vector<T>&)` for every field. Resizing (with each field's default), reordering, size checks,
// checkpointing and VTK export all walk that one table, so no hand-kept field list can drift from the struct.
//
// An entity table split into role components (the grains' `Solids`, the MPS particles' `FluidParticles`) is an
// `EntityGroup` of its roles: it derives from every role, and its table is the roles' tables one after the other. A
// system that writes one role sees only that role's fields; one that reorders the entities writes every role and
// gets the whole group back with `whole_group`.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "components/component_id.hpp"
#include "components/vec.hpp"

namespace riffle {

/// Describes one per-entity field of a component.
struct FieldInfo {
  const char* name;  ///< snake_case name, also the VTK array name
  const char* unit;  ///< SI unit, "1" for dimensionless or ids
  bool output;       ///< written to VTK frames
  double fill = 0.0; ///< value of a new entity's field until set (a Vec3 gets it in every component)
  /// The checkpoint format that first stored this field: reading an older file leaves it at `fill`.
  unsigned since_format = 0;
  /// false: a diagnostic that its system writes before anything reads it (so a resume continues bit for bit without
  /// it): checkpoints leave it out and a read sets it to `fill`. Only FluidParticles::serialize honours it (a
  /// component_model test refuses it on any other table).
  bool checkpointed = true;
};

/// The value a new entity's field of type Value starts with.
template <class Value>
Value field_default(const FieldInfo& info) {
  if constexpr (std::is_same_v<Value, Vec3>) return Vec3::Constant(info.fill);
  else if constexpr (std::is_arithmetic_v<Value>) return static_cast<Value>(info.fill);
  else return Value{};
}

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

/// Every field holds `count` values; new entities get each field's default (FieldInfo::fill).
template <class Component>
void resize_fields(Component& component, std::size_t count) {
  Component::for_each_field(component, [&](const FieldInfo& info, auto& field) {
    using Value = typename std::decay_t<decltype(field)>::value_type;
    field.resize(count, field_default<Value>(info));
  });
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

/// Keeps the entities of slots `kept` (ascending, no repeats) and drops the others: new slot k holds what slot
/// kept[k] held, and every field shrinks to kept.size(). Ids travel with their data; nothing is reordered.
template <class Value>
void keep_slots(std::vector<Value>& values, const std::vector<std::size_t>& kept) {
  for (std::size_t k = 0; k < kept.size(); ++k)
    if (kept[k] != k) values[k] = std::move(values[kept[k]]);  // kept[k] >= k: the source is not yet overwritten
  values.resize(kept.size());
}
template <class Component>
void keep_fields(Component& component, const std::vector<std::size_t>& kept) {
  Component::for_each_field(component, [&](const FieldInfo&, auto& field) { keep_slots(field, kept); });
}

/// An entity table made of role components: it is every role at once, and its field table is the roles' tables in
/// the order of `Roles`. So resize_fields, permute_fields and check_field_sizes on the group cover every role.
template <class... Roles>
struct EntityGroup : Roles... {
  using RoleList = TypeList<Roles...>;

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    (Roles::for_each_field(static_cast<std::conditional_t<std::is_const_v<Self>, const Roles, Roles>&>(self), visit),
     ...);
  }
};

namespace detail {
template <class Group, class... Given, class... Roles>
constexpr bool names_every_role(TypeList<Roles...>) {
  return sizeof...(Given) == sizeof...(Roles) &&
         ((detail::index_in<Roles>(TypeList<Given...>{}) < sizeof...(Given)) && ...);
}
}  // namespace detail

/// The group that the role references belong to, for systems that must touch every role at once (the sorts that
/// reorder the entities): every role of the group must be given (checked when compiling), each fetched through the
/// system's declared access, and all must be parts of one group object (checked when running).
template <class Group, class... Roles>
Group& whole_group(Roles&... roles) {
  static_assert(detail::names_every_role<Group, Roles...>(typename Group::RoleList{}),
                "give every role of the group, each once");
  Group* group = nullptr;
  bool same = true;
  ((same = same && (group == nullptr || group == &static_cast<Group&>(roles)), group = &static_cast<Group&>(roles)),
   ...);
  if (!same) throw std::logic_error("whole_group: the roles belong to different groups");
  return *group;
}

/// Visits the fields of the whole table in its written order: a group that declares `kFieldOrder` (the order its
/// fields had as one table, before the split into roles) is visited in that order, so that checkpoints and VTK frames
/// keep their bytes; any other table in its for_each_field order. Every field of the table must be named exactly once.
template <class Component, class Visit>
void for_each_field_in_order(Component& component, Visit&& visit) {
  using Table = std::remove_const_t<Component>;
  if constexpr (requires { Table::kFieldOrder; }) {
    std::size_t fields = 0;
    Table::for_each_field(component, [&](const FieldInfo&, auto&) { ++fields; });
    if (fields != Table::kFieldOrder.size())
      throw std::logic_error(std::string(Table::kName) + "::kFieldOrder names " +
                             std::to_string(Table::kFieldOrder.size()) + " fields, the table has " +
                             std::to_string(fields));
    for (const char* name : Table::kFieldOrder) {
      std::size_t found = 0;
      Table::for_each_field(component, [&](const FieldInfo& info, auto& field) {
        if (std::strcmp(info.name, name) != 0) return;
        ++found;
        visit(info, field);
      });
      if (found != 1)
        throw std::logic_error(std::string(Table::kName) + "::kFieldOrder names '" + name + "', found " +
                               std::to_string(found) + " times in the table");
    }
  } else {
    Table::for_each_field(component, visit);
  }
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
