#pragma once
// The bed statistics of systems/physics/measures/bed_statistics.hpp written while a run goes: bed_profile.csv (one
// row per time and sub-layer) and class_centroids.csv (one row per time), every output.bed_profile_interval.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "components/model.hpp"
#include "components/world.hpp"
#include "engine/output/output_series.hpp"
#include "systems/physics/measures/bed_statistics.hpp"

namespace riffle {

/// bed_profile.csv (long format: one row per time and layer) and class_centroids.csv (one row per time).
class BedProfileWriter {
 public:
  /// On a resume (fresh_run false) keeps the rows up to world.time.
  BedProfileWriter(const Model& model, const std::filesystem::path& out_dir, const World& world, bool fresh_run);
  void write(const World& world);
  void write_if_due(const World& world) {
    if (schedule_.take(world.time)) write(world);
  }
  bool due(double time) const { return schedule_.due(time); }
  /// Its two files (CsvSeries::set_aside: where a resume copied an earlier file of other columns).
  std::vector<const CsvSeries*> series() const { return {&profile_file_, &centroid_file_}; }

 private:
  const Model* model_;
  std::vector<std::int32_t> classes_;  ///< of the grains at the start (the same on a resume: none come or go)
  double thickness_;
  std::size_t layer_count_;
  IntervalSchedule schedule_;
  CsvSeries profile_file_;
  CsvSeries centroid_file_;
};

}  // namespace riffle
