#include "engine/scene/scene_overrides.hpp"

#include <charconv>
#include <cstdio>
#include <sstream>

namespace riffle {

namespace {

/// One step of a key path: a key, and an index when it names an element of an array of tables.
struct PathStep {
  std::string key;
  std::optional<std::size_t> index;
};

/// Whether `text` is well-formed UTF-8 (TOML text must be; a checkpoint's scene is read back as TOML).
bool is_utf8(const std::string& text) {
  std::size_t at = 0;
  while (at < text.size()) {
    const unsigned char lead = static_cast<unsigned char>(text[at]);
    const std::size_t length = lead < 0x80 ? 1 : (lead >> 5) == 0x6 ? 2 : (lead >> 4) == 0xe ? 3 : (lead >> 3) == 0x1e ? 4 : 0;
    if (length == 0 || at + length > text.size()) return false;
    std::uint32_t code = length == 1 ? lead : lead & (0x7fu >> length);
    for (std::size_t k = 1; k < length; ++k) {
      const unsigned char next = static_cast<unsigned char>(text[at + k]);
      if ((next >> 6) != 0x2) return false;
      code = (code << 6) | (next & 0x3fu);
    }
    // Overlong forms, surrogates and code points past U+10FFFF are not UTF-8.
    const std::uint32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (code < smallest[length] || (code >= 0xd800 && code <= 0xdfff) || code > 0x10ffff) return false;
    at += length;
  }
  return true;
}

bool is_bare_key_character(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

/// "a.b[2].c" -> {a}, {b, 2}, {c}; nullopt (with `why`) for anything else.
std::optional<std::vector<PathStep>> parse_key_path(const std::string& path, std::string& why) {
  std::vector<PathStep> steps;
  std::size_t at = 0;
  while (true) {
    PathStep step;
    while (at < path.size() && is_bare_key_character(path[at])) step.key += path[at++];
    if (step.key.empty()) {
      why = "expected a key (letters, digits, '_' or '-') at character " + std::to_string(at + 1) + " of '" + path +
            "'";
      return std::nullopt;
    }
    if (at < path.size() && path[at] == '[') {
      const std::size_t close = path.find(']', at);
      std::size_t index = 0;
      const char* first = path.data() + at + 1;
      const char* last = close == std::string::npos ? first : path.data() + close;
      const auto [end, error] = std::from_chars(first, last, index);
      if (close == std::string::npos || close == at + 1 || error != std::errc{} || end != last) {
        why = "expected an index such as " + step.key + "[0] in '" + path + "'";
        return std::nullopt;
      }
      step.index = index;
      at = close + 1;
    }
    steps.push_back(std::move(step));
    if (at == path.size()) return steps;
    if (path[at] != '.') {
      why = "unexpected '" + std::string(1, path[at]) + "' at character " + std::to_string(at + 1) + " of '" + path +
            "'";
      return std::nullopt;
    }
    ++at;
  }
}

/// The value of `text` as a TOML value, its source named `origin`; a text that is not a TOML value is a string.
toml::table parse_value(const std::string& text, const std::string& origin) {
  try {
    toml::table snippet = toml::parse("value = " + text, origin);
    if (snippet.size() == 1) return snippet;
  } catch (const toml::parse_error&) {
  }
  // As a TOML basic string, parsed like any value so that it carries its source too.
  std::string quoted = "value = \"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      quoted += escape;
    } else {
      quoted += c;
    }
  }
  quoted += '"';
  return toml::parse(quoted, origin);  // the text is UTF-8 (checked before), so this parses
}

/// A new, empty table whose source is the override (so a problem found in it later names the --set).
toml::table new_table(const std::string& origin) {
  toml::table snippet = toml::parse("value = {}", origin);
  return std::move(*snippet.get("value")->as_table());
}

/// Moves `node` into `table` at `key`, keeping its type and its source.
void put(toml::table& table, const std::string& key, toml::node&& node) {
  // The key takes the value's source too: an unknown key is reported where its key came from.
  const toml::key named{key, node.source()};
  std::move(node).visit([&](auto&& concrete) {
    table.erase(key);  // insert_or_assign would keep the old key, and with it the file's line
    table.insert(named, std::move(concrete));
  });
}

/// The table at `step` below `table`, created if missing; nullptr (with `why`) if the path cannot go through.
toml::table* descend(toml::table& table, const PathStep& step, const std::string& origin, std::string& why) {
  toml::node* node = table.get(step.key);
  if (!step.index) {
    if (!node) {
      put(table, step.key, new_table(origin));
      return table.get(step.key)->as_table();
    }
    if (node->is_array_of_tables()) {
      why = "'" + step.key + "' is an array of tables: name an element, e.g. " + step.key + "[0]";
      return nullptr;
    }
    if (!node->is_table()) {
      why = "'" + step.key + "' is " + toml_type_name(*node) + ", not a table";
      return nullptr;
    }
    return node->as_table();
  }
  if (!node) {
    toml::table holder = toml::parse("value = []", origin);
    put(table, step.key, std::move(*holder.get("value")));
    node = table.get(step.key);
  }
  toml::array* array = node->as_array();
  if (!array || !(array->empty() || array->is_array_of_tables())) {
    why = "'" + step.key + "' is " + toml_type_name(*node) + ", not an array of tables";
    return nullptr;
  }
  const std::size_t index = *step.index;
  if (index > array->size()) {
    why = "'" + step.key + "' has " + std::to_string(array->size()) + " table(s); an index may be at most " +
          std::to_string(array->size()) + " (which appends one)";
    return nullptr;
  }
  if (index == array->size()) array->push_back(new_table(origin));
  return (*array)[index].as_table();
}

}  // namespace

