#pragma once
// Typed, validating access to a parsed TOML scene. Every problem becomes one line "file:line:column: key: what
// was expected, what was found"; unknown keys are problems too, so typos cannot pass silently.
#include <toml++/toml.h>

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

/// Raised when a scene (or a checkpoint's embedded scene) is invalid. what() lists every problem, one per line.
class SceneError : public std::runtime_error {
 public:
  explicit SceneError(const std::vector<std::string>& problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

/// Closed or open bounds on a number, with the wording used in messages.
struct Bounds {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  bool max_inclusive = true;
  /// Where the bounds follow the scene (the tank's extent), what they are in words ("the tank's z extent"): the key
  /// catalogue records this, so that it describes the reading and not one scene's numbers; messages give the numbers.
  const char* name = nullptr;

  static Bounds any() { return {}; }
  static Bounds positive() { return {0.0, std::numeric_limits<double>::infinity(), false, true}; }
  static Bounds non_negative() { return {0.0, std::numeric_limits<double>::infinity(), true, true}; }
  static Bounds closed(double lo, double hi) { return {lo, hi, true, true}; }
  bool contains(double value) const;
  std::string describe() const;
  /// describe(), or "a number in NAME" where the bounds have a name: the range the key catalogue records.
  std::string catalogue_range() const;
};

/// One key as the scene reader asks for it: what it holds, its range, unit and default, as the code that reads the
/// scene applies them. The reader records every key it asks for (SceneKeyCatalogue), so the scene's table of keys is
/// the reading itself and cannot drift from it; `riffle keys` prints it and docs/SCENES.md is checked against it.
struct SceneKey {
  std::string kind;   ///< "number", "integer", "boolean", "string", "one of", "list of", "3 numbers", "integers",
                      ///< "points", "table", "tables", "named tables"
  /// Its bounds, or the allowed strings; empty if any value of the kind will do. More than one where the range
  /// follows another key (shifting_coefficient's follows shifting_diffusivity).
  std::set<std::string> ranges;
  std::string unit;   ///< SI unit, "1" for a pure number; empty where none applies
  /// Every default it was asked with, spelled as a scene would write it; "required" when asked without one. More
  /// than one when the default follows another key (gc = true unless conservative_gradient).
  std::set<std::string> defaults;
  bool given = false;  ///< the scene sets it (in some table where it was asked)
};

/// The keys one or more scenes' reading asked for, by key: dotted, an item of an array of tables as []
/// ("fluid.boxes[].low"), a named table as NAME ("materials.NAME.density").
class SceneKeyCatalogue {
 public:
  void note(const std::string& key, const std::string& kind, const std::string& range, const std::string& unit,
            const std::string& fallback, bool given);
  const std::map<std::string, SceneKey>& keys() const { return keys_; }

 private:
  std::map<std::string, SceneKey> keys_;
};

/// The problems found so far while reading one scene file (and, when `catalogue` is set, the keys asked for).
struct SceneProblems {
  std::string file;
  std::vector<std::string> lines;
  SceneKeyCatalogue* catalogue = nullptr;
  void add(const toml::source_region& where, const std::string& key, const std::string& message);
  /// What add() writes before the message: "file:line:column: key: " (or "--set ...: key: ").
  std::string prefix(const toml::source_region& where, const std::string& key) const;
};

/// Reads one TOML table. Every key asked for is remembered; finish() reports the keys nobody asked for.
class TableReader {
 public:
  TableReader(const toml::table& table, std::string key_prefix, SceneProblems& problems);

  bool has(const std::string& key) const { return table_->contains(key); }
  const toml::source_region& where() const { return table_->source(); }
  /// Problems reported so far in the whole file; lets a caller skip checks that would only echo an earlier one.
  std::size_t problem_count() const { return problems_->lines.size(); }
  std::string full_key(const std::string& key) const;

  double number(const std::string& key, std::optional<double> fallback, const char* unit, Bounds bounds);
  std::int64_t integer(const std::string& key, std::optional<std::int64_t> fallback, std::int64_t min,
                       std::int64_t max);
  bool boolean(const std::string& key, std::optional<bool> fallback);
  std::string text(const std::string& key, std::optional<std::string> fallback);
  /// A string that must be one of `allowed`.
  std::string choice(const std::string& key, std::optional<std::string> fallback,
                     const std::vector<std::string>& allowed);
  /// A list of strings, each one of `allowed`, no repeats. Where `allowed` follows the scene, `allowed_name` says
  /// what it is in words ("the material names") for the key catalogue.
  std::vector<std::string> choices(const std::string& key, const std::vector<std::string>& allowed,
                                   const char* allowed_name = nullptr);
  Vec3 vec3(const std::string& key, std::optional<Vec3> fallback, const char* unit, Bounds component_bounds);
  /// An array of integers, each in [min, max]. Every bad item is reported at the item; then the result is empty,
  /// so a non-empty result has one value per item (item k is key[k] for item_problem).
  std::vector<std::int64_t> integers(const std::string& key, bool required, std::int64_t min, std::int64_t max);
  /// An array of points, each an array of `width` (2 or 3) finite numbers [unit]; a 2-number point gets z = 0.
  /// Every bad item is reported at the item (key[k], or key[k][c] for a component); then the result is empty, so a
  /// non-empty result has one point per item.
  std::vector<Vec3> points(const std::string& key, bool required, std::size_t width, const char* unit);
  /// Reports a problem at item `index` of the array `key` (named key[index]), or at the key if there is no such item.
  void item_problem(const std::string& key, std::size_t index, const std::string& message);

  /// A sub-table; nullopt if absent (or a problem if `required`).
  std::optional<TableReader> table(const std::string& key, bool required);
  /// An array of tables ([[key]]); empty if absent.
  std::vector<TableReader> tables(const std::string& key);
  /// Every sub-table of this table, keyed by its name (for named entries such as [materials.sand]).
  std::vector<std::pair<std::string, TableReader>> named_tables();

  /// Reports a problem at `key` (or at the table if the key is absent or "", the table itself).
  void problem(const std::string& key, const std::string& message);
  /// What problem(key, message) writes before the message, for a problem found after the scene is read (at set-up).
  std::string problem_prefix(const std::string& key) const;
  /// Reports keys that were never asked for.
  void finish();

 private:
  TableReader(const toml::table& table, std::string key_prefix, std::string catalogue_prefix,
              SceneProblems& problems);
  const toml::node* lookup(const std::string& key);
  /// text() without recording the key in the catalogue (choice() records it as a choice).
  std::string read_text(const std::string& key, const std::optional<std::string>& fallback);
  /// Records `key` in problems_->catalogue, if one is kept.
  void note(const std::string& key, const char* kind, const std::string& range, const std::string& unit,
            const std::string& fallback);

  const toml::table* table_;
  std::string prefix_;
  std::string catalogue_prefix_;  ///< prefix_ with array items as [] and named tables as NAME
  SceneProblems* problems_;
  std::vector<std::string> known_;
};

/// A string key naming one value of an enum: `names` pairs each scene spelling with its value (components/model.hpp
/// SceneNames); the default is `fallback`, the model's own default. A name not in the list is reported, and gives
/// `fallback`.
template <typename Enum, std::size_t N>
Enum enum_choice(TableReader& reader, const std::string& key, Enum fallback,
                 const std::array<std::pair<const char*, Enum>, N>& names) {
  std::vector<std::string> allowed;
  std::string fallback_name;
  for (const auto& [name, value] : names) {
    allowed.emplace_back(name);
    if (value == fallback) fallback_name = name;
  }
  const std::string chosen = reader.choice(key, fallback_name, allowed);
  for (const auto& [name, value] : names)
    if (chosen == name) return value;
  return fallback;
}

/// A default as a scene would spell it.
std::string scene_spelling(const Vec3& value);

/// A number as messages show it: the shortest form with 6 significant digits (0.005, 1e-07).
std::string format_number(double value);

/// A name a scene gives (a probe, a file it writes, a wall box): letters, digits, '_', '-' and '.', not starting
/// with '.', at most 200 characters, so it is safe as a file name and in a CSV header.
bool plain_name(const std::string& name);

/// Parses TOML text; syntax errors are reported as problems with the file's line and column.
std::optional<toml::table> parse_toml(const std::string& text, SceneProblems& problems);

std::string toml_type_name(const toml::node& node);

}  // namespace riffle
