// The component model: one component list, role tables that cover every field of their struct, the whole-group
// helpers, field defaults, and the checkpoint layout of format 4 that the role split must not change.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <memory>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <cereal/archives/binary.hpp>

#include "systems/system.hpp"
#include "engine/output/checkpoint.hpp"
#include "engine/setup/initial_state.hpp"
#include "systems/coupling/solid_drag.hpp"
#include "systems/coupling/solid_fluid_sampling.hpp"
#include "systems/dem/solid_contacts.hpp"
#include "systems/dem/solid_force_sum.hpp"
#include "systems/dem/solid_integrate.hpp"
#include "systems/dem/solid_neighbours.hpp"
#include "systems/dem/wall_motion.hpp"
#include "systems/mps/fluid_cell_sort.hpp"
#include "systems/mps/fluid_correct.hpp"
#include "systems/mps/fluid_free_surface.hpp"
#include "systems/mps/fluid_neighbours.hpp"
#include "systems/mps/fluid_predict.hpp"
#include "systems/mps/fluid_pressure.hpp"
#include "systems/mps/fluid_wall_motion.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

namespace {

/// Fields a role's table visits.
template <class Role>
std::size_t table_fields() {
  Role role;
  std::size_t fields = 0;
  Role::for_each_field(role, [&](const FieldInfo&, auto&) { ++fields; });
  return fields;
}

/// A role holds nothing but its per-entity vectors (all of one size, whatever the element), so a role whose table
/// forgets a field is larger than its table says.
template <class... Roles>
void check_tables_cover_structs(TypeList<Roles...>) {
  const auto check = [](std::string_view name, std::size_t bytes, std::size_t fields) {
    CHECK_MESSAGE(bytes == fields * sizeof(std::vector<int>), name);
  };
  (check(Roles::kName, sizeof(Roles), table_fields<Roles>()), ...);
}

template <class Group>
std::vector<std::string> group_field_names() {
  Group group;
  std::vector<std::string> names;
  Group::for_each_field(group, [&](const FieldInfo& info, auto&) { names.emplace_back(info.name); });
  return names;
}

/// True if one of the two writes a component the other reads or writes: they cannot run side by side.
bool conflict(const System& a, const System& b) {
  const Access first = a.access(), second = b.access();
  const auto touches = [](const Access& access, ComponentId id) {
    return access.reads_component(id) || access.writes_component(id);
  };
  for (const ComponentId id : first.writes)
    if (touches(second, id)) return true;
  for (const ComponentId id : second.writes)
    if (touches(first, id)) return true;
  return false;
}

}  // namespace

TEST_CASE("the role split lets contact beside drag, and the fluid's step beside the grains' sub-steps") {
  const Model model = test::fluid_model();
  const SolidContactForces contact_forces;
  const SolidDrag drag(model);
  CHECK_FALSE(conflict(contact_forces, drag));
  // ... but the sum waits for both, and the sampling's result is read by the drag.
  const SolidForceSum force_sum;
  const SolidFluidSampling sampling(model);
  CHECK(conflict(contact_forces, force_sum));
  CHECK(conflict(drag, force_sum));
  CHECK(conflict(sampling, drag));

  using At = FluidNeighbourSearch::Positions;
  std::vector<std::unique_ptr<System>> fluid_step, grain_substep;
  fluid_step.push_back(std::make_unique<FluidNeighbourSearch>(0.01, 0.001, 0.001, At::kCurrent));
  fluid_step.push_back(std::make_unique<FluidPredict>(model.fluid));
  fluid_step.push_back(std::make_unique<FluidWallMotion>());
  fluid_step.push_back(std::make_unique<FluidCellSort>(10, 1, 0.01, 0.001));
  fluid_step.push_back(std::make_unique<FluidNeighbourSearch>(0.01, 0.001, 0.001, At::kPredicted));
  fluid_step.push_back(std::make_unique<FluidFreeSurface>(model.fluid));
  fluid_step.push_back(std::make_unique<FluidPressureSolve>(model));
  fluid_step.push_back(std::make_unique<FluidCorrect>(model.fluid));
  grain_substep.push_back(std::make_unique<SolidFluidSampling>(model));
  grain_substep.push_back(std::make_unique<SolidKickDrift>(model));
  grain_substep.push_back(std::make_unique<WallMotion>());
  grain_substep.push_back(std::make_unique<SolidNeighbours>());
  grain_substep.push_back(std::make_unique<SolidContactForces>());
  grain_substep.push_back(std::make_unique<SolidDrag>(model));
  grain_substep.push_back(std::make_unique<SolidForceSum>());
  grain_substep.push_back(std::make_unique<SolidKick>(model));
  for (const auto& fluid : fluid_step)
    for (const auto& grain : grain_substep) {
      CAPTURE(fluid->name());
      CAPTURE(grain->name());
      CHECK_FALSE(conflict(*fluid, *grain));
    }
}

