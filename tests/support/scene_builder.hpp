#pragma once
// Scene TOML for the tests, written by calls instead of inline text, so that a test states only what matters to it:
//
//   const std::string scene = SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3})
//       .material("grain", {.density = 2650.0}).tank({.size = {0.1, 0.1, 0.1}, .wall_material = "grain"})
//       .sphere({.position = {0.05, 0.05, 0.05}, .radius = 0.005, .material = "grain"})
//       .fluid({.spacing = 0.01}).fluid_box({0.0, 0.0, 0.0}, {0.1, 0.1, 0.08}).toml();
//
// The builder writes nothing a test did not ask for: every key is written only when it is given, with the value
// given, so the scene means exactly what the same TOML written by hand means (riffle's own defaults apply to the
// rest). Tables are written in the order of the calls, keys in the order of each table's fields below; set() adds
// any other key to the table opened last, table() and array_table() open any other table.
#include <array>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace riffle::test {

using Triple = std::array<double, 3>;

/// One TOML value as the tests write them: a float, an integer, a boolean, a string or an array of those.
class TomlValue {
 public:
  TomlValue(double value) : text_(number(value)) {}
  TomlValue(int value) : text_(std::to_string(value)) {}
  TomlValue(long value) : text_(std::to_string(value)) {}
  TomlValue(unsigned long value) : text_(std::to_string(value)) {}
  TomlValue(bool value) : text_(value ? "true" : "false") {}
  TomlValue(const char* value) : text_(quoted(value)) {}
  TomlValue(const std::string& value) : text_(quoted(value)) {}
  TomlValue(const Triple& value) : text_(list(value.begin(), value.end())) {}
  TomlValue(std::initializer_list<double> values) : text_(list(values.begin(), values.end())) {}
  TomlValue(const std::vector<double>& values) : text_(list(values.begin(), values.end())) {}
  TomlValue(const std::vector<std::string>& values) : text_(list(values.begin(), values.end())) {}
  TomlValue(const std::vector<int>& values) : text_(list(values.begin(), values.end())) {}
  TomlValue(const std::vector<Triple>& values) : text_(list(values.begin(), values.end())) {}
  TomlValue(const std::vector<TomlValue>& values) : text_(list(values.begin(), values.end())) {}
  /// Text written verbatim (an inline table, say).
  static TomlValue verbatim(std::string text) {
    TomlValue value(0);
    value.text_ = std::move(text);
    return value;
  }
  const std::string& text() const { return text_; }

  /// The shortest text that reads back as exactly `value`, always a TOML float, written as the tests write numbers
  /// by hand: "2500.0", "0.0025", one significant digit far from 1 as "1.0e7" or "1.0e-5", and a time step in
  /// seconds, with `seconds`, as "1.0e-3".
  static std::string number(double value, bool seconds = false) {
    if (std::isnan(value)) return "nan";
    if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
    char buffer[64];
    std::string text(buffer, std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::scientific).ptr);
    const std::size_t e = text.find('e');
    const int exponent = std::stoi(text.substr(e + 1));
    if (e <= 2 && (exponent < (seconds ? -2 : -4) || exponent > 5))  // "1e-03": one digit, an optional sign
      return text.substr(0, e) + ".0e" + std::to_string(exponent);
    text.assign(buffer, std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed).ptr);
    if (text.find('.') == std::string::npos) text += ".0";
    return text;
  }

 private:
  static std::string quoted(const std::string& value) {
    std::string text = "\"";
    for (const char c : value) {
      if (c == '"' || c == '\\') text += '\\';
      text += c;
    }
    return text + "\"";
  }
  static std::string item(double value) { return number(value); }
  static std::string item(int value) { return std::to_string(value); }
  static std::string item(const std::string& value) { return quoted(value); }
  static std::string item(const Triple& value) { return list(value.begin(), value.end()); }
  static std::string item(const TomlValue& value) { return value.text_; }
  template <class Iterator>
  static std::string list(Iterator first, Iterator last) {
    std::string text = "[";
    for (Iterator it = first; it != last; ++it) text += (it == first ? "" : ", ") + item(*it);
    return text + "]";
  }

  std::string text_;
};

/// Builds the TOML text of a scene, table by table.
class SceneBuilder {
 public:
  /// The layout of the text: kCompact, every line a header or a key; kSpaced, a blank line before every table (and so
  /// one first), the layout of scenes written by hand, whose line numbers tests quote in expected messages.
  enum Layout { kCompact, kSpaced };
  explicit SceneBuilder(Layout layout = kCompact) : layout_(layout) {}

