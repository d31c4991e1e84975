#include "systems/physics/mps/particle_packing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "systems/physics/mps/mps_kernel.hpp"
#include "systems/physics/mps/particle_shifting.hpp"

namespace riffle {

namespace {

/// SplitMix64 (Steele, Lea & Flood 2014): a uniform number in [-1, 1) from a counter.
double uniform_symmetric(std::uint64_t counter) {
  std::uint64_t z = counter + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53 * 2.0 - 1.0;
}

/// A cell list of every particle and, along periodic axes, of the images within r_e of the box: the neighbours
/// of any particle are in its own and the 26 adjacent cells.
class NeighbourCells {
 public:
  NeighbourCells(const std::vector<Vec3>& positions, const PeriodicBox& box, double radius) : radius_(radius) {
    const std::vector<Vec3> shifts = periodic_image_shifts(box);
    for (std::size_t i = 0; i < positions.size(); ++i)
      for (const Vec3& shift : shifts) {
        const Vec3 image = positions[i] + shift;
        if (!shift.isZero() && !near_box(box, image)) continue;
        points_.push_back(image);
        owners_.push_back(static_cast<std::uint32_t>(i));
        cells_[key(image)].push_back(static_cast<std::uint32_t>(points_.size() - 1));
      }
  }

  /// Calls visit(owner, offset) for every point within r_e of `position` but the particle `self` itself.
  template <class Visit>
  void for_each_neighbour(std::size_t self, const Vec3& position, Visit&& visit) const {
    const std::array<std::int64_t, 3> centre = cell_of(position);
    for (std::int64_t dz = -1; dz <= 1; ++dz)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
          const auto found = cells_.find(pack({centre[0] + dx, centre[1] + dy, centre[2] + dz}));
          if (found == cells_.end()) continue;
          for (const std::uint32_t point : found->second) {
            const Vec3 offset = points_[point] - position;
            const double distance = offset.norm();
            if (distance >= radius_ || (owners_[point] == self && distance == 0.0)) continue;
            visit(owners_[point], offset, distance);
          }
        }
  }

 private:
  bool near_box(const PeriodicBox& box, const Vec3& point) const {
    for (int a = 0; a < 3; ++a)
      if (box.periodic[static_cast<std::size_t>(a)] &&
          (point[a] < box.low[a] - radius_ || point[a] > box.low[a] + box.length[a] + radius_))
        return false;
    return true;
  }
  std::array<std::int64_t, 3> cell_of(const Vec3& point) const {
    return {static_cast<std::int64_t>(std::floor(point.x() / radius_)),
            static_cast<std::int64_t>(std::floor(point.y() / radius_)),
            static_cast<std::int64_t>(std::floor(point.z() / radius_))};
  }
  static std::uint64_t pack(const std::array<std::int64_t, 3>& cell) {
    // 21 bits per axis: cells of r_e over any tank riffle can hold (the budget bounds the particle count).
    const auto part = [](std::int64_t c) { return static_cast<std::uint64_t>(c + (1 << 20)) & 0x1FFFFFull; };
    return part(cell[0]) | (part(cell[1]) << 21) | (part(cell[2]) << 42);
  }
  std::uint64_t key(const Vec3& point) const { return pack(cell_of(point)); }

  double radius_;
  std::vector<Vec3> points_;
  std::vector<std::uint32_t> owners_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

/// n_i / n0 and grad C_i of every particle in `which`.
void concentration(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& which,
                   const PeriodicBox& box, const WendlandKernel& kernel, double n0, std::vector<double>& ratio,
                   std::vector<Vec3>& gradient) {
  const NeighbourCells cells(positions, box, kernel.effective_radius);
  ratio.assign(which.size(), 0.0);
  gradient.assign(which.size(), Vec3::Zero());
  for (std::size_t k = 0; k < which.size(); ++k) {
    double n = 0.0;
    Vec3 sum = Vec3::Zero();
    cells.for_each_neighbour(which[k], positions[which[k]], [&](std::uint32_t, const Vec3& offset, double distance) {
      n += kernel.weight_inside(distance);
      sum += concentration_gradient_term(kernel.derivative_over_distance(distance), offset);
    });
    ratio[k] = n / n0;
    gradient[k] = sum / n0;
  }
}

double rms_deviation(const std::vector<double>& ratio) {
  if (ratio.empty()) return 0.0;
  double sum = 0.0;
  for (const double r : ratio) sum += (r - 1.0) * (r - 1.0);
  return std::sqrt(sum / static_cast<double>(ratio.size()));
}

}  // namespace

PackingReport pack_particles(std::vector<Vec3>& positions, const std::vector<char>& movable, const PeriodicBox& box,
                             const PackingSettings& settings) {
  PackingReport report;
  const double l0 = settings.spacing;
  const WendlandKernel kernel(settings.effective_radius);
  const double n0 = lattice_constants(3, l0, settings.effective_radius).number_density;
  std::vector<std::uint32_t> candidates;
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (movable[i]) candidates.push_back(static_cast<std::uint32_t>(i));
  std::vector<double> ratio;
  std::vector<Vec3> gradient;
  concentration(positions, candidates, box, kernel, n0, ratio, gradient);
  // A complete kernel on the lattice: n = n0 to rounding. Within r_e of a free surface n < n0: those stay put, so
  // that the surface stays where the scene put it.
  std::vector<std::uint32_t> moved;
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (std::abs(ratio[k] - 1.0) < 1e-9) moved.push_back(candidates[k]);
  report.moved = moved.size();
  if (moved.empty()) return report;
  const std::vector<Vec3> sites = [&] {
    std::vector<Vec3> out;
    for (const std::uint32_t i : moved) out.push_back(positions[i]);
    return out;
  }();
  for (std::size_t k = 0; k < moved.size(); ++k) {
    Vec3& position = positions[moved[k]];
    for (int a = 0; a < 3; ++a)
      position[a] += settings.jitter * l0 * uniform_symmetric(settings.seed ^ (3 * static_cast<std::uint64_t>(moved[k]) + a) * 0xD1B54A32D192ED03ull);
    position = box.wrap(position);
  }
  concentration(positions, moved, box, kernel, n0, ratio, gradient);
  report.spread_after_offset = rms_deviation(ratio);
  const double diffusivity = settings.diffusivity * l0 * l0, cap = settings.max_shift * l0;
  for (int iteration = 0; iteration < settings.iterations; ++iteration) {
    // Jacobi: every shift from the same arrangement, then all applied.
    for (std::size_t k = 0; k < moved.size(); ++k)
      positions[moved[k]] = box.wrap(positions[moved[k]] + fickian_shift(diffusivity, gradient[k], cap));
    concentration(positions, moved, box, kernel, n0, ratio, gradient);
  }
  report.spread_after_packing = rms_deviation(ratio);
  double offset = 0.0;
  for (std::size_t k = 0; k < moved.size(); ++k)
    offset += nearest_image_difference(box, positions[moved[k]] - sites[k]).norm();
  report.mean_offset = offset / static_cast<double>(moved.size()) / l0;
  return report;
}

}  // namespace riffle
