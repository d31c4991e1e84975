// Forged checkpoints: a checksum anyone can recompute proves nothing, so every length, index, count, enum and real
// of a checkpoint is checked before it is used. Each case forges one defect class with encode_checkpoint (the
// checksum is then valid) and expects a refusal that names the file and the field.
#include <doctest/doctest.h>
#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <new>
#include <numeric>

#include "engine/output/checkpoint.hpp"
#include "engine/scene/scene.hpp"
#include "engine/run/simulation.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

// The largest single allocation while `g_track_allocations` is set: the decoder must not allocate what a forged
// length asks for before it knows the bytes are there.
namespace {
std::atomic<bool> g_track_allocations{false};
std::atomic<std::size_t> g_largest_allocation{0};
}  // namespace

// ThreadSanitizer's runtime defines operator new and delete itself (not weakly), so its build keeps the library's.
#if defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define RIFFLE_NO_ALLOCATION_TRACKING 1
#endif
#endif
#if defined(__SANITIZE_THREAD__)
#define RIFFLE_NO_ALLOCATION_TRACKING 1
#endif

#ifndef RIFFLE_NO_ALLOCATION_TRACKING
void* operator new(std::size_t size) {
  if (g_track_allocations.load(std::memory_order_relaxed)) {
    std::size_t largest = g_largest_allocation.load(std::memory_order_relaxed);
    while (size > largest && !g_largest_allocation.compare_exchange_weak(largest, size)) {
    }
  }
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
// GCC cannot see that the operator new above takes its memory from malloc.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#endif

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A closed box of touching grains with contacts, after a few steps: pairs, wall pairs and springs exist.
std::string contact_scene_text() {
  return SceneBuilder().run({.name = "contacts", .end_time = 0.05, .dt = 1.0e-3})
      .material("grain", {.density = 2500.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
      .material("glass", {.density = 2500.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
      .contact({.law = "hertz_mindlin", .restitution = 0.5, .friction = 0.4})
      .tank({.size = {0.03, 0.03, 0.03}, .wall_material = "glass"})
      .block({.min = {0.0025, 0.0025, 0.0025}, .max = {0.0275, 0.0275, 0.0125}, .spacing = 0.005, .radius = 0.0025,
              .material = "grain"})
      .set("size_class", 1)
      .output().set("vtk_interval", 0.001).set("checkpoint_interval", 0.002).set("checkpoint_keep", 2).toml();
}

CheckpointData stepped(Model model, int steps) {
  auto simulation = Simulation::from_model(std::move(model));
  for (int step = 0; step < steps; ++step) simulation->step();
  CheckpointData data = simulation->checkpoint_data();
  return data;
}

const CheckpointData& contact_checkpoint() {
  static const CheckpointData data = [] {
    CheckpointData result = stepped(parse_scene(contact_scene_text(), "contacts.toml"), 3);
    result.output.frame_times = {0.0, 0.001, 0.002, 0.003};
    result.output.checkpoints_due = 1;
    result.output.kept_steps = {2};
    return result;
  }();
  return data;
}

const CheckpointData& fluid_checkpoint() {
  static const CheckpointData data = stepped(test::fluid_model(), 2);
  return data;
}

/// Writes `base` changed by `forge` (the checksum is valid) and resumes it; the refusal's message, or "accepted".
std::string resume(const CheckpointData& base, const std::function<void(CheckpointData&)>& forge) {
  CheckpointData data = base;
  forge(data);
  const auto directory = test::scratch_dir("checkpoint_forged");
  const std::string path = (directory / "forged.ckpt").string();
  write_checkpoint(path, data);
  try {
    Simulation::from_checkpoint(path);
  } catch (const CheckpointError& error) {
    return error.what();
  }
  return "accepted";
}

/// The message must name the file, then hold `expected`.
void refused(const std::string& message, const std::string& expected) {
  INFO(message);
  CHECK(message.find("forged.ckpt: ") != std::string::npos);
  CHECK(message.find(expected) != std::string::npos);
}

/// The payload of an encoded checkpoint with its first length prefix (the scene file name's) set to `length`, and
/// the header's checksum recomputed.
std::string with_first_length(const CheckpointData& data, std::uint64_t length) {
  std::string bytes = encode_checkpoint(data);
  constexpr std::size_t kHeader = 32;
  std::memcpy(bytes.data() + kHeader, &length, sizeof length);
  const std::uint64_t checksum = fnv1a64(bytes.substr(kHeader));
  std::memcpy(bytes.data() + 24, &checksum, sizeof checksum);
  return bytes;
}

}  // namespace

TEST_CASE("valid checkpoints with contacts and with a fluid still resume") {
  const CheckpointData& contacts = contact_checkpoint();
  REQUIRE(contacts.world.contacts.has_value());
  CHECK(contacts.world.contacts->pair_count() > 0);
  CHECK(contacts.world.contacts->wall_pair_count() > 0);
  CHECK(resume(contacts, [](CheckpointData&) {}) == "accepted");
  CHECK(resume(fluid_checkpoint(), [](CheckpointData&) {}) == "accepted");
}

TEST_CASE("a forged length prefix is refused before it is allocated") {
  const CheckpointData& data = contact_checkpoint();
  const std::string bytes = encode_checkpoint(data);
  for (std::uint64_t length : {std::uint64_t{1} << 40, std::uint64_t{1000000000}, std::uint64_t(bytes.size())}) {
    const std::string forged = with_first_length(data, length);
    g_largest_allocation = 0;
    g_track_allocations = true;
    std::string message;
    try {
      decode_checkpoint(forged, "forged.ckpt");
    } catch (const CheckpointError& error) {
      message = error.what();
    }
    g_track_allocations = false;
    refused(message, "cannot fit in the");
    // Nothing larger than the file itself (the payload copy) was asked for.
#ifndef RIFFLE_NO_ALLOCATION_TRACKING
    CHECK(g_largest_allocation.load() <= bytes.size());
#endif
  }
  SUBCASE("bytes left over after the last field") {
    std::string longer = encode_checkpoint(data);
    const std::string payload = longer.substr(32) + std::string(8, '\0');
    const std::uint64_t size = payload.size(), checksum = fnv1a64(payload);
    longer = longer.substr(0, 32) + payload;
    std::memcpy(longer.data() + 16, &size, sizeof size);
    std::memcpy(longer.data() + 24, &checksum, sizeof checksum);
    CHECK_THROWS_WITH_AS(decode_checkpoint(longer, "x.ckpt"), doctest::Contains("8 bytes left over"), CheckpointError);
  }
}

TEST_CASE("a checkpoint must be a regular file: directories, devices and FIFOs are refused without reading") {
  const auto directory = test::scratch_dir("checkpoint_special");
  SUBCASE("a directory") {
    CHECK_THROWS_WITH_AS(read_checkpoint(directory.string()), doctest::Contains("not a regular file (a directory)"),
                         CheckpointError);
  }
  SUBCASE("/dev/zero") {
    CHECK_THROWS_WITH_AS(read_checkpoint("/dev/zero"), doctest::Contains("/dev/zero: not a regular file"),
                         CheckpointError);
  }
  SUBCASE("a FIFO nobody writes to") {
    const std::string fifo = (directory / "pipe.ckpt").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    CHECK_THROWS_WITH_AS(read_checkpoint(fifo), doctest::Contains("not a regular file (a FIFO)"), CheckpointError);
  }
}

TEST_CASE("contact lists whose indices do not fit the grains and walls are refused") {
  const CheckpointData& data = contact_checkpoint();
  const auto grains = static_cast<std::uint32_t>(data.world.solids->size());
  SUBCASE("pair_second beyond the grains") {
    refused(resume(data, [&](CheckpointData& d) { d.world.contacts->pair_second[0] = grains + 5; }),
            "contacts.pair_second[0] = " + std::to_string(grains + 5));
  }
  SUBCASE("pair_second not above its first grain") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts->pair_second[0] = 0; }),
            "contacts.pair_second[0] = 0: must be above its first grain");
  }
  SUBCASE("empty pair offsets") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts->pair_offsets.clear(); }),
            "contacts.pair_offsets: holds 0 entries");
  }
  SUBCASE("short pair offsets") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts->pair_offsets.pop_back(); }),
            "contacts.pair_offsets: holds");
  }
  SUBCASE("offsets that decrease") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts->pair_offsets[1] = 1000000; }),
            "contacts.pair_offsets[2]");
  }
  SUBCASE("a pair whose grains lay beyond the list's reach at its build") {
    // The contact pass writes both grains of a pair from the first grain's slab: a pair three slabs apart would let
    // two tasks write one grain.
    const auto& contacts = *data.world.contacts;
    const std::uint32_t j = contacts.pair_second[0];
    REQUIRE(contacts.build_position[0].x() < 0.005);
    refused(resume(data, [&](CheckpointData& d) { d.world.contacts->build_position[j].x() = 0.0275; }),
            "lies beyond the list's reach of its first grain 0");
  }
  SUBCASE("a reverse index that points elsewhere") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts->second_pairs[0] = 4000000000u; }),
            "contacts.second_pairs[0] = 4000000000");
  }
  SUBCASE("a wall index beyond the walls") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts->wall_pair_wall[0] = 6; }),
            "contacts.wall_pair_wall[0] = 6: must be below the wall count 6");
  }
  SUBCASE("a pair array shorter than the pairs") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts->pair_spring.pop_back(); }),
            "contacts.pair_spring: holds");
  }
  SUBCASE("a skin that is not the scene's") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts->skin = kNaN; }), "contacts.skin = nan");
  }
}