  template <class T>
  using Opt = std::optional<T>;
  /// An optional point or vector that a braced list {x, y, z} sets.
  struct OptTriple {
    std::optional<Triple> value;
    OptTriple() = default;
    OptTriple(double x, double y, double z) : value(Triple{x, y, z}) {}
    OptTriple(const Triple& triple) : value(triple) {}
  };
  /// A list of names, written only when not empty.
  using Names = std::vector<std::string>;

  struct Run {
    Opt<std::string> name{};
    Opt<double> end_time{};
    Opt<double> dt{};
    Opt<int> solid_substeps{};
    OptTriple gravity{};
  };
  struct Material {
    double density{};
    Opt<double> young_modulus{};
    Opt<double> poisson_ratio{};
  };
  struct Contact {
    Opt<std::string> law{};
    Opt<double> restitution{};
    Opt<double> friction{};
    Opt<double> rolling_friction{};
    Opt<double> max_impact_speed{};
  };
  struct Tank {
    OptTriple size{};
    OptTriple origin{};
    Names open_faces{};
    Names periodic{};
    Opt<std::string> wall_material{};
  };
  struct Motion {
    std::string kind = "sinusoidal";
    Opt<double> amplitude{};
    Opt<double> frequency{};
    Opt<double> ramp_time{};
    OptTriple direction{};
  };
  struct Sphere {
    Triple position{};
    Opt<double> radius{};
    Opt<std::string> material{};
    OptTriple velocity{};
    OptTriple angular_velocity{};
  };
  struct Block {
    Triple min{};
    Triple max{};
    double spacing{};
    double radius{};
    std::string material{};
    OptTriple velocity{};
  };
  /// A generated bed ([[solids.layered_beds]]); its size classes follow as bed_class() calls.
  struct LayeredBed {
    Opt<double> x_min{};
    Opt<double> x_max{};
    Opt<double> y_min{};
    Opt<double> y_max{};
    Opt<double> base{};
    int layers{};
    double layer_thickness{};
    double loose_factor{};
    int seed{};
  };
  /// A box filled at random ([[solids.fills]]); its size classes follow as fill_class() calls.
  struct Fill {
    Triple min{};
    Triple max{};
    int seed{};
  };
  /// One size class of a layered bed or a fill.
  struct GrainClass {
    double diameter{};
    int count{};
    std::string material{};
    Opt<int> size_class{};
    Opt<std::string> arrangement{};
  };
  struct Fluid {
    Opt<double> spacing{};
    Opt<double> kinematic_viscosity{};
    Opt<bool> clamp_negative_pressure{};
  };
  /// Wall particles from `low` to `high`; a lid ("no_slip" or "free_slip") slides along x at `velocity`.
  struct WallBox {
    Triple low{};
    Triple high{};
    Opt<std::string> lid{};
    Opt<double> velocity{};
  };

