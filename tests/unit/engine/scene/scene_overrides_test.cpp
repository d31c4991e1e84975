// --set KEY=VALUE (engine/scene/scene_overrides.hpp) through parse_scene, the path `riffle run --set` takes: a value
// replaces the file's, a table or an element of an array of tables is created where the path asks for one, the scene
// stored for checkpoints rebuilds the same model, and every malformed override is refused with a message that names
// the --set it came from.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "engine/scene/scene.hpp"
#include "engine/scene/scene_overrides.hpp"
#include "tests/support/test_support.hpp"

namespace riffle {
namespace {

using test::small_model;
using test::small_scene_text;

Model with(const std::vector<std::string>& overrides) {
  return parse_scene(small_scene_text(), "small.toml", {}, overrides);
}

std::vector<std::string> problems_with(const std::vector<std::string>& overrides) {
  try {
    with(overrides);
  } catch (const SceneError& error) {
    return error.problems();
  }
  FAIL_CHECK("the overrides were accepted");
  return {};
}

bool starts_with(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

TEST_CASE("--set replaces a value, and a later --set of the same key wins") {
  const Model base = small_model();
  const Model model = with({"run.end_time=0.02", "tank.motion.amplitude=0.02", "tank.motion.amplitude=0.03"});
  CHECK(base.end_time == doctest::Approx(0.05));
  CHECK(model.end_time == 0.02);
  CHECK(model.tank.motion.amplitude == 0.03);
  CHECK(model.tank.motion.frequency == base.tank.motion.frequency);  // the rest of the table is the file's
}

TEST_CASE("--set takes a bare word as a string and any TOML value as itself") {
  const Model model = with({"run.name=other", "run.gravity=[0.0, 0.0, -1.5]", "solids.blocks[0].velocity=[1, 2, 3]"});
  CHECK(model.name == "other");
  CHECK(model.gravity.z() == -1.5);
}

TEST_CASE("--set creates a missing table and appends an element to an array of tables") {
  // [materials.sand] is new; [[solids.blocks]] has one element, so index 1 appends a second block.
  const Model model = with({"materials.sand.density=2650.0", "solids.blocks[1].min=[0.02, 0.02, 0.10]",
                            "solids.blocks[1].max=[0.06, 0.06, 0.12]", "solids.blocks[1].spacing=0.02",
                            "solids.blocks[1].radius=0.003", "solids.blocks[1].material=sand"});
  REQUIRE(model.materials.size() == 2);
  CHECK(model.materials[1].name == "sand");
  CHECK(model.materials[1].density == 2650.0);
}

TEST_CASE("the scene a run with --set stores rebuilds the same model without the command line") {
  const std::vector<std::string> overrides{"run.end_time=0.03", "tank.motion.amplitude=0.015", "run.name=changed"};
  const Model model = with(overrides);
  CHECK(starts_with(model.scene_text, "# small.toml, as changed on the command line by:\n#   --set run.end_time=0.03\n"));
  const Model rebuilt = parse_scene(model.scene_text, "small.toml");
  CHECK(rebuilt.end_time == 0.03);
  CHECK(rebuilt.tank.motion.amplitude == 0.015);
  CHECK(rebuilt.tank.motion.frequency == model.tank.motion.frequency);
  CHECK(rebuilt.name == "changed");
  CHECK(rebuilt.scene_text == model.scene_text);  // parsed without overrides: stored as given
  // Without overrides the stored text is the file's, byte for byte.
  CHECK(small_model().scene_text == small_scene_text());
}

TEST_CASE("a value set on the command line is checked like the file's, and the message names the --set") {
  const std::vector<std::string> problems = problems_with({"run.dt=-1", "run.nonsense=3", "tank.motion.kind=wobble"});
  REQUIRE(problems.size() == 3);
  auto reported = [&](const std::string& prefix) {
    for (const std::string& line : problems)
      if (starts_with(line, prefix)) return true;
    return false;
  };
  CHECK(reported("--set run.dt=-1: run.dt: expected a number > 0"));
  CHECK(reported("--set tank.motion.kind=wobble: tank.motion.kind: expected one of"));
  CHECK(reported("--set run.nonsense=3: run.nonsense: unknown key"));
}

TEST_CASE("malformed overrides are refused, each naming itself, and the rest of the scene is still checked") {
  const std::vector<std::string> problems =
      problems_with({"run.end_time", "run..dt=1", "run.dt[0]=1", "solids.blocks.radius=1", "run.name.x=1",
                     "solids.blocks[7].radius=1", "solids.blocks[99999999999999999999].radius=1", "=3",
                     "run.end_time=-2"});
  REQUIRE(problems.size() == 9);
  CHECK(problems[0] == "--set run.end_time: expected KEY=VALUE, e.g. contact.friction=0.3");
  CHECK(starts_with(problems[1], "--set run..dt=1: expected a key"));
  CHECK(starts_with(problems[2], "--set run.dt[0]=1: the last key names a value"));
  CHECK(starts_with(problems[3], "--set solids.blocks.radius=1: 'blocks' is an array of tables"));
  CHECK(starts_with(problems[4], "--set run.name.x=1: 'name' is a string, not a table"));
  CHECK(starts_with(problems[5], "--set solids.blocks[7].radius=1: 'blocks' has 1 table(s)"));
  CHECK(starts_with(problems[6], "--set solids.blocks[99999999999999999999].radius=1: expected an index"));
  CHECK(starts_with(problems[7], "--set =3: expected a key"));
  CHECK(starts_with(problems[8], "--set run.end_time=-2: run.end_time: expected"));
}

TEST_CASE("too many or too long overrides are refused before any is applied") {
  CHECK(starts_with(problems_with(std::vector<std::string>(kMaxSceneOverrides + 1, "run.dt=0.001")).front(),
                    "--set: 257 overrides given, more than the 256 allowed"));
  const std::string long_value = "run.name=" + std::string(kMaxSceneOverrideLength, 'a');
  CHECK(problems_with({long_value}).front().find("longer than 4096 characters") != std::string::npos);
}

TEST_CASE("a value with quotes, backslashes or control characters stays one string and is refused by its key's check") {
  const std::vector<std::string> problems = problems_with({"run.name=a\"b\\c", std::string("run.name=x\ny\x01")});
  REQUIRE(problems.size() == 1);  // the later one wins; it is a string, and not a plain folder name
  CHECK(starts_with(problems[0], "--set run.name=x"));
  const Model model = with({"run.name=quoted\"name"});
  CHECK(model.name == "quoted\"name");
}

TEST_CASE("an override that is not UTF-8 is refused, and control characters are escaped in the stored record") {
  const std::vector<std::string> problems = problems_with({std::string("run.name=a\xff"), "tank.size=\xc0\xaf"});
  REQUIRE(problems.size() == 2);
  CHECK(problems[0] == "--set: an override is not valid UTF-8 text");
  // The record of the overrides is a TOML comment: it must read back, whatever bytes the command line held.
  toml::table root;
  root.insert("key", 1);
  const std::string text = scene_text_with_overrides(root, "s.toml", {std::string("run.name=a\x01" "b\tc\x7f")});
  CHECK(text.find("#   --set run.name=a\\x01b\\x09c\\x7f\n") != std::string::npos);
  CHECK_NOTHROW(static_cast<void>(toml::parse(text)));
}

}  // namespace
}  // namespace riffle