TEST_CASE("the component list names every component once and the World stores each") {
  CHECK(kComponentNames.size() == kComponentCount);
  CHECK(component_name(component_id<GrainState>) == "grain_state");
  CHECK(component_name(component_id<FluidSample>) == "fluid_sample");
  CHECK(component_ids<Solids>().size() == 9);
  CHECK(component_ids<FluidParticles, Walls>().size() == 6);
  const std::set<std::string_view> distinct(kComponentNames.begin(), kComponentNames.end());
  CHECK(distinct.size() == kComponentCount);

  // A dry scene: the grains' roles are there (found inside Solids), the particles' are not.
  World world = initial_world(test::small_model());
  CHECK(world.has(component_id<GrainState>));
  CHECK(world.has(component_id<GrainVoidage>));
  CHECK(world.has(component_id<StepStatus>));
  CHECK_FALSE(world.has(component_id<ParticleState>));
  CHECK_FALSE(world.has(component_id<FluidNeighbours>));
  CHECK(world.find<GrainDrag>() == static_cast<GrainDrag*>(&*world.solids));
  CHECK(world.find<ParticlePressure>() == nullptr);
}

TEST_CASE("checkpoints hold the persistent parts in the order of format 4, the mean-flow column after them") {
  std::vector<std::string_view> persistent;
  World world;
  World::for_each_part(world, [&](auto& part) {
    using Stored = typename detail::unwrap_optional<std::decay_t<decltype(part)>>::type;
    if (Stored::kPersistent) persistent.push_back(Stored::kName);
  });
  CHECK(persistent == std::vector<std::string_view>{"solids", "walls", "tank_motion", "contacts", "fluid",
                                                     "fluid_summary", "mean_flow_column"});
}

TEST_CASE("each role's table lists every field of its struct, and the group's written order names each once") {
  check_tables_cover_structs(Solids::RoleList{});
  check_tables_cover_structs(FluidParticles::RoleList{});
  for (const auto& [names, order] :
       {std::pair{group_field_names<Solids>(), std::vector<std::string>(Solids::kFieldOrder.begin(),
                                                                        Solids::kFieldOrder.end())},
        std::pair{group_field_names<FluidParticles>(),
                  std::vector<std::string>(FluidParticles::kFieldOrder.begin(), FluidParticles::kFieldOrder.end())}}) {
    CHECK(std::set<std::string>(names.begin(), names.end()).size() == names.size());
    CHECK(std::is_permutation(names.begin(), names.end(), order.begin(), order.end()));
  }
  // The written order is the one table's order before the split (checkpoint format 4, VTK frames), then the fields
  // added since, each from the format that first stored it.
  Solids solids;
  std::vector<std::string> written;
  for_each_field_in_order(solids, [&](const FieldInfo& info, auto&) { written.emplace_back(info.name); });
  CHECK(written == std::vector<std::string>{"id", "position", "velocity", "angular_velocity", "radius", "mass",
                                            "moment_of_inertia", "force", "torque", "contact_force",
                                            "contact_torque", "drag_force", "drag_impulse", "pressure_force",
                                            "fluid_velocity", "voidage", "fluid_weight", "material", "size_class",
                                            "undisturbed_velocity", "fluid_acceleration", "added_mass_force",
                                            "history_force", "lubrication_force", "history_relative_velocity",
                                            "history_mode_0", "history_mode_1", "history_mode_2", "history_mode_3",
                                            "history_mode_4", "history_mode_5", "history_mode_6",
                                            "history_mode_7", "self_induced_fast",
                                            "self_induced_middle", "self_induced_slow", "viscous_force", "fixed", "fluctuation_state",
                                            "self_induced_wall_x", "self_induced_wall_y", "self_induced_wall_z",
                                            "ergun_resistance", "ergun_inertial_resistance", "history_mass"});
}