TEST_CASE("material, size class, wall and id indices outside the scene are refused") {
  const CheckpointData& data = contact_checkpoint();
  SUBCASE("material 2^31-1") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->material[3] = 2147483647; }),
            "solids.material[3] = 2147483647: must be a material index below 2");
  }
  SUBCASE("material 99 of 2") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->material[0] = 99; }), "solids.material[0] = 99");
  }
  SUBCASE("another valid material than the scene gave the grain") {
    const std::int32_t other = 1 - data.world.solids->material[0];
    refused(resume(data, [&](CheckpointData& d) { d.world.solids->material[0] = other; }),
            "solids.material[0] = " + std::to_string(other) + ": differs from the scene's grain id");
  }
  SUBCASE("a size class out of range") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->size_class[2] = -4; }),
            "solids.size_class[2] = -4: must be in 0..1000");
  }
  SUBCASE("a Langevin state far beyond a unit variance's reach") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->fluctuation_state[2] = Vec3(0.0, 1e300, 0.0); }),
            "solids.fluctuation_state[2] = ");
    refused(resume(data, [](CheckpointData& d) { d.world.solids->fluctuation_state[2] = Vec3(0.0, 0.0, -101.0); }),
            "each component must lie within +-100");
  }
  SUBCASE("a fixed flag other than 0 or 1") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->fixed[1] = 2; }),
            "solids.fixed[1] = 2: must be 0 or 1");
  }
  SUBCASE("a grain fixed that its scene left free") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->fixed[0] = 1; }),
            "solids.fixed[0] = 1: differs from the scene's grain id");
  }
  SUBCASE("every wall removed") {
    refused(resume(data, [](CheckpointData& d) { d.world.walls = Walls{}; }), "walls: holds 0 entries, expected 6");
  }
  SUBCASE("a wall moved off the tank") {
    refused(resume(data, [](CheckpointData& d) { d.world.walls->normal[1] = Vec3(0.0, 0.0, 1.0); }),
            "walls[1] (\"x_max\"): differs from the scene's tank wall");
  }
  SUBCASE("a duplicate grain id") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->id[1] = d.world.solids->id[0]; }),
            "solids.id[1] = " + std::to_string(data.world.solids->id[0]) + ": is used twice");
  }
  SUBCASE("a grain id at next_id") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->id[0] = d.world.solids->next_id; }),
            "must be below next_id");
  }
  SUBCASE("a grain more or less than the scene") {
    refused(resume(data, [](CheckpointData& d) { resize_fields(*d.world.solids, d.world.solids->size() - 1); }),
            "solids.next_id");
  }
  SUBCASE("a component the scene does not have") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts.reset(); }),
            "contacts: absent, but its scene needs it");
  }
}

