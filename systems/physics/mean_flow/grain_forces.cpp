#include "systems/physics/mean_flow/grain_forces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace riffle {

namespace {

double horizontal_square(const Vec3& v) { return v.x() * v.x() + v.y() * v.y(); }
}  // namespace

double shear_lift(double density, double lift_coefficient, double radius, const Vec3& top_relative,
                  const Vec3& bottom_relative) {
  return 0.5 * density * lift_coefficient * std::numbers::pi * radius * radius *
         (horizontal_square(top_relative) - horizontal_square(bottom_relative));
}

double TurbulentShear::friction_velocity() const { return std::sqrt(std::hypot(stress_x, stress_y)); }

TurbulentShear turbulent_shear_at(const ColumnGrid& grid, const MeanFlowColumn& column, const ColumnEnds& ends_x,
                                  const ColumnEnds& ends_y, double z) {
  const auto at_face = [&](std::size_t j) {
    TurbulentShear face;
    const double gx = face_gradient(grid, column.velocity_x, ends_x, j);
    const double gy = face_gradient(grid, column.velocity_y, ends_y, j);
    const double eddy = column.eddy_viscosity[j];
    face.stress_x = eddy * gx;
    face.stress_y = eddy * gy;
    face.shear_rate = std::hypot(gx, gy);
    return face;
  };
  if (std::isnan(z)) return {};  // a height that is not a number: no turbulence read (and no index made of it)
  const double position = std::clamp((z - grid.bottom) / grid.cell_height, 0.0, static_cast<double>(grid.cells));
  const auto below = std::min(static_cast<std::size_t>(position), grid.cells - 1);
  const double weight = position - static_cast<double>(below);
  const TurbulentShear low = at_face(below), high = at_face(below + 1);
  TurbulentShear shear;
  shear.stress_x = (1.0 - weight) * low.stress_x + weight * high.stress_x;
  shear.stress_y = (1.0 - weight) * low.stress_y + weight * high.stress_y;
  shear.shear_rate = (1.0 - weight) * low.shear_rate + weight * high.shear_rate;
  return shear;
}

double lagrangian_time_scale(double shear_rate, double c0, const TurbulenceIntensities& intensities) {
  if (!(shear_rate > 0.0)) return std::numeric_limits<double>::infinity();
  return 2.0 * intensities.vertical * intensities.vertical / (c0 * shear_rate);
}

Vec3 advance_langevin(const Vec3& state, double dt, double time_scale, const Vec3& normals) {
  if (!(dt > 0.0)) return state;
  const double memory = std::exp(-dt / time_scale);  // 1 for an infinite time scale: the state held
  return memory * state + std::sqrt(std::max(0.0, 1.0 - memory * memory)) * normals;
}

Vec3 fluctuation_velocity(const Vec3& state, const TurbulentShear& shear, const TurbulenceIntensities& intensities) {
  const double stress = std::hypot(shear.stress_x, shear.stress_y);
  if (!(stress > 0.0)) return Vec3::Zero();
  const double friction = std::sqrt(stress);
  const double along_x = shear.stress_x / stress, along_y = shear.stress_y / stress;  // the shear's direction
  const double correlation = -1.0 / (intensities.streamwise * intensities.vertical);
  const double along = intensities.streamwise * friction *
                       (correlation * state.z() + std::sqrt(1.0 - correlation * correlation) * state.x());
  const double across = intensities.spanwise * friction * state.y();
  return Vec3(along * along_x - across * along_y, along * along_y + across * along_x,
              intensities.vertical * friction * state.z());
}

}  // namespace riffle
