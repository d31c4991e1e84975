#include "engine/toml/scene_reader.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace riffle {

namespace {
std::string join(const std::vector<std::string>& items, const char* separator) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (k) out += separator;
    out += items[k];
  }
  return out;
}

// toml++'s value<double>() refuses an integer that a double cannot hold exactly (above 2^53); a scene number
// that large is still a number, so convert it rather than report "got 0" or "got an integer".
std::optional<double> as_double(const toml::node& node) {
  if (const auto* integer = node.as_integer()) return static_cast<double>(integer->get());
  if (const auto* floating = node.as_floating_point()) return floating->get();
  return std::nullopt;
}

}  // namespace

std::string format_number(double value) {
  std::ostringstream stream;
  stream << value;  // shortest form: 0.005, not 0.005000; 1e-07, not 0.000000
  return stream.str();
}

bool plain_name(const std::string& name) {
  if (name.empty() || name.front() == '.' || name.size() > 200) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
  });
}

SceneError::SceneError(const std::vector<std::string>& problems)
    : std::runtime_error(join(problems, "\n")), problems_(problems) {}

bool Bounds::contains(double value) const {
  if (!std::isfinite(value)) return false;
  const bool above = min_inclusive ? value >= min : value > min;
  const bool below = max_inclusive ? value <= max : value < max;
  return above && below;
}

std::string Bounds::describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (!has_min && !has_max) return "a finite number";
  if (has_min && !has_max) {
    if (min == 0.0) return min_inclusive ? "a number >= 0" : "a number > 0";
    return std::string("a number ") + (min_inclusive ? ">= " : "> ") + format_number(min);
  }
  if (!has_min) return std::string("a number ") + (max_inclusive ? "<= " : "< ") + format_number(max);
  return "a number in " + std::string(min_inclusive ? "[" : "(") + format_number(min) + ", " + format_number(max) +
         (max_inclusive ? "]" : ")");
}

std::string Bounds::catalogue_range() const { return name ? std::string("a number in ") + name : describe(); }

void SceneProblems::add(const toml::source_region& where, const std::string& key, const std::string& message) {
  lines.push_back(prefix(where, key) + message);
}

std::string SceneProblems::prefix(const toml::source_region& where, const std::string& key) const {
  std::ostringstream line;
  // A value set on the command line (engine/scene/scene_overrides.hpp) carries its --set as its source: name that.
  if (where.path && !where.path->empty() && *where.path != file && where.path->rfind("--set ", 0) == 0)
    line << *where.path << ": " << key << ": ";
  else
    line << file << ':' << where.begin.line << ':' << where.begin.column << ": " << key << ": ";
  return line.str();
}

std::string toml_type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

std::optional<toml::table> parse_toml(const std::string& text, SceneProblems& problems) {
  try {
    return toml::parse(text, problems.file);
  } catch (const toml::parse_error& error) {
    problems.add(error.source(), "(syntax)", std::string(error.description()));
    return std::nullopt;
  }
}

void SceneKeyCatalogue::note(const std::string& key, const std::string& kind, const std::string& range,
                             const std::string& unit, const std::string& fallback, bool given) {
  const auto [found, inserted] = keys_.try_emplace(key);
  SceneKey& entry = found->second;
  if (inserted) {  // the first reading of a key describes it; later ones add their ranges and defaults
    entry.kind = kind;
    entry.unit = unit;
  }
  entry.ranges.insert(range);
  entry.defaults.insert(fallback);
  entry.given = entry.given || given;
}

std::string scene_spelling(const Vec3& value) {
  return "[" + format_number(value.x()) + ", " + format_number(value.y()) + ", " + format_number(value.z()) + "]";
}

TableReader::TableReader(const toml::table& table, std::string key_prefix, SceneProblems& problems)
    : TableReader(table, key_prefix, key_prefix, problems) {}

TableReader::TableReader(const toml::table& table, std::string key_prefix, std::string catalogue_prefix,
                         SceneProblems& problems)
    : table_(&table), prefix_(std::move(key_prefix)), catalogue_prefix_(std::move(catalogue_prefix)),
      problems_(&problems) {}

void TableReader::note(const std::string& key, const char* kind, const std::string& range, const std::string& unit,
                       const std::string& fallback) {
  if (!problems_->catalogue) return;
  problems_->catalogue->note(catalogue_prefix_.empty() ? key : catalogue_prefix_ + "." + key, kind, range, unit,
                             fallback, table_->contains(key));
}

