#pragma once
// Wall planes. The tank is six (or fewer, for open faces) planes that move with the prescribed tank motion;
// the wall-motion system is the only writer of their kinematics.
#include <cereal/types/string.hpp>
#include <cereal/types/vector.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "components/component_id.hpp"
#include "components/soa.hpp"
#include "components/vec.hpp"

namespace riffle {

struct Walls {
  static constexpr ComponentId kId = component_id<Walls>;
  static constexpr std::string_view kName = "walls";
  static constexpr bool kPersistent = true;

  std::vector<EntityId> id;            ///< [1] stable identity
  std::vector<std::string> name;       ///< "floor", "left", ... as named in the scene
  std::vector<Vec3> rest_point;        ///< [m] a point on the plane at zero tank displacement (the face centre)
  std::vector<Vec3> point;             ///< [m] the face centre now (rest_point + tank displacement if moving)
  std::vector<Vec3> normal;            ///< [1] unit normal pointing into the domain
  std::vector<Vec3> velocity;          ///< [m/s] plane velocity, the exact time derivative of `point`
  std::vector<Vec3> half_extent_u;     ///< [m] half of the face's first edge (for drawing and bounds)
  std::vector<Vec3> half_extent_v;     ///< [m] half of the face's second edge
  std::vector<std::int32_t> moves_with_tank;  ///< [1] 1 if the plane follows the tank motion
  std::vector<std::int32_t> material;  ///< [1] index into the scene's material table

  EntityId next_id = 0;

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"id", "1", true}, self.id);
    visit(FieldInfo{"name", "", false}, self.name);
    visit(FieldInfo{"rest_point", "m", false}, self.rest_point);
    visit(FieldInfo{"point", "m", false}, self.point);
    visit(FieldInfo{"normal", "1", true}, self.normal);
    visit(FieldInfo{"velocity", "m/s", true}, self.velocity);
    visit(FieldInfo{"half_extent_u", "m", false}, self.half_extent_u);
    visit(FieldInfo{"half_extent_v", "m", false}, self.half_extent_v);
    visit(FieldInfo{"moves_with_tank", "1", true}, self.moves_with_tank);
    visit(FieldInfo{"material", "1", true}, self.material);
  }

  std::size_t size() const { return id.size(); }

  /// Appends one plane, at rest; returns its slot.
  std::size_t add(const std::string& wall_name, const Vec3& centre, const Vec3& inward_normal, const Vec3& half_u,
                  const Vec3& half_v, bool follows_tank, std::int32_t material_index) {
    const std::size_t slot = size();
    resize_fields(*this, slot + 1);
    id[slot] = next_id++;
    name[slot] = wall_name;
    rest_point[slot] = centre;
    point[slot] = centre;
    normal[slot] = inward_normal.normalized();
    half_extent_u[slot] = half_u;
    half_extent_v[slot] = half_v;
    moves_with_tank[slot] = follows_tank ? 1 : 0;
    material[slot] = material_index;
    return slot;
  }

  template <class Archive>
  void serialize(Archive& archive) {
    archive(next_id);
    for_each_field(*this, [&](const FieldInfo&, auto& field) { archive(field); });
  }
};

}  // namespace riffle