TEST_CASE("a new entity's fields start at their table defaults") {
  Solids solids;
  solids.add(Vec3(1, 2, 3), Vec3(4, 5, 6), 0.01, 1000.0, 2, 1);
  CHECK(solids.voidage[0] == 1.0);  // dry until the voidage is computed
  CHECK(solids.fluid_weight[0] == 0.0);
  CHECK(solids.angular_velocity[0] == Vec3::Zero());
  CHECK(solids.drag_impulse[0] == Vec3::Zero());
  CHECK(solids.force[0] == Vec3::Zero());
  CHECK(solids.material[0] == 2);
  FluidParticles particles;
  particles.add(Vec3(1, 0, 0), Vec3(0, 1, 0), FluidKind::kWall);
  CHECK(particles.rest_position[0] == Vec3(1, 0, 0));
  CHECK(particles.predicted_position[0] == Vec3(1, 0, 0));
  CHECK(particles.pressure[0] == 0.0);
  CHECK(particles.drag_reaction[0] == Vec3::Zero());
  CHECK(particles.free_surface[0] == 0);
  Walls walls;
  walls.add("floor", Vec3::Zero(), Vec3(0, 0, 2), Vec3(1, 0, 0), Vec3(0, 1, 0), true, 0);
  CHECK(walls.velocity[0] == Vec3::Zero());
  CHECK(walls.normal[0] == Vec3(0, 0, 1));
}

