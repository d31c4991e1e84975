#pragma once
// `riffle run/check/graph --set KEY=VALUE`: scene keys overridden from the command line, so a study can vary one
// parameter (a bed's seed, a friction, a coupling switch) without copying the scene file.
//
// KEY is a dotted path from the scene's root: `contact.friction`, `solids.layered_beds[0].seed`; an array of tables
// is indexed `name[i]`, and `name[n]` with n its current length appends a new table (so
// `contact.pairs[0].materials=["grain","glass"]` adds a pair to a scene that has none). Missing tables on the path are
// created. VALUE is a TOML value (`0.3`, `true`, `[1, 2]`, `"text"`); a VALUE that is not valid TOML is taken as a
// string, so `coupling.fluid_velocity=pore` needs no shell quoting. What the key means and whether the value is
// allowed is checked afterwards by the scene reader, like any key in the file; its messages name the `--set` instead
// of a line of the file.
#include <string>
#include <vector>

#include "engine/toml/scene_reader.hpp"

namespace riffle {

/// At most this many --set options, and this many characters in one (a study sets a handful).
inline constexpr std::size_t kMaxSceneOverrides = 256;
inline constexpr std::size_t kMaxSceneOverrideLength = 4096;

/// Applies each "KEY=VALUE" to `root` in order (a later one wins). A malformed override, an index past the end of
/// its array or a path through a value that is not a table is reported in `problems` (naming the --set) and skipped.
void apply_scene_overrides(toml::table& root, const std::vector<std::string>& overrides, SceneProblems& problems);

/// The scene a run with overrides stores in its checkpoints: `root` written back as TOML, after a comment naming the
/// file and the overrides, so a resume rebuilds the same scene without the command line.
std::string scene_text_with_overrides(const toml::table& root, const std::string& file_name,
                                      const std::vector<std::string>& overrides);

}  // namespace riffle