TEST_CASE("fluid kinds, slots and counts that do not match the scene are refused") {
  const CheckpointData& data = fluid_checkpoint();
  const std::size_t fluid_count = data.world.fluid_summary->fluid_count;
  REQUIRE(fluid_count > 0);
  SUBCASE("kind 7") {
    refused(resume(data, [](CheckpointData& d) { d.world.fluid->kind[0] = 7; }), "fluid.kind[0] = 7: must be 0");
  }
  SUBCASE("a wall particle among the fluid slots") {
    refused(resume(data, [](CheckpointData& d) { d.world.fluid->kind[1] = 1; }), "fluid.kind[1] = 1: must be 0");
  }
  SUBCASE("a wall particle swapped into the fluid slots") {
    refused(resume(data,
                   [&](CheckpointData& d) {
                     FluidParticles& fluid = *d.world.fluid;
                     std::vector<std::size_t> order(fluid.size());
                     std::iota(order.begin(), order.end(), std::size_t{0});
                     std::swap(order[0], order[fluid_count]);  // slot 0 takes the first wall particle
                     permute_fields(fluid, order);
                   }),
            "fluid particles (0) must hold slots [0, " + std::to_string(fluid_count) + ")");
  }
  SUBCASE("fluid_count 1e9") {
    refused(resume(data, [](CheckpointData& d) { d.world.fluid_summary->fluid_count = 1000000000; }),
            "fluid_summary.fluid_count = 1000000000: must equal the fluid particles, " + std::to_string(fluid_count));
  }
  SUBCASE("a summary without its fluid") {
    refused(resume(data, [](CheckpointData& d) { d.world.fluid_summary.reset(); }), "fluid_summary: absent");
  }
  SUBCASE("a free-surface flag of 3") {
    refused(resume(data, [](CheckpointData& d) { d.world.fluid->free_surface[2] = 3; }),
            "fluid.free_surface[2] = 3: must be 0 or 1");
  }
  // fluid_escape (escape = "remove", the default) takes escaped fluid particles out of the table for good.
  const auto remove_fluid = [](std::size_t count, const std::string& fluid_keys) {
    return [count, fluid_keys](CheckpointData& d) {
      FluidParticles& fluid = *d.world.fluid;
      std::vector<std::size_t> kept;
      for (std::size_t i = count; i < fluid.size(); ++i) kept.push_back(i);  // the first `count` fluid slots go
      keep_fields(fluid, kept);
      d.world.fluid_summary->fluid_count -= count;
      d.world.fluid_summary->removed_lone_droplet += count;  // each removal has its reason
      const std::string spacing = "spacing = 0.005\n";
      d.scene_text.replace(d.scene_text.find(spacing), spacing.size(), spacing + fluid_keys + "\n");
    };
  };
  SUBCASE("removed fluid particles within fluid.escape_fraction_limit are accepted") {
    CHECK(resume(data, remove_fluid(3, "escape_fraction_limit = 0.05")) == "accepted");
  }
  SUBCASE("removals whose reasons do not add up to the particles removed are refused") {
    refused(resume(data,
                   [&](CheckpointData& d) {
                     remove_fluid(3, "escape_fraction_limit = 0.05")(d);
                     d.world.fluid_summary->removed_lone_droplet = 1;
                     d.world.fluid_summary->removed_left_domain = 1;
                   }),
            "fluid_summary.removed_left_domain + removed_lone_droplet = 1 + 1: must equal the fluid particles "
            "removed, 3");
  }
  SUBCASE("more removed than fluid.escape_fraction_limit is refused") {
    refused(resume(data, remove_fluid(4, "escape_fraction_limit = 0.05")),
            "fluid: holds " + std::to_string(fluid_count - 4) + " fluid particles of the scene's " +
                std::to_string(fluid_count) + ": more were removed than fluid.escape_fraction_limit = 0.05");
  }
  SUBCASE("a removed fluid particle with escape = \"stop\" is refused") {
    refused(resume(data, remove_fluid(1, "escape = \"stop\"")), "fluid: holds");
  }
  SUBCASE("a removed wall particle is refused") {
    refused(resume(data,
                   [&](CheckpointData& d) {
                     FluidParticles& fluid = *d.world.fluid;
                     std::vector<std::size_t> kept;
                     for (std::size_t i = 0; i + 1 < fluid.size(); ++i) kept.push_back(i);
                     keep_fields(fluid, kept);
                   }),
            "must be 0, the kind of particle id");
  }
  SUBCASE("a fluid particle far outside the tank") {
    refused(resume(data, [](CheckpointData& d) { d.world.fluid->position[0] = Vec3(1e9, 0.0, 0.0); }),
            "fluid.position[0] = (1000000000, 0, 0): is outside the domain");
  }
}

