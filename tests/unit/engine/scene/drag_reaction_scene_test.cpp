// [coupling] drag_reaction (docs/SCENES.md; docs/COUPLING.md "Where the drag reaction lands"): "grid" by default,
// "sampling_kernel" on request; anything else is refused naming the file, line, column and key.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "engine/scene/scene.hpp"
#include "tests/support/test_support.hpp"

namespace riffle {

TEST_CASE("coupling.drag_reaction: grid by default, sampling_kernel on request, a bad value named with its line") {
  const std::string scene = test::coupled_scene_text();
  CHECK_FALSE(parse_scene(scene, "coupled.toml").coupling.sampling_kernel_reaction);
  CHECK_FALSE(parse_scene(scene + "[coupling]\ndrag_reaction = \"grid\"\n", "coupled.toml")
                  .coupling.sampling_kernel_reaction);
  CHECK(parse_scene(scene + "[coupling]\ndrag_reaction = \"sampling_kernel\"\n", "coupled.toml")
            .coupling.sampling_kernel_reaction);
  // The [coupling] table is line 19 of the scene; the key is on line 20, its value at column 17.
  const std::vector<std::string> problems =
      test::problems_of(scene + "[coupling]\ndrag_reaction = \"kernel\"\n", "coupled.toml");
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].rfind("coupled.toml:20:17: coupling.drag_reaction: ", 0) == 0);
  CHECK(problems[0].find("expected one of \"grid\", \"sampling_kernel\", got \"kernel\"") != std::string::npos);
  const std::vector<std::string> wrong_type =
      test::problems_of(scene + "[coupling]\ndrag_reaction = true\n", "coupled.toml");
  REQUIRE(wrong_type.size() == 1);
  CHECK(wrong_type[0].find("coupling.drag_reaction: expected a string") != std::string::npos);
}

}  // namespace riffle
