#include "systems/physics/mps/particle_packing.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "systems/physics/geometry/cell_grid.hpp"
#include "systems/physics/math/counter_random.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "systems/physics/mps/particle_shifting.hpp"

namespace riffle {

namespace {

/// A uniform number in [-1, 1) named by a counter (SplitMix64's mixing, systems/physics/math/counter_random.hpp).
double uniform_symmetric(std::uint64_t counter) {
  return static_cast<double>(splitmix64(counter) >> 11) * 0x1.0p-53 * 2.0 - 1.0;
}

/// Every particle and, along periodic axes, its images within r_e of the box, in a CellGrid of r_e cells: the
/// neighbours of any particle within r_e, across the seams too.
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
      }
    const Vec3 unbounded = Vec3::Constant(1e300);
    grid_.build(points_, 0, points_.size(), radius, -unbounded, unbounded);
  }

  /// Calls visit(owner, offset, distance) for every point within r_e of `position` but the particle `self` itself.
  template <class Visit>
  void for_each_neighbour(std::size_t self, const Vec3& position, Visit&& visit) const {
    grid_.for_each_within(points_, position, radius_, [&](std::uint32_t point) {
      const Vec3 offset = points_[point] - position;
      const double distance = offset.norm();
      if (owners_[point] == self && distance == 0.0) return;
      visit(owners_[point], offset, distance);
    });
  }

 private:
  bool near_box(const PeriodicBox& box, const Vec3& point) const {
    for (int a = 0; a < 3; ++a)
      if (box.periodic[static_cast<std::size_t>(a)] &&
          (point[a] < box.low[a] - radius_ || point[a] > box.low[a] + box.length[a] + radius_))
        return false;
    return true;
  }

  double radius_;
  std::vector<Vec3> points_;
  std::vector<std::uint32_t> owners_;
  CellGrid grid_;
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
