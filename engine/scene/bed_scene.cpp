#include "engine/scene/bed_scene.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>

#include "engine/setup/budget.hpp"
#include "engine/scene/scene.hpp"
#include "engine/setup/bed_generation.hpp"

namespace riffle {

namespace {

void read_grain_class(TableReader& reader, const Model& model, GrainClassSpec& grains) {
  grains.diameter = reader.number("diameter", std::nullopt, "m", Bounds::positive());
  grains.count = reader.integer("count", std::nullopt, 0, kBedMaxSpheres);
  grains.material = read_material(model, reader, "material");
  grains.size_class = static_cast<std::int32_t>(reader.integer("size_class", 0, 0, 1000));
}

/// Reports a generator's complaint at the key it names, in the bed's or fill's table or one of its classes.
void report(const BedGenerationError& error, TableReader& table, std::vector<TableReader>& classes) {
  if (error.class_index() && *error.class_index() < classes.size())
    classes[*error.class_index()].problem(error.key(), error.what());
  else
    table.problem(error.key(), error.what());
}

/// Whether the scene's grains, with these classes added, stay within the scene's grain cap and memory limit (each
/// class is capped alone; this is the total).
template <class ClassSpec>
bool scene_has_room(TableReader& table, const Model& model, const std::vector<ClassSpec>& classes) {
  double total = static_cast<double>(scene_sphere_count(model.solids));
  for (const ClassSpec& grains : classes) total += static_cast<double>(grains.count);
  const std::string problem = grain_count_problem(model, total);
  if (!problem.empty()) table.problem("classes", problem);
  return problem.empty();
}

/// Where the table's and its classes' keys were given, for a problem the generator finds at set-up.
SceneTableSource table_source(const TableReader& table, std::initializer_list<const char*> keys,
                              const std::vector<TableReader>& classes,
                              std::initializer_list<const char*> class_keys) {
  SceneTableSource source;
  source.table_prefix = table.problem_prefix("");
  for (const char* key : keys) source.key_prefix[key] = table.problem_prefix(key);
  for (std::size_t k = 0; k < classes.size(); ++k)
    for (const char* key : class_keys)
      source.key_prefix["classes[" + std::to_string(k) + "]." + key] = classes[k].problem_prefix(key);
  return source;
}

std::string span_text(double low, double high) { return format_number(low) + " to " + format_number(high); }

void read_layered_bed(TableReader& bed, Model& model, bool tank_known) {
  const std::size_t problems_before = bed.problem_count();
  const Vec3 tank_low = model.tank.origin;
  const Vec3 tank_high = model.tank.origin + model.tank.size;
  LayeredBedSpec spec;
  // The region defaults to the whole tank floor.
  spec.x_min = bed.number("x_min", tank_low.x(), "m", Bounds::any());
  spec.x_max = bed.number("x_max", tank_high.x(), "m", Bounds::any());
  spec.y_min = bed.number("y_min", tank_low.y(), "m", Bounds::any());
  spec.y_max = bed.number("y_max", tank_high.y(), "m", Bounds::any());
  spec.base = bed.number("base", tank_low.z(), "m", Bounds::any());
  spec.layers = bed.integer("layers", std::nullopt, 1, 1000);
  spec.layer_thickness = bed.number("layer_thickness", std::nullopt, "m", Bounds::positive());
  spec.loose_factor = bed.number("loose_factor", spec.loose_factor, "1", Bounds::closed(1.0, 1000.0));
  spec.seed = static_cast<std::uint64_t>(bed.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  std::vector<TableReader> classes = bed.tables("classes");
  for (TableReader& reader : classes) {
    BedClassSpec grains;
    read_grain_class(reader, model, grains);
    grains.arrangement = reader.choice("arrangement", "random", {"regular", "random"}) == "regular"
                             ? BedArrangement::kRegular
                             : BedArrangement::kRandom;
    reader.finish();
    spec.classes.push_back(grains);
  }
  if (classes.empty()) bed.problem("classes", "expected at least one [[" + bed.full_key("classes") + "]] table");
  bed.finish();
  // A bed with a bad key cannot be laid out meaningfully, and without a valid tank neither can its region be judged.
  if (bed.problem_count() != problems_before || !tank_known) return;

  const std::size_t geometry_before = bed.problem_count();
  if (!(spec.x_max > spec.x_min)) bed.problem("x_max", "x_max must be greater than x_min");
  if (!(spec.y_max > spec.y_min)) bed.problem("y_max", "y_max must be greater than y_min");
  const std::string tank_x = " (the tank spans x from " + span_text(tank_low.x(), tank_high.x()) + ")";
  const std::string tank_y = " (the tank spans y from " + span_text(tank_low.y(), tank_high.y()) + ")";
  const std::string tank_z = " (the tank spans z from " + span_text(tank_low.z(), tank_high.z()) + ")";
  if (spec.x_min < tank_low.x()) bed.problem("x_min", "the region must lie inside the tank" + tank_x);
  if (spec.x_max > tank_high.x()) bed.problem("x_max", "the region must lie inside the tank" + tank_x);
  if (spec.y_min < tank_low.y()) bed.problem("y_min", "the region must lie inside the tank" + tank_y);
  if (spec.y_max > tank_high.y()) bed.problem("y_max", "the region must lie inside the tank" + tank_y);
  if (spec.base < tank_low.z() || spec.base >= tank_high.z())
    bed.problem("base", "the base must lie inside the tank" + tank_z);
  else if (spec.slab_bottom(spec.layers) > tank_high.z())
    bed.problem("loose_factor", "the loosened bed (layers x layer_thickness x loose_factor = " +
                                    format_number(spec.slab_bottom(spec.layers) - spec.base) + " m above the base) "
                                    "rises above the tank" + tank_z);
  if (bed.problem_count() != geometry_before) return;

  if (!scene_has_room(bed, model, spec.classes)) return;
  try {
    check_layered_bed(spec);  // all but a jam of the random classes, which only generating shows
  } catch (const BedGenerationError& error) {
    report(error, bed, classes);
    return;
  }
  spec.source = table_source(bed,
                             {"x_min", "x_max", "y_min", "y_max", "base", "layers", "layer_thickness", "loose_factor",
                              "seed", "classes"},
                             classes, {"diameter", "count", "material", "size_class", "arrangement"});
  model.solids.layered_beds.push_back(std::move(spec));
}

void read_fill(TableReader& fill, Model& model, bool tank_known) {
  const std::size_t problems_before = fill.problem_count();
  FillSpec spec;
  spec.min = fill.vec3("min", std::nullopt, "m", Bounds::any());
  spec.max = fill.vec3("max", std::nullopt, "m", Bounds::any());
  spec.seed = static_cast<std::uint64_t>(fill.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  std::vector<TableReader> classes = fill.tables("classes");
  for (TableReader& reader : classes) {
    GrainClassSpec grains;
    read_grain_class(reader, model, grains);
    reader.finish();
    spec.classes.push_back(grains);
  }
  if (classes.empty()) fill.problem("classes", "expected at least one [[" + fill.full_key("classes") + "]] table");
  fill.finish();
  if (fill.problem_count() != problems_before || !tank_known) return;
  if (((spec.max - spec.min).array() <= 0.0).any()) {
    fill.problem("max", "every component of max must be > the one of min");
    return;
  }
  // The spheres must fit in the tank at rest, so the part of the box outside the tank is left empty.
  const Vec3 low = spec.min.cwiseMax(model.tank.origin);
  const Vec3 high = spec.max.cwiseMin(model.tank.origin + model.tank.size);
  if (((high - low).array() <= 0.0).any()) {
    fill.problem("min", "the box does not overlap the tank (which spans origin to origin + size)");
    return;
  }
  spec.min = low;
  spec.max = high;
  if (!scene_has_room(fill, model, spec.classes)) return;
  try {
    check_fill(spec);  // all but a jam, which only generating shows
  } catch (const BedGenerationError& error) {
    report(error, fill, classes);
    return;
  }
  spec.source = table_source(fill, {"min", "max", "seed", "classes"}, classes,
                             {"diameter", "count", "material", "size_class"});
  model.solids.fills.push_back(std::move(spec));
}

}  // namespace

void read_bed_generators(TableReader& solids, Model& model) {
  // Without a valid tank size every region would also be reported as outside the tank, burying the real problem.
  const bool tank_known = (model.tank.size.array() > 0.0).all();
  for (TableReader& bed : solids.tables("layered_beds")) read_layered_bed(bed, model, tank_known);
  for (TableReader& fill : solids.tables("fills")) read_fill(fill, model, tank_known);
}

}  // namespace riffle