  SceneBuilder& run(const Run& run) {
    table("run").put("name", run.name, "end_time", run.end_time);
    if (run.dt) set("dt", TomlValue::verbatim(TomlValue::number(*run.dt, true)));
    return put("solid_substeps", run.solid_substeps, "gravity", run.gravity);
  }
  SceneBuilder& material(const std::string& name, const Material& m) {
    return table("materials." + name)
        .put("density", m.density, "young_modulus", m.young_modulus, "poisson_ratio", m.poisson_ratio);
  }
  SceneBuilder& contact(const Contact& c) {
    return table("contact").put("law", c.law, "restitution", c.restitution, "friction", c.friction,
                                "rolling_friction", c.rolling_friction, "max_impact_speed", c.max_impact_speed);
  }
  SceneBuilder& tank(const Tank& t) {
    return table("tank").put("size", t.size, "origin", t.origin, "open_faces", t.open_faces, "periodic", t.periodic,
                             "wall_material", t.wall_material);
  }
  /// [tank.motion]; kind "sinusoidal" unless told.
  SceneBuilder& tank_motion(const Motion& m) {
    return table("tank.motion").put("kind", m.kind, "amplitude", m.amplitude, "frequency", m.frequency,
                                    "ramp_time", m.ramp_time, "direction", m.direction);
  }
  /// [solids] with no keys (set() adds them); sphere(), block(), layered_bed() and fill() open it themselves when it
  /// is not open yet.
  SceneBuilder& solids() { return table("solids"); }
  SceneBuilder& sphere(const Sphere& g) {
    return within_or_open("solids").array_table("solids.spheres").put("position", g.position, "radius", g.radius,
        "material", g.material, "velocity", g.velocity, "angular_velocity", g.angular_velocity);
  }
  SceneBuilder& block(const Block& b) {
    return within_or_open("solids").array_table("solids.blocks").put("min", b.min, "max", b.max, "spacing", b.spacing,
        "radius", b.radius, "material", b.material, "velocity", b.velocity);
  }
  SceneBuilder& layered_bed(const LayeredBed& b) {
    return within_or_open("solids").array_table("solids.layered_beds").put("x_min", b.x_min, "x_max", b.x_max,
        "y_min", b.y_min, "y_max", b.y_max, "base", b.base, "layers", b.layers, "layer_thickness", b.layer_thickness,
        "loose_factor", b.loose_factor, "seed", b.seed);
  }
  SceneBuilder& bed_class(const GrainClass& grains) { return grain_class("solids.layered_beds.classes", grains); }
  SceneBuilder& fill(const Fill& f) {
    return within_or_open("solids").array_table("solids.fills").put("min", f.min, "max", f.max, "seed", f.seed);
  }
  SceneBuilder& fill_class(const GrainClass& grains) { return grain_class("solids.fills.classes", grains); }
  SceneBuilder& fluid(const Fluid& f) {
    return table("fluid").put("spacing", f.spacing, "kinematic_viscosity", f.kinematic_viscosity,
                              "clamp_negative_pressure", f.clamp_negative_pressure);
  }
  /// [[fluid.boxes]]: water from `low` to `high`, at rest unless `velocity` is given.
  SceneBuilder& fluid_box(const Triple& low, const Triple& high, const OptTriple& velocity = {}) {
    return within_or_open("fluid").array_table("fluid.boxes").put("low", low, "high", high, "velocity", velocity);
  }
  SceneBuilder& wall_box(const WallBox& w) {
    return within_or_open("fluid").array_table("fluid.wall_boxes")
        .put("low", w.low, "high", w.high, "lid", w.lid, "velocity", w.velocity);
  }
  /// The text continues a [table] written elsewhere (a test appends it): sphere(), block(), fluid_box() and the
  /// other calls that open their parent table then do not open it again.
  SceneBuilder& within(const std::string& table) {
    headers_.push_back("[" + table + "]");
    return *this;
  }
  /// [fluid.body_force] of `kind` (set() adds its other keys).
  SceneBuilder& body_force(const std::string& kind) { return table("fluid.body_force").set("kind", kind); }
  /// [coupling] with no keys (set() adds them).
  SceneBuilder& coupling() { return table("coupling"); }
  /// [output] with no keys (set() adds them).
  SceneBuilder& output() { return table("output"); }
  /// [[output.probes]] of `kind` (set() adds its other keys).
  SceneBuilder& probe(const std::string& kind) { return array_table("output.probes").set("kind", kind); }

  /// Opens [header] (any table).
  SceneBuilder& table(const std::string& header) { return open("[" + header + "]"); }
  /// Opens [[header]] (one more element of an array of tables).
  SceneBuilder& array_table(const std::string& header) { return open("[[" + header + "]]"); }
  /// key = value in the table opened last.
  SceneBuilder& set(const std::string& key, const TomlValue& value) {
    text_ += key + " = " + value.text() + "\n";
    return *this;
  }
  /// TOML text appended as it is (a test's deliberately odd line, say).
  SceneBuilder& verbatim(const std::string& text) {
    text_ += text;
    return *this;
  }

  /// The scene's TOML text.
  std::string toml() const { return text_; }
  operator std::string() const { return text_; }

 private:
  SceneBuilder& open(const std::string& header) {
    text_ += (layout_ == kSpaced ? "\n" : "") + header + "\n";
    headers_.push_back(header);
    return *this;
  }
  /// Opens [name] unless it is open already (or within() said the text continues it).
  SceneBuilder& within_or_open(const std::string& name) {
    for (const std::string& header : headers_)
      if (header == "[" + name + "]") return *this;
    return table(name);
  }
  SceneBuilder& grain_class(const std::string& header, const GrainClass& g) {
    return array_table(header).put("diameter", g.diameter, "count", g.count, "material", g.material,
                                   "size_class", g.size_class, "arrangement", g.arrangement);
  }
  /// key = value for each given pair, in order: optional values only when set, lists of names only when not empty.
  SceneBuilder& put() { return *this; }
  template <class T, class... Rest>
  SceneBuilder& put(const char* key, const T& value, const Rest&... rest) {
    put_one(key, value);
    return put(rest...);
  }
  template <class T>
  void put_one(const char* key, const T& value) {
    set(key, value);
  }
  template <class T>
  void put_one(const char* key, const Opt<T>& value) {
    if (value) set(key, *value);
  }
  void put_one(const char* key, const OptTriple& value) { put_one(key, value.value); }
  void put_one(const char* key, const Names& names) {
    if (!names.empty()) set(key, names);
  }

  Layout layout_;
  std::string text_;
  std::vector<std::string> headers_;
};

}  // namespace riffle::test
