#pragma once
// What a decoded checkpoint says, checked before anything uses it. The checksum has no key, so a checkpoint that
// passes it is still only well-formed bytes: every index, count and enum is checked here against the others and
// against the scene the checkpoint carries, every real must be finite, and radii, masses and moments of inertia
// positive. A refusal throws CheckpointError naming the file and the field, e.g.
//   "x.ckpt: solids.radius[12] = -1: must be positive".
#include <cstdint>
#include <string>

#include "engine/output/checkpoint.hpp"
#include "components/model.hpp"
#include "components/world.hpp"

namespace riffle {

/// Size classes are 0..kMaxSizeClass, as the scene reader accepts them ([solids] spheres and blocks).
inline constexpr std::int32_t kMaxSizeClass = 1000;
/// The largest component of a grain's Langevin state (GrainSampledFluid::fluctuation_state, unit variance) a
/// checkpoint may hold.
inline constexpr double kLargestFluctuationState = 100.0;

/// Grains on their own (a [solids] initial_state, or a resumed run's): every real finite; radius, mass and moment of
/// inertia positive; voidage in (0, 1]; material in [0, material_count); size class in [0, kMaxSizeClass]; ids
/// unique, below next_id, and next_id equal to the grain count (grains are never removed). `name` is the file.
void validate_grains(const Solids& grains, std::size_t material_count, const std::string& name);

/// A checkpoint to resume, against the model rebuilt from its own scene and `initial`, the world that model builds
/// at t = 0 (engine/setup/initial_state.hpp): the same components; the same grains (by id: radius, material, size class,
/// mass, inertia), walls and fluid wall particles as the scene makes; grains and fluid inside the domain; contact
/// lists consistent with the grain and wall counts; fluid particles in slots [0, F) with fluid_count = F; time
/// finite, non-negative and consistent with the step count; output bookkeeping consistent with the time.
void validate_checkpoint(const CheckpointData& data, const Model& model, const World& initial,
                         const std::string& name);

}  // namespace riffle