TEST_CASE("non-finite and non-positive values and an inconsistent time are refused") {
  const CheckpointData& data = contact_checkpoint();
  SUBCASE("radius -1") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->radius[12] = -1.0; }),
            "solids.radius[12] = -1: must be positive");
  }
  SUBCASE("radius 0") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->radius[0] = 0.0; }),
            "solids.radius[0] = 0: must be positive");
  }
  SUBCASE("radius 5e-324 (positive, but not the scene's)") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->radius[0] = 5e-324; }),
            "differs from the scene's grain");
  }
  SUBCASE("a NaN velocity") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->velocity[4][1] = kNaN; }),
            "solids.velocity[4] = (");
  }
  SUBCASE("an infinite tangential spring") {
    refused(resume(data, [](CheckpointData& d) { d.world.contacts->pair_spring[0][0] = kInf; }),
            "contacts.pair_spring[0] = (inf");
  }
  SUBCASE("voidage 0") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->voidage[3] = 0.0; }),
            "solids.voidage[3] = 0: must be in (0, 1]");
  }
  SUBCASE("mass 0") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->mass[1] = 0.0; }),
            "solids.mass[1] = 0: must be positive");
  }
  SUBCASE("time -inf") {
    refused(resume(data, [](CheckpointData& d) { d.world.time = -kInf; }), "time = -inf: must be finite");
  }
  SUBCASE("time NaN") {
    refused(resume(data, [](CheckpointData& d) { d.world.time = kNaN; }), "time = nan: must be finite");
  }
  SUBCASE("a time the steps cannot have reached") {
    refused(resume(data, [](CheckpointData& d) { d.world.time = 1e6; }), "time = 1000000: does not match step = 3");
  }
  SUBCASE("a step count far beyond the time") {
    refused(resume(data, [](CheckpointData& d) { d.world.step = ~std::uint64_t{0}; }), "does not match step");
  }
  SUBCASE("a grain outside the domain") {
    refused(resume(data, [](CheckpointData& d) { d.world.solids->position[0] = Vec3(0.01, 0.01, -1e300); }),
            "solids.position[0] = (0.01, 0.01, -1.0000000000000001e+300): is outside the domain");
  }
  SUBCASE("a NaN tank displacement") {
    refused(resume(data, [](CheckpointData& d) { d.world.tank_motion->displacement[0] = kNaN; }),
            "tank_motion.displacement = (nan");
  }
  SUBCASE("frame times out of order") {
    refused(resume(data, [](CheckpointData& d) { d.output.frame_times[2] = 0.0; }),
            "output.frame_times[2] = 0: must be after the frame before it");
  }
  SUBCASE("a NaN frame time") {
    refused(resume(data, [](CheckpointData& d) { d.output.frame_times[1] = kNaN; }), "output.frame_times[1] = nan");
  }
  SUBCASE("kept checkpoints from the future") {
    refused(resume(data, [](CheckpointData& d) { d.output.kept_steps = {1000}; }),
            "output.kept_steps[0] = 1000: must be ascending and not after step 3");
  }
  SUBCASE("more interval checkpoints than the time allows") {
    refused(resume(data, [](CheckpointData& d) { d.output.checkpoints_due = ~std::uint64_t{0}; }),
            "output.checkpoints_due = 18446744073709551615");
  }
}

