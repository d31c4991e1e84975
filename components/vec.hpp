#pragma once
// Small vector vocabulary shared by every component and system.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <cstdint>

namespace riffle {

using Vec3 = Eigen::Vector3d;  ///< [SI] a 3-vector; 24 bytes, no alignment requirement
using EntityId = std::uint64_t;  ///< stable identity of a particle or wall; never reused within a run

}  // namespace riffle

namespace cereal {
// Vec3 is stored as three doubles so checkpoints do not depend on Eigen's memory layout.
template <class Archive>
void serialize(Archive& archive, riffle::Vec3& v) {
  archive(v[0], v[1], v[2]);
}
}  // namespace cereal