TEST_CASE("whole_group gives back the group of its roles and resizes, permutes and checks every role") {
  World world = initial_world(test::small_model());
  Solids& solids = whole_group<Solids>(*world.find<GrainState>(), *world.find<GrainProperties>(),
                                       *world.find<GrainTotalForce>(), *world.find<GrainContactForce>(),
                                       *world.find<GrainDrag>(), *world.find<GrainSampledFluid>(),
                                       *world.find<GrainVoidage>(), *world.find<GrainAddedMass>(),
                                       *world.find<GrainLubrication>());
  CHECK(&solids == &*world.solids);
  REQUIRE(solids.size() >= 2);
  solids.drag_impulse[0] = Vec3(7, 0, 0);
  const EntityId first = solids.id[0];
  std::vector<std::size_t> order(solids.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = order.size() - 1 - k;
  permute_fields(solids, order);
  CHECK(solids.id.back() == first);
  CHECK(solids.drag_impulse.back() == Vec3(7, 0, 0));
  solids.fluid_weight.pop_back();
  CHECK_THROWS_WITH(check_field_sizes(solids, "solids"),
                    doctest::Contains("solids.fluid_weight holds"));

  Solids other;
  other.add(Vec3::Zero(), Vec3::Zero(), 0.01, 1000.0, 0, 0);
  CHECK_THROWS_AS(whole_group<Solids>(static_cast<GrainState&>(other), static_cast<GrainProperties&>(solids),
                                      static_cast<GrainTotalForce&>(solids), static_cast<GrainContactForce&>(solids),
                                      static_cast<GrainDrag&>(solids), static_cast<GrainSampledFluid&>(solids),
                                      static_cast<GrainVoidage&>(solids), static_cast<GrainAddedMass&>(solids),
                                      static_cast<GrainLubrication&>(solids)),
                  std::logic_error);
}

TEST_CASE("only the fluid's and the grains' tables leave fields out of checkpoints (FieldInfo::checkpointed)") {
  // FluidParticles::serialize and Solids::serialize leave out a field marked not checkpointed; Walls::serialize writes
  // every field, so none may be marked there. The grains' marked fields are those solid_drag_law sets at every step's
  // start, before any reader.
  const auto unmarked_names = [](auto& table) {
    std::vector<std::string> names;
    std::remove_reference_t<decltype(table)>::for_each_field(table, [&](const FieldInfo& info, auto&) {
      if (!info.checkpointed) names.emplace_back(info.name);
    });
    return names;
  };
  Solids solids;
  Walls walls;
  FluidParticles fluid;
  CHECK(unmarked_names(solids) == std::vector<std::string>{"ergun_resistance", "ergun_inertial_resistance"});
  CHECK(unmarked_names(walls).empty());
  CHECK(unmarked_names(fluid) == std::vector<std::string>{"applied_pressure_gradient"});
}

TEST_CASE("checkpoints of the corpus read and write back: the current format byte for byte, older ones as the same data") {
  const std::filesystem::path corpus = RIFFLE_SOURCE_DIR "/tests/fuzz/corpus/checkpoint";
  auto contents = [](const std::filesystem::path& path) {
    std::ifstream file(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  };
  auto version_of = [](const std::string& bytes) {
    std::uint32_t version = 0;
    std::memcpy(&version, bytes.data() + 8, sizeof version);
    return version;
  };
  std::size_t current = 0, legacy = 0, legacy_fluid = 0, legacy_grains = 0, legacy_fluid_fields = 0, legacy_contacts = 0;
  for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
    CAPTURE(entry.path().string());
    CheckpointData data;
    try {
      data = read_checkpoint(entry.path().string());
    } catch (const CheckpointError&) {
      continue;  // a fuzz find damaged below the format (refused before any field is read)
    }
    const std::string bytes = contents(entry.path());
    const std::string written = encode_checkpoint(data);
    CHECK(version_of(written) == kCheckpointVersion);
    if (version_of(bytes) == kCheckpointVersion) {
      CHECK(written == bytes);
      ++current;
      continue;
    }
    // An older file (the compatibility fixtures v4_*.ckpt and v5_*.ckpt, and fuzz finds of their time) is the same
    // data: written back, it is the current format, which reads back to the same bytes again. Its payload is the old
    // one with the grains' fields added since its format (each a cereal vector: an 8-byte count and the values, at
    // their defaults) inserted after the old ones, and, for format 4, without the 8 bytes of FluidSummary's last_dt.
    const std::uint32_t old_version = version_of(bytes);
    REQUIRE(old_version >= kOldestCheckpointVersionRead);
    CHECK(encode_checkpoint(decode_checkpoint(written, "rewritten")) == written);
    std::string old_payload = bytes.substr(32), new_payload = written.substr(32);
    // Formats up to 12 held each grain pair's force and two torques after its spring: three vectors of 3-vectors,
    // erased from the old payload after the pairs' seconds and springs (found by their bytes).
    if (data.world.contacts && data.world.contacts->valid && old_version <= Contacts::kLastFormatWithPairForces) {
      const Contacts& contacts = *data.world.contacts;
      std::ostringstream stream;
      {
        cereal::BinaryOutputArchive archive(stream);
        archive(contacts.pair_second, contacts.pair_spring);
      }
      const std::string before = stream.str();
      const std::size_t at = old_payload.find(before);
      REQUIRE(at != std::string::npos);
      const std::size_t dropped = 3 * (8 + 3 * sizeof(double) * contacts.pair_count());
      REQUIRE(at + before.size() + dropped <= old_payload.size());
      old_payload.erase(at + before.size(), dropped);
      ++legacy_contacts;
    }
    // Formats before 15 have no rolling springs: the new payload holds a vector of zero 3-vectors, one per pair,
    // after the pairs' springs, and one per wall pair after the wall pairs' springs (found by the bytes before them).
    if (data.world.contacts && data.world.contacts->valid && old_version < Contacts::kFirstFormatWithRollingSprings) {
      const Contacts& contacts = *data.world.contacts;
      for (const bool walls : {false, true}) {
        std::ostringstream stream;
        {
          cereal::BinaryOutputArchive archive(stream);
          if (walls)
            archive(contacts.wall_pair_offsets, contacts.wall_pair_wall, contacts.wall_pair_spring);
          else
            archive(contacts.pair_offsets, contacts.pair_second, contacts.pair_spring);
        }
        const std::string before = stream.str();
        const std::size_t at = new_payload.find(before);
        REQUIRE(at != std::string::npos);
        const std::vector<Vec3>& rolling = walls ? contacts.wall_pair_rolling_spring : contacts.pair_rolling_spring;
        CHECK(rolling.size() == (walls ? contacts.wall_pair_count() : contacts.pair_count()));
        for (const Vec3& value : rolling) CHECK(value == Vec3::Zero());
        const std::size_t added = 8 + 3 * sizeof(double) * rolling.size();
        REQUIRE(at + before.size() + added <= new_payload.size());
        new_payload.erase(at + before.size(), added);
      }
    }
    // The fields a table gained since the old format, written at its end (the grains' table comes before the fluid's
    // in the payload, World::kParts): each at its default; erased from the new payload where it first differs.
    const auto erase_added = [&](const auto& table) {
      std::size_t added = 0;
      for_each_field_in_order(table, [&](const FieldInfo& info, const auto& field) {
        using Value = typename std::decay_t<decltype(field)>::value_type;
        if (!info.checkpointed || info.since_format <= old_version) return;
        for (const Value& value : field) CHECK(value == field_default<Value>(info));
        added += 8 + field.size() * sizeof(Value);
      });
      if (added == 0) return false;
      const auto slot = static_cast<std::size_t>(
          std::mismatch(old_payload.begin(), old_payload.end(), new_payload.begin()).first - old_payload.begin());
      REQUIRE(slot + added <= new_payload.size());
      new_payload.erase(slot, added);
      return true;
    };
    // Format 9's mean-flow column, absent in every older file: cereal's one-byte flag of an empty optional, between
    // the world's parts and the output state (a vector of frame times, the checkpoints due, a vector of kept steps).
    if (old_version < kFirstCheckpointVersionWithMeanFlow) {
      const OutputState& output = data.output;
      const std::size_t output_bytes = 8 + 8 * output.frame_times.size() + 8 + 8 + 8 * output.kept_steps.size();
      const std::size_t flag = new_payload.size() - output_bytes - 1;
      CHECK(new_payload[flag] == 1);
      new_payload.erase(flag, 1);
    }
    if (data.world.solids) legacy_grains += erase_added(*data.world.solids) ? 1 : 0;
    if (data.world.fluid) legacy_fluid_fields += erase_added(*data.world.fluid) ? 1 : 0;
    if (data.world.fluid_summary && old_version == 4) {
      // FluidSummary's last_dt: 8 bytes the old payload holds after solver_converged.
      const auto slot = static_cast<std::size_t>(
          std::mismatch(new_payload.begin(), new_payload.end(), old_payload.begin()).first - new_payload.begin());
      REQUIRE(slot + 8 <= old_payload.size());
      old_payload.erase(slot, 8);
      ++legacy_fluid;
    }
    if (data.world.fluid_summary && old_version < FluidSummary::kFirstFormatWithRemovalReasons) {
      // Format 12's removals by reason and the controller's integral: three 8-byte members after courant, at their
      // defaults (zero); erased from the new payload where it first differs.
      CHECK(data.world.fluid_summary->removed_left_domain == 0);
      CHECK(data.world.fluid_summary->removed_lone_droplet == 0);
      CHECK(data.world.fluid_summary->body_force_integral == 0.0);
      const auto slot = static_cast<std::size_t>(
          std::mismatch(old_payload.begin(), old_payload.end(), new_payload.begin()).first - old_payload.begin());
      REQUIRE(slot + 24 <= new_payload.size());
      new_payload.erase(slot, 24);
    }
    CHECK(old_payload == new_payload);
    ++legacy;
  }
  CHECK(current >= 5);  // dry_contacts, dry_contacts_early, tiny_coupled, tiny_fluid, tiny_fluid_early at least
  CHECK(legacy >= 6);   // their v4_ fixtures and v5_tiny_coupled
  CHECK(legacy_fluid >= 3);
  CHECK(legacy_grains >= 3);
  CHECK(legacy_fluid_fields >= 3);  // the fluid's viscous_acceleration (format 7) in the v4_, v5_ and v6_ fluid files
  CHECK(legacy_contacts >= 8);      // the v4_ to v12_ files with contacts
}