void apply_scene_overrides(toml::table& root, const std::vector<std::string>& overrides, SceneProblems& problems) {
  if (overrides.size() > kMaxSceneOverrides) {
    problems.lines.push_back("--set: " + std::to_string(overrides.size()) + " overrides given, more than the " +
                             std::to_string(kMaxSceneOverrides) + " allowed");
    return;
  }
  for (const std::string& text : overrides) {
    const std::string origin = "--set " + text;
    auto refuse = [&](const std::string& why) { problems.lines.push_back(origin + ": " + why); };
    if (text.size() > kMaxSceneOverrideLength) {
      refuse("longer than " + std::to_string(kMaxSceneOverrideLength) + " characters");
      continue;
    }
    if (!is_utf8(text)) {
      problems.lines.emplace_back("--set: an override is not valid UTF-8 text");
      continue;
    }
    const std::size_t equals = text.find('=');
    if (equals == std::string::npos) {
      refuse("expected KEY=VALUE, e.g. contact.friction=0.3");
      continue;
    }
    std::string why;
    const std::optional<std::vector<PathStep>> path = parse_key_path(text.substr(0, equals), why);
    if (!path) {
      refuse(why);
      continue;
    }
    if (path->back().index) {
      refuse("the last key names a value, not an element of an array of tables: drop [" +
             std::to_string(*path->back().index) + "]");
      continue;
    }
    toml::table* table = &root;
    for (std::size_t k = 0; table && k + 1 < path->size(); ++k) table = descend(*table, (*path)[k], origin, why);
    if (!table) {
      refuse(why);
      continue;
    }
    toml::table value = parse_value(text.substr(equals + 1), origin);
    put(*table, path->back().key, std::move(*value.get("value")));
  }
}

std::string scene_text_with_overrides(const toml::table& root, const std::string& file_name,
                                      const std::vector<std::string>& overrides) {
  std::ostringstream text;
  text << "# " << file_name << ", as changed on the command line by:\n";
  for (const std::string& override_text : overrides) {
    // A TOML comment may hold no control character but tab (a newline would end it): each is written as \xNN, so
    // the record stays one line and the stored scene reads back. The text is UTF-8 (apply_scene_overrides refused
    // any that is not).
    std::string line;
    for (const char c : override_text) {
      const unsigned char byte = static_cast<unsigned char>(c);
      if (byte < 0x20 || byte == 0x7f) {
        char escape[8];
        std::snprintf(escape, sizeof escape, "\\x%02x", static_cast<unsigned>(byte));
        line += escape;
      } else {
        line += c;
      }
    }
    text << "#   --set " << line << "\n";
  }
  text << toml::toml_formatter{root} << "\n";
  return text.str();
}

}  // namespace riffle