std::string TableReader::full_key(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }

const toml::node* TableReader::lookup(const std::string& key) {
  known_.push_back(key);
  return table_->get(key);
}

void TableReader::problem(const std::string& key, const std::string& message) {
  problems_->lines.push_back(problem_prefix(key) + message);
}

std::string TableReader::problem_prefix(const std::string& key) const {
  const toml::node* node = key.empty() ? nullptr : table_->get(key);
  // A problem of the table as a whole ("") is named by the table's own key, not with a trailing dot.
  return problems_->prefix(node ? node->source() : table_->source(), key.empty() ? prefix_ : full_key(key));
}

double TableReader::number(const std::string& key, std::optional<double> fallback, const char* unit,
                           Bounds bounds) {
  const toml::node* node = lookup(key);
  const std::string expected = bounds.describe() + " [" + unit + "]";
  note(key, "number", bounds.catalogue_range(), unit, fallback ? format_number(*fallback) : "required");
  if (!node) {
    if (!fallback) problem(key, "missing required key; expected " + expected);
    return fallback.value_or(0.0);
  }
  if (!node->is_number()) {
    problem(key, "expected " + expected + ", got " + toml_type_name(*node));
    return fallback.value_or(0.0);
  }
  const double value = *as_double(*node);
  if (!bounds.contains(value)) {
    problem(key, "expected " + expected + ", got " + format_number(value));
    return fallback.value_or(0.0);
  }
  return value;
}

std::int64_t TableReader::integer(const std::string& key, std::optional<std::int64_t> fallback, std::int64_t min,
                                  std::int64_t max) {
  const toml::node* node = lookup(key);
  const std::string expected = "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  note(key, "integer", "[" + std::to_string(min) + ", " + std::to_string(max) + "]", "",
       fallback ? std::to_string(*fallback) : "required");
  if (!node) {
    if (!fallback) problem(key, "missing required key; expected " + expected);
    return fallback.value_or(min);
  }
  if (!node->is_integer()) {
    problem(key, "expected " + expected + ", got " + toml_type_name(*node));
    return fallback.value_or(min);
  }
  const std::int64_t value = node->value<std::int64_t>().value_or(min);
  if (value < min || value > max) {
    problem(key, "expected " + expected + ", got " + std::to_string(value));
    return fallback.value_or(min);
  }
  return value;
}

bool TableReader::boolean(const std::string& key, std::optional<bool> fallback) {
  const toml::node* node = lookup(key);
  note(key, "boolean", "", "", fallback ? (*fallback ? "true" : "false") : "required");
  if (!node) {
    if (!fallback) problem(key, "missing required key; expected true or false");
    return fallback.value_or(false);
  }
  if (!node->is_boolean()) {
    problem(key, "expected true or false, got " + toml_type_name(*node));
    return fallback.value_or(false);
  }
  return node->value<bool>().value_or(false);
}

std::string TableReader::text(const std::string& key, std::optional<std::string> fallback) {
  note(key, "string", "", "", fallback ? "\"" + *fallback + "\"" : "required");
  return read_text(key, fallback);
}

std::string TableReader::read_text(const std::string& key, const std::optional<std::string>& fallback) {
  const toml::node* node = lookup(key);
  if (!node) {
    if (!fallback) problem(key, "missing required key; expected a string");
    return fallback.value_or("");
  }
  if (!node->is_string()) {
    problem(key, "expected a string, got " + toml_type_name(*node));
    return fallback.value_or("");
  }
  return node->value<std::string>().value_or("");
}

std::string TableReader::choice(const std::string& key, std::optional<std::string> fallback,
                                const std::vector<std::string>& allowed) {
  const toml::node* node = table_->get(key);
  const bool present = node != nullptr;
  note(key, "one of", "\"" + join(allowed, "\", \"") + "\"", "", fallback ? "\"" + *fallback + "\"" : "required");
  const std::string value = read_text(key, fallback);
  if (present && node->is_string() && std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
    problem(key, "expected one of \"" + join(allowed, "\", \"") + "\", got \"" + value + "\"");
    return fallback.value_or(allowed.front());
  }
  return value;
}

