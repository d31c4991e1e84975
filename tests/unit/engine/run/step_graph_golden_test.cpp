// The coupled seed scene's step graph, pinned edge by edge: tests/data/seed_step_graph.dot is what `riffle graph`
// prints for scenes/oscillating_tank_quick.toml. A change to a system's access, to the registry's order or to the
// scheduler's rules shows up here as a changed edge, to be checked and then regenerated.
#include <doctest/doctest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "engine/run/registry.hpp"
#include "engine/run/stepper.hpp"
#include "engine/scene/scene.hpp"
#include "engine/setup/initial_state.hpp"

using namespace riffle;

namespace {


}  // namespace

TEST_CASE("the seed scene's step graph is the pinned one (tests/data/seed_step_graph.dot)") {
  const std::string source = RIFFLE_SOURCE_DIR;
  std::string scene = test::file_text(source + "/scenes/oscillating_tank_quick.toml");
  // The scene starts from the settled bed's checkpoint, which a fresh clone does not have. The graph depends on
  // which systems the scene enables, not on the grains, so one grain stands in for the bed.
  const std::regex initial_state(R"(\ninitial_state = [^\n]*)");
  REQUIRE(std::regex_search(scene, initial_state));
  scene = std::regex_replace(scene, initial_state,
                             "\n[[solids.spheres]]\nposition = [0.12, 0.08, 0.1]\nradius = 0.005\nmaterial = \"grain\"");
  const Model model = parse_scene(scene, source + "/scenes/oscillating_tank_quick.toml");
  World world = initial_world(model);
  const Stepper stepper(build_pipeline(model), world, model);
  const std::string expected = test::file_text(source + "/tests/data/seed_step_graph.dot");
  INFO("the step graph changed; if that is intended, check the new edges and regenerate the file with\n"
       "  build/riffle graph scenes/oscillating_tank_quick.toml > tests/data/seed_step_graph.dot\n"
       "(the scene needs the settled bed: build/riffle run scenes/dry_bed_settle.toml). The graph now:\n"
       << stepper.dot());
  CHECK(stepper.dot() == expected);
}