TEST_CASE("a [solids] initial_state checkpoint is validated like a resumed one") {
  const auto directory = test::scratch_dir("checkpoint_initial_state");
  // The contact scene without its grains, starting from the grains of a forged checkpoint of itself.
  std::string host = contact_scene_text();
  host = host.substr(0, host.find("[[solids.blocks]]")) + "initial_state = \"bed.ckpt\"\n";
  auto start_from = [&](const std::function<void(Solids&)>& forge) {
    CheckpointData data = contact_checkpoint();
    forge(*data.world.solids);
    write_checkpoint((directory / "bed.ckpt").string(), data);
    try {
      parse_scene(host, (directory / "host.toml").string());
    } catch (const std::exception& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  CHECK(start_from([](Solids&) {}) == "accepted");
  const std::string negative = start_from([](Solids& grains) { grains.radius[12] = -1.0; });
  CHECK_MESSAGE(negative.find("bed.ckpt: solids.radius[12] = -1: must be positive") != std::string::npos, negative);
  const std::string infinite = start_from([](Solids& grains) { grains.position[0][2] = kInf; });
  CHECK_MESSAGE(infinite.find("bed.ckpt: solids.position[0] = (") != std::string::npos, infinite);
  const std::string duplicate = start_from([](Solids& grains) { grains.id[6] = grains.id[5]; });
  CHECK_MESSAGE(duplicate.find("bed.ckpt: solids.id[6]") != std::string::npos, duplicate);
  CHECK_MESSAGE(duplicate.find("is used twice") != std::string::npos, duplicate);
  // A radius so small that this scene's mass or moment of inertia underflows to zero.
  const std::string tiny = start_from([](Solids& grains) { grains.radius[0] = 1e-80; });
  CHECK_MESSAGE(tiny.find("bed.ckpt: solids.moment_of_inertia[0] = 0: must be positive") != std::string::npos, tiny);
}

TEST_CASE("a periodic box: a pair with a ghost second is accepted, one beyond the ghosts refused") {
  // The contact scene's block fills the 3 cm tank wall to wall, so with x and y periodic the grains along the faces
  // touch their neighbours across the seam: the list holds pairs whose second is a ghost (slot >= grains). The
  // resumed run rebuilds the halo from the list's build positions; validation does the same to judge the slots.
  std::string text = contact_scene_text();
  text.replace(text.find("wall_material = \"glass\"\n"), 0, "periodic = [\"x\", \"y\"]\n");
  const CheckpointData data = stepped(parse_scene(text, "periodic_contacts.toml"), 3);
  const auto grains = static_cast<std::uint32_t>(data.world.solids->size());
  const auto& second = data.world.contacts->pair_second;
  const auto ghost = std::find_if(second.begin(), second.end(), [&](std::uint32_t j) { return j >= grains; });
  REQUIRE(ghost != second.end());
  CHECK(resume(data, [](CheckpointData&) {}) == "accepted");
  const auto k = static_cast<std::size_t>(ghost - second.begin());
  refused(resume(data, [&](CheckpointData& d) { d.world.contacts->pair_second[k] = 4000000u; }),
          "contacts.pair_second[" + std::to_string(k) + "] = 4000000: must be above its first grain");
  refused(resume(data, [&](CheckpointData& d) { d.world.contacts->pair_second[k] = 4000000u; }), "(ghosts included)");
  // A grain that crossed a periodic face is wrapped only at the next rebuild: a centre past an x or y face, beyond
  // the domain's margin even, is a state a run writes; a whole period out it is not (a blow-up's), nor past the
  // floor (z is never periodic).
  CHECK(resume(data, [](CheckpointData& d) { d.world.solids->position[0].x() = 0.03 + 0.02; }) == "accepted");
  CHECK(resume(data, [](CheckpointData& d) { d.world.solids->position[0].y() = -0.02; }) == "accepted");
  refused(resume(data, [](CheckpointData& d) { d.world.solids->position[0].x() = 0.03 + 0.031; }),
          "is outside the domain");
  refused(resume(data, [](CheckpointData& d) { d.world.solids->position[0].y() = 1e300; }), "is outside the domain");
  refused(resume(data, [](CheckpointData& d) { d.world.solids->position[0].z() = -0.2; }), "is outside the domain");
}