std::vector<std::string> TableReader::choices(const std::string& key, const std::vector<std::string>& allowed,
                                              const char* allowed_name) {
  std::vector<std::string> values;
  const toml::node* node = lookup(key);
  note(key, "list of", allowed_name ? allowed_name : "\"" + join(allowed, "\", \"") + "\"", "", "[]");
  if (!node) return values;
  const toml::array* array = node->as_array();
  const std::string expected = "an array of strings from \"" + join(allowed, "\", \"") + "\"";
  if (!array) {
    problem(key, "expected " + expected + ", got " + toml_type_name(*node));
    return values;
  }
  for (const toml::node& item : *array) {
    const auto value = item.value<std::string>();
    if (!item.is_string() || std::find(allowed.begin(), allowed.end(), *value) == allowed.end()) {
      problems_->add(item.source(), full_key(key), "expected " + expected + ", got " +
                                                       (item.is_string() ? "\"" + *value + "\"" : toml_type_name(item)));
      continue;
    }
    if (std::find(values.begin(), values.end(), *value) != values.end()) {
      problems_->add(item.source(), full_key(key), "\"" + *value + "\" is listed twice");
      continue;
    }
    values.push_back(*value);
  }
  return values;
}

Vec3 TableReader::vec3(const std::string& key, std::optional<Vec3> fallback, const char* unit,
                       Bounds component_bounds) {
  const toml::node* node = lookup(key);
  const std::string expected =
      std::string("an array of 3 numbers [") + unit + "], each " + component_bounds.describe();
  note(key, "3 numbers", component_bounds.catalogue_range(), unit,
       fallback ? scene_spelling(*fallback) : "required");
  if (!node) {
    if (!fallback) problem(key, "missing required key; expected " + expected);
    return fallback.value_or(Vec3::Zero());
  }
  const toml::array* array = node->as_array();
  if (!array || array->size() != 3) {
    problem(key, "expected " + expected + ", got " +
                     (array ? "an array of " + std::to_string(array->size()) + " items" : toml_type_name(*node)));
    return fallback.value_or(Vec3::Zero());
  }
  Vec3 value;
  for (std::size_t k = 0; k < 3; ++k) {
    const toml::node& item = *array->get(k);
    const std::optional<double> component = as_double(item);
    if (!component || !component_bounds.contains(*component)) {
      problems_->add(item.source(), full_key(key) + "[" + std::to_string(k) + "]",
                     "expected " + component_bounds.describe() + " [" + unit + "], got " +
                         (component ? format_number(*component) : toml_type_name(item)));
      return fallback.value_or(Vec3::Zero());
    }
    value[static_cast<Eigen::Index>(k)] = *component;
  }
  return value;
}

std::vector<std::int64_t> TableReader::integers(const std::string& key, bool required, std::int64_t min,
                                                std::int64_t max) {
  std::vector<std::int64_t> values;
  const toml::node* node = lookup(key);
  const std::string expected =
      "an array of integers, each in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  note(key, "integers", "[" + std::to_string(min) + ", " + std::to_string(max) + "]", "", required ? "required" : "[]");
  if (!node) {
    if (required) problem(key, "missing required key; expected " + expected);
    return values;
  }
  const toml::array* array = node->as_array();
  if (!array) {
    problem(key, "expected " + expected + ", got " + toml_type_name(*node));
    return values;
  }
  bool all_good = true;
  for (std::size_t k = 0; k < array->size(); ++k) {
    const toml::node& item = *array->get(k);
    const std::optional<std::int64_t> value = item.is_integer() ? item.value<std::int64_t>() : std::nullopt;
    if (!value || *value < min || *value > max) {
      problems_->add(item.source(), full_key(key) + "[" + std::to_string(k) + "]",
                     "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "], got " +
                         (value ? std::to_string(*value) : toml_type_name(item)));
      all_good = false;
      continue;
    }
    values.push_back(*value);
  }
  if (!all_good) values.clear();
  return values;
}

