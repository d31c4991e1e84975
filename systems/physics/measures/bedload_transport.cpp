#include "systems/physics/measures/bedload_transport.hpp"

#include <cmath>

#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/measures/bedload.hpp"
#include "systems/physics/mean_flow/column_model.hpp"

namespace riffle {

ShieldsGrain shields_grain(const Model& model, const Solids& grains) {
  const MeanFlowModel& flow = model.mean_flow;
  if (flow.shields_number > 0.0) return {flow.shields_diameter, flow.shields_density};
  double diameters = 0.0, volume = 0.0, mass = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < grains.size(); ++i) {
    if (grains.fixed[i]) continue;
    diameters += 2.0 * grains.radius[i];
    volume += grain_volume(grains.radius[i]);
    mass += grains.mass[i];
    ++count;
  }
  if (count == 0) return {};
  return {diameters / static_cast<double>(count), mass / volume};
}

BedloadTransport bedload_transport(const Model& model, const Solids& grains, const MeanFlowColumn& column,
                                   const ShieldsGrain& grain, double threshold) {
  const MeanFlowModel& flow = model.mean_flow;
  const double gravity = std::abs(model.gravity.z());
  BedloadTransport out;
  out.bed_surface = column.bed_surface;
  out.bed_stress = column_bed_stress(flow, column);
  out.shields = shields_number(out.bed_stress, grain.density, flow.density, gravity, grain.diameter);
  out.friction_velocity = std::sqrt(std::abs(out.bed_stress) / flow.density);
  const double area = model.tank.size.x() * model.tank.size.y();
  std::size_t mobile = 0;
  double speed = 0.0, height = 0.0, speed_above = 0.0;
  for (std::size_t i = 0; i < grains.size(); ++i) {
    if (grains.fixed[i]) continue;
    ++mobile;
    out.flux += grain_volume(grains.radius[i]) * grains.velocity[i].x();
    if (grains.velocity[i].norm() > threshold) {
      ++out.moving;
      speed += grains.velocity[i].x();
      height += grains.position[i].z() - column.bed_surface;
      if (grains.position[i].z() > column.bed_surface) {
        ++out.moving_above_bed;
        speed_above += grains.velocity[i].x();
      }
    }
  }
  out.flux /= area;
  out.flux_star = einstein_number(out.flux, grain.diameter, grain.density / flow.density, gravity);
  if (mobile > 0) out.moving_fraction = static_cast<double>(out.moving) / static_cast<double>(mobile);
  if (out.moving > 0) {
    out.moving_speed = speed / static_cast<double>(out.moving);
    out.moving_height = height / static_cast<double>(out.moving);
  }
  if (out.moving_above_bed > 0) out.moving_above_bed_speed = speed_above / static_cast<double>(out.moving_above_bed);
  return out;
}

}  // namespace riffle
