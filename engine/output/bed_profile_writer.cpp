#include "engine/output/bed_profile_writer.hpp"

#include <optional>
#include <string>

namespace riffle {

namespace {
std::string centroid_header(const std::vector<std::int32_t>& classes) {
  std::string header = "time_s,t_over_T";
  for (std::int32_t size_class : classes) header += ",class_" + std::to_string(size_class) + "_centroid_m";
  return header;
}
}  // namespace

BedProfileWriter::BedProfileWriter(const Model& model, const std::filesystem::path& out_dir, const World& world,
                                   bool fresh_run)
    : model_(&model),
      classes_(world.solids ? size_classes(*world.solids) : std::vector<std::int32_t>{}),
      thickness_(world.solids ? bed_layer_thickness(model, *world.solids) : 0.0),
      layer_count_(bed_layer_count(model, thickness_)),
      schedule_(model.output.bed_profile_interval, model.dt, world.time),
      profile_file_(out_dir / "bed_profile.csv",
                    "time_s,t_over_T,layer,z_low_m,z_high_m,grains,contacts,coordination_number,"
                    "mean_dimensionless_overlap",
                    fresh_run ? std::nullopt : std::optional<double>(world.time)),
      centroid_file_(out_dir / "class_centroids.csv", centroid_header(classes_),
                     fresh_run ? std::nullopt : std::optional<double>(world.time)) {}

void BedProfileWriter::write(const World& world) {
  if (!world.solids) return;
  const double floor_z = tank_floor_z(*model_, world);
  std::string time = format_exact(world.time);
  append_field(time, format_value(oscillation_periods(*model_, world.time)));
  const BedProfile profile = bed_profile(*world.solids, world.contacts ? &*world.contacts : nullptr, floor_z,
                                         thickness_, layer_count_);
  std::string rows;
  for (std::size_t k = 0; k < profile.layers.size(); ++k) {
    const BedLayer& layer = profile.layers[k];
    rows += time;
    append_field(rows, std::to_string(k));
    append_field(rows, format_value(layer.z_low));
    append_field(rows, format_value(layer.z_high));
    append_field(rows, std::to_string(layer.grains));
    if (profile.contacts_known) {
      append_field(rows, std::to_string(layer.contacts));
      append_field(rows, format_value(layer.coordination_number()));
      append_field(rows, format_value(layer.mean_dimensionless_overlap()));
    } else {
      rows += ",,,";  // the contact list does not exist yet (before the first step): unknown, not zero
    }
    rows += '\n';
  }
  profile_file_.write_rows(rows);
  std::string row = time;
  for (const ClassCentroid& centroid : class_centroids(*world.solids, classes_, floor_z))
    append_field(row, format_value(centroid.height));
  centroid_file_.write_row(row);
}

}  // namespace riffle