std::vector<Vec3> TableReader::points(const std::string& key, bool required, std::size_t width, const char* unit) {
  std::vector<Vec3> values;
  const toml::node* node = lookup(key);
  const std::string point = "an array of " + std::to_string(width) + " numbers [" + unit + "]";
  note(key, "points", std::to_string(width) + " numbers each", unit, required ? "required" : "[]");
  const std::string expected = "an array of points, each " + point;
  if (!node) {
    if (required) problem(key, "missing required key; expected " + expected);
    return values;
  }
  const toml::array* array = node->as_array();
  if (!array) {
    problem(key, "expected " + expected + ", got " + toml_type_name(*node));
    return values;
  }
  bool all_good = true;
  for (std::size_t k = 0; k < array->size(); ++k) {
    const toml::node& item = *array->get(k);
    const std::string item_key = full_key(key) + "[" + std::to_string(k) + "]";
    const toml::array* coordinates = item.as_array();
    if (!coordinates || coordinates->size() != width) {
      problems_->add(item.source(), item_key,
                     "expected " + point + ", got " +
                         (coordinates ? "an array of " + std::to_string(coordinates->size()) + " items"
                                      : toml_type_name(item)));
      all_good = false;
      continue;
    }
    Vec3 value = Vec3::Zero();
    for (std::size_t c = 0; c < width; ++c) {
      const toml::node& coordinate = *coordinates->get(c);
      const std::optional<double> number = as_double(coordinate);
      if (!number || !std::isfinite(*number)) {
        problems_->add(coordinate.source(), item_key + "[" + std::to_string(c) + "]",
                       std::string("expected a finite number [") + unit + "], got " +
                           (number ? format_number(*number) : toml_type_name(coordinate)));
        all_good = false;
        break;
      }
      value[static_cast<Eigen::Index>(c)] = *number;
    }
    values.push_back(value);
  }
  if (!all_good) values.clear();
  return values;
}

void TableReader::item_problem(const std::string& key, std::size_t index, const std::string& message) {
  const toml::node* node = table_->get(key);
  const toml::array* array = node ? node->as_array() : nullptr;
  if (!array || index >= array->size()) {
    problem(key, message);
    return;
  }
  problems_->add(array->get(index)->source(), full_key(key) + "[" + std::to_string(index) + "]", message);
}

std::optional<TableReader> TableReader::table(const std::string& key, bool required) {
  const toml::node* node = lookup(key);
  note(key, "table", "", "", required ? "required" : "absent");
  if (!node) {
    if (required) problem(key, "missing required table [" + full_key(key) + "]");
    return std::nullopt;
  }
  if (!node->is_table()) {
    problem(key, "expected a table, got " + toml_type_name(*node));
    return std::nullopt;
  }
  return TableReader(*node->as_table(), full_key(key),
                     catalogue_prefix_.empty() ? key : catalogue_prefix_ + "." + key, *problems_);
}

std::vector<TableReader> TableReader::tables(const std::string& key) {
  std::vector<TableReader> readers;
  const toml::node* node = lookup(key);
  note(key, "tables", "", "", "[]");
  if (!node) return readers;
  const toml::array* array = node->as_array();
  // An empty array is an empty list of tables ("spheres = []"), not a type error.
  if (!array || (!array->empty() && !array->is_array_of_tables())) {
    problem(key, "expected an array of tables ([[" + full_key(key) + "]]), got " + toml_type_name(*node));
    return readers;
  }
  for (std::size_t k = 0; k < array->size(); ++k)
    readers.push_back(TableReader(*array->get(k)->as_table(), full_key(key) + "[" + std::to_string(k) + "]",
                                  (catalogue_prefix_.empty() ? key : catalogue_prefix_ + "." + key) + "[]",
                                  *problems_));
  return readers;
}

std::vector<std::pair<std::string, TableReader>> TableReader::named_tables() {
  std::vector<std::pair<std::string, TableReader>> readers;
  for (auto&& [key, node] : *table_) {
    const std::string name(key.str());
    known_.push_back(name);
    if (!node.is_table()) {
      problems_->add(node.source(), full_key(name), "expected a table, got " + toml_type_name(node));
      continue;
    }
    readers.emplace_back(name, TableReader(*node.as_table(), full_key(name),
                                           catalogue_prefix_.empty() ? "NAME" : catalogue_prefix_ + ".NAME",
                                           *problems_));
  }
  return readers;
}

void TableReader::finish() {
  for (auto&& [key, node] : *table_) {
    const std::string name(key.str());
    if (std::find(known_.begin(), known_.end(), name) != known_.end()) continue;
    std::vector<std::string> known = known_;
    std::sort(known.begin(), known.end());
    known.erase(std::unique(known.begin(), known.end()), known.end());
    problems_->add(key.source(), full_key(name),
                   "unknown key" + (known.empty() ? std::string() : " (known keys here: " + join(known, ", ") + ")"));
  }
}

}  // namespace riffle
