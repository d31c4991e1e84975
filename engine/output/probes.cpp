#include "engine/output/probes.hpp"

#include "systems/physics/math/not_a_number.hpp"
#include "systems/physics/mean_flow/column_model.hpp"
#include "systems/physics/mean_flow/column.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "systems/physics/measures/bed_statistics.hpp"
#include "systems/physics/measures/bedload.hpp"
#include "systems/physics/mps/hydrostatic.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "systems/physics/measures/pressure_sensor.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

namespace fs = std::filesystem;

GrainSlotMap::GrainSlotMap(std::vector<EntityId> ids) : ids_(std::move(ids)), slots_(ids_.size(), kNone) {}

bool GrainSlotMap::refresh(const Solids& solids) {
  bool current = true;
  for (std::size_t k = 0; k < ids_.size() && current; ++k)
    current = slots_[k] < solids.size() && solids.id[slots_[k]] == ids_[k];
  if (current) return false;
  std::unordered_map<EntityId, std::size_t> wanted;
  for (std::size_t k = 0; k < ids_.size(); ++k) wanted.emplace(ids_[k], k);
  std::fill(slots_.begin(), slots_.end(), kNone);
  for (std::size_t slot = 0; slot < solids.size(); ++slot)
    if (const auto found = wanted.find(solids.id[slot]); found != wanted.end()) slots_[found->second] = slot;
  return true;
}

std::string probe_header(const ProbeModel& probe, const World& world) {
  std::string header = "time_s,step";
  if (probe.kind == ProbeModel::Kind::kGrains) {
    for (EntityId id : probe.ids)
      for (const char* column : kGrainProbeColumns) header += ",grain" + std::to_string(id) + "_" + column;
  } else if (probe.kind == ProbeModel::Kind::kWallForces) {
    if (world.walls)
      for (const std::string& name : world.walls->name)
        for (const char* column : {"fx_N", "fy_N", "fz_N"}) header += "," + name + "_" + column;
  } else if (probe.kind == ProbeModel::Kind::kFluidPressure) {
    for (std::size_t k = 0; k < probe.points.size(); ++k) header += ",p" + std::to_string(k) + "_Pa";
  } else if (probe.kind == ProbeModel::Kind::kWaveGauge) {
    for (std::size_t k = 0; k < probe.points.size(); ++k) header += ",gauge" + std::to_string(k) + "_z_m";
  } else if (probe.kind == ProbeModel::Kind::kPressureTransducer) {
    for (std::size_t k = 0; k < probe.points.size(); ++k) header += ",p" + std::to_string(k) + "_Pa";
  } else if (probe.kind == ProbeModel::Kind::kSurgeFront) {
    header += ",front_m";
  } else if (probe.kind == ProbeModel::Kind::kMovingFraction || probe.kind == ProbeModel::Kind::kBedloadFlux ||
             probe.kind == ProbeModel::Kind::kBedShearStress) {
    const std::vector<std::int32_t> classes = world.solids ? size_classes(*world.solids) : std::vector<std::int32_t>{};
    auto per_class = [&](const std::string& suffix, bool all) {
      for (std::int32_t size_class : classes) header += ",class_" + std::to_string(size_class) + "_" + suffix;
      if (all) header += ",all_" + suffix;
    };
    if (probe.kind == ProbeModel::Kind::kMovingFraction) {
      per_class("moving_fraction", true);
    } else if (probe.kind == ProbeModel::Kind::kBedloadFlux) {
      per_class("q_m2_s", true);
      per_class("q_mean_m2_s", true);
    } else {
      header += ",grains_fx_N,floor_fx_N,tau_b_Pa";
      if (probe.lid) header += ",tau_lid_Pa";
      per_class("diameter_m", false);
      per_class("shields_b", false);
      if (probe.lid) per_class("shields_lid", false);
    }
  } else if (probe.kind == ProbeModel::Kind::kPackingDensity) {
    header += ",lambda,top_layer_grains";
  } else if (probe.kind == ProbeModel::Kind::kVelocityProfile) {
    header += ",layer,z_low_m,z_high_m,fluid_particles,fluid_ux_m_s,grain_ux_m_s,solid_fraction";
  } else if (probe.kind == ProbeModel::Kind::kMeanFlowProfile) {
    header += ",cell,z_m,ux_m_s,uy_m_s,solid_fraction,eddy_viscosity_m2_s,shear_stress_Pa";
  } else if (probe.kind == ProbeModel::Kind::kBedloadTransport) {
    header += ",shields,u_star_m_s,tau_b_Pa,bed_surface_m,q_m2_s,q_star,moving_fraction,moving_ux_over_u_star,"
              "moving_height_over_d,moving_grains,body_force_m_s2,moving_above_bed_ux_over_u_star,moving_above_bed_grains";
  } else if (probe.kind == ProbeModel::Kind::kDrivenFlow) {
    header += ",body_force_m_s2,bulk_velocity_m_s";
    for (std::size_t k = 0; k < probe.lid_areas.size(); ++k)
      for (const char* column : {"fx_N", "fy_N", "fz_N", "shear_Pa"}) header += ",lid" + std::to_string(k) + "_" + column;
  } else {
    header += ",fluid_particles,volume_m3,kinetic_energy_J,max_speed_m_s,mean_density_ratio,surface_particles,"
              "ppe_iterations,ppe_residual,removed_particles,removed_mass_kg,removed_volume_m3,removed_left_domain,"
              "removed_lone_droplets";
  }
  return header;
}

ProbeWriter::ProbeWriter(const Model& model, const ProbeModel& probe, const fs::path& out_dir, const World& world,
                         bool fresh_run)
    : model_(&model),
      probe_(probe),
      classes_(world.solids ? grain_classes(*world.solids) : GrainClasses{}),
      shear_(probe.kind == ProbeModel::Kind::kBedShearStress && model.fluid.enabled ? shear_settings(model)
                                                                                   : ShearSettings{}),
      shields_grain_(probe.kind == ProbeModel::Kind::kBedloadTransport && world.solids
                         ? shields_grain(model, *world.solids)
                         : ShieldsGrain{}),
      profile_layers_(probe.kind == ProbeModel::Kind::kVelocityProfile && probe.layer_thickness > 0.0
                          ? static_cast<std::size_t>(std::clamp(
                                std::ceil(model.tank.size.z() / probe.layer_thickness * (1.0 - 1e-12)), 1.0, 1e5))
                          : 0),
      window_(probe.kind == ProbeModel::Kind::kPressureTransducer && probe.average_window > 0.0
                  ? std::optional<WindowMean>(std::in_place, probe.average_window)
                  : std::nullopt),
      fluid_(model.fluid.enabled ? fluid_probe_settings(model) : FluidProbeSettings{}),
      slots_(probe.ids),
      schedule_(probe.interval, model.dt, world.time),
      file_(out_dir / probe.file, probe_header(probe, world),
            fresh_run ? std::nullopt : std::optional<double>(world.time)) {
  if (probe.kind == ProbeModel::Kind::kPressureTransducer && probe.normals.size() != probe.points.size())
    throw std::invalid_argument("ProbeWriter: a pressure_transducer needs one wall normal per point");
}

std::vector<double> ProbeWriter::transducer_readings(const World& world) const {
  if (!world.fluid) return {};
  const TankMotion tank = world.tank_motion.value_or(TankMotion{});
  std::vector<double> readings;
  for (std::size_t k = 0; k < probe_.points.size(); ++k)
    readings.push_back(
        pressure_transducer_reading(*world.fluid, fluid_, tank, probe_.points[k], probe_.normals[k], probe_.diameter));
  return readings;
}

void ProbeWriter::take_reading(const World& world) {
  if (!world.fluid || window_->latest_time() == world.time) return;
  window_->add(world.time, transducer_readings(world));
}

std::string ProbeWriter::bedload_fields(const World& world) {
  std::string fields;
  const TankFrame frame = tank_frame(*model_, world.tank_motion ? &*world.tank_motion : nullptr);
  auto append_values = [&fields](const std::vector<double>& values) {
    for (double value : values) append_field(fields, format_value(value));
  };
  const Solids* solids = world.solids ? &*world.solids : nullptr;
  const std::size_t classes = classes_.classes.size();
  switch (probe_.kind) {
    case ProbeModel::Kind::kMovingFraction:
      if (solids)
        append_values(moving_fractions(*solids, classes_, frame, probe_.threshold));
      else
        fields.append(classes + 1, ',');
      break;
    case ProbeModel::Kind::kPackingDensity: {
      if (!solids) {
        fields += ",,";
        break;
      }
      TopLayerSettings settings;
      settings.threshold = probe_.threshold;
      settings.depth = probe_.layer_depth;
      if (!std::isnan(probe_.layer_bottom)) settings.bottom = probe_.layer_bottom;
      const PackingDensity packing = packing_density(*solids, frame, settings);
      append_field(fields, format_value(packing.lambda));
      append_field(fields, std::to_string(packing.grains));
      break;
    }
    case ProbeModel::Kind::kBedloadFlux:
      if (solids) {
        const std::vector<double> flux = bedload_flux(*solids, classes_, frame);
        append_values(flux);
        append_values(flux_mean_.add(world.time, flux));
      } else {
        fields.append(2 * (classes + 1), ',');
      }
      break;
    case ProbeModel::Kind::kBedShearStress: {
      const BedShear shear = bed_shear_stress(solids, world.fluid ? &*world.fluid : nullptr, shear_, frame);
      append_field(fields, format_value(shear.grains_fx));
      append_field(fields, format_value(shear.floor_fx));
      append_field(fields, format_value(shear.tau));
      std::optional<double> lid;
      if (probe_.lid) {
        lid = lid_shear_stress(*model_, world);
        append_field(fields, lid ? format_value(*lid) : std::string());
      }
      const double gravity = model_->gravity.norm();
      append_values(classes_.diameter);
      for (std::size_t k = 0; k < classes; ++k)
        append_field(fields, format_value(shields_number(shear.tau, classes_.density[k], model_->fluid.density,
                                                         gravity, classes_.diameter[k])));
      if (probe_.lid)
        for (std::size_t k = 0; k < classes; ++k)
          append_field(fields, lid ? format_value(shields_number(*lid, classes_.density[k], model_->fluid.density,
                                                                 gravity, classes_.diameter[k]))
                                   : std::string());
      break;
    }
    case ProbeModel::Kind::kMeanFlowProfile: {
      if (!world.mean_flow) break;
      const MeanFlowColumn& column = *world.mean_flow;
      const MeanFlowModel& flow = model_->mean_flow;
      const ColumnGrid grid = column_grid(flow);
      const ColumnEnds ends = column_ends(flow, true);
      std::string start = format_exact(world.time);
      append_field(start, std::to_string(world.step));
      for (std::size_t k = 0; k < grid.cells; ++k) {
        fields += start;
        append_field(fields, std::to_string(k));
        append_field(fields, format_value(grid.centre(k)));
        append_field(fields, format_value(column.velocity_x[k]));
        append_field(fields, format_value(column.velocity_y[k]));
        append_field(fields, format_value(column.solid_fraction[k]));
        // At the cell's centre: the mean of its two faces.
        const double eddy = column.eddy_viscosity.size() == grid.cells + 1
                                ? 0.5 * (column.eddy_viscosity[k] + column.eddy_viscosity[k + 1])
                                : 0.0;
        append_field(fields, format_value(eddy));
        // The stress at the cell's top face (the floor's stress is floor_stress).
        const double stress =
            column.eddy_viscosity.size() == grid.cells + 1
                ? column_shear_stress(grid, column.solid_fraction, column.eddy_viscosity, column.velocity_x, ends,
                                      flow.density, flow.kinematic_viscosity, grid.face(k + 1))
                : 0.0;
        append_field(fields, format_value(stress));
        fields += '\n';
      }
      break;
    }
    case ProbeModel::Kind::kBedloadTransport: {
      if (!world.mean_flow || !solids) {
        fields.append(13, ',');
        break;
      }
      const BedloadTransport transport =
          bedload_transport(*model_, *solids, *world.mean_flow, shields_grain_, probe_.threshold);
      const double u_star = transport.friction_velocity;
      const double moving_speed = transport.moving > 0 && u_star > 0.0 ? transport.moving_speed / u_star : kNaN;
      const double moving_height =
          transport.moving > 0 ? transport.moving_height / shields_grain_.diameter : kNaN;
      for (double value : {transport.shields, u_star, transport.bed_stress, transport.bed_surface, transport.flux,
                           transport.flux_star, transport.moving_fraction, moving_speed, moving_height})
        append_field(fields, format_value(value));
      append_field(fields, std::to_string(transport.moving));
      append_field(fields, format_value(world.mean_flow->body_force));
      const double above_speed =
          transport.moving_above_bed > 0 && u_star > 0.0 ? transport.moving_above_bed_speed / u_star : kNaN;
      append_field(fields, format_value(above_speed));
      append_field(fields, std::to_string(transport.moving_above_bed));
      // The means the run prints at its end: over the rows in the run's second half.
      if (world.time >= 0.5 * model_->end_time)
        transport_mean_.add(transport, moving_speed, moving_height, above_speed);
      break;
    }
    case ProbeModel::Kind::kVelocityProfile: {
      const std::vector<ProfileLayer> layers = velocity_profile(solids, world.fluid ? &*world.fluid : nullptr,
                                                                frame, probe_.layer_thickness, profile_layers_);
      std::string start = format_exact(world.time);
      append_field(start, std::to_string(world.step));
      for (std::size_t k = 0; k < layers.size(); ++k) {
        const ProfileLayer& layer = layers[k];
        fields += start;
        append_field(fields, std::to_string(k));
        append_field(fields, format_value(layer.z_low));
        append_field(fields, format_value(layer.z_high));
        append_field(fields, std::to_string(layer.fluid_particles));
        append_field(fields, format_value(layer.fluid_ux));
        append_field(fields, format_value(layer.grain_ux));
        append_field(fields, format_value(layer.solid_fraction));
        fields += '\n';
      }
      break;
    }
    default:
      break;
  }
  return fields;
}

std::string ProbeWriter::summary() const {
  if (probe_.kind != ProbeModel::Kind::kBedloadTransport || transport_mean_.rows == 0) return {};
  const TransportMean& mean = transport_mean_;
  const double rows = static_cast<double>(mean.rows);
  const double moving_rows = static_cast<double>(mean.moving_rows);
  char line[512];
  std::snprintf(line, sizeof line,
                "%s, mean of %zu rows over the run's second half: Theta = %.4g, q* = %.4g, moving fraction = %.4g, "
                "u_p/u* = %.4g (above the bed %.4g), h_p/d = %.4g",
                probe_.name.c_str(), mean.rows, mean.shields / rows, mean.flux_star / rows, mean.moving_fraction / rows,
                mean.moving_rows > 0 ? mean.moving_speed / moving_rows : kNaN,
                mean.above_rows > 0 ? mean.above_speed / static_cast<double>(mean.above_rows) : kNaN,
                mean.moving_rows > 0 ? mean.moving_height / moving_rows : kNaN);
  return line;
}

void ProbeWriter::write(const World& world) {
  if (probe_.kind == ProbeModel::Kind::kVelocityProfile || probe_.kind == ProbeModel::Kind::kMeanFlowProfile) {
    file_.write_rows(bedload_fields(world));  // long format: one line per layer
    return;
  }
  std::string row = format_exact(world.time);
  append_field(row, std::to_string(world.step));
  auto append = [&row](const Vec3& value) {
    for (int axis = 0; axis < 3; ++axis) append_field(row, format_value(value[axis]));
  };
  auto append_empty = [&row](std::size_t fields) {
    for (std::size_t k = 0; k < fields; ++k) row += ",";
  };
  // A fluid probe in a world without fluid particles (yet) writes empty fields: unknown, not zero.
  const TankMotion tank = world.tank_motion.value_or(TankMotion{});
  auto append_fluid = [&](std::size_t columns, auto&& measure) {
    for (std::size_t k = 0; k < columns; ++k)
      append_field(row, world.fluid ? format_value(measure(*world.fluid, k)) : std::string());
  };
  switch (probe_.kind) {
    case ProbeModel::Kind::kGrains: {
      const Solids* solids = world.solids ? &*world.solids : nullptr;
      if (solids) slots_.refresh(*solids);
      // Wrapped into the period, as the VTK frames: a grain past a periodic face is wrapped in the state only at
      // the next neighbour-list rebuild.
      const PeriodicBox box = periodic_box(*model_);
      for (std::size_t k = 0; k < probe_.ids.size(); ++k) {
        const std::size_t slot = solids ? slots_.slot(k) : GrainSlotMap::kNone;
        if (slot == GrainSlotMap::kNone) {
          append_empty(kGrainProbeColumns.size());  // the grain is gone (or never was): empty, not made up
          continue;
        }
        append(box.wrap(solids->position[slot]));
        append(solids->velocity[slot]);
        append(solids->angular_velocity[slot]);
        append(solids->contact_force[slot]);
        append_field(row, format_value(solids->voidage[slot]));
        append(solids->undisturbed_velocity[slot]);
        append(solids->drag_force[slot]);
        append(solids->pressure_force[slot]);
        append(solids->added_mass_force[slot]);
        append(solids->history_force[slot]);
        append(solids->lubrication_force[slot]);
      }
      break;
    }
    case ProbeModel::Kind::kWallForces: {
      const std::size_t walls = world.walls ? world.walls->size() : 0;
      const std::vector<Vec3> forces =
          world.contacts ? wall_reaction_forces(*world.contacts, walls) : std::vector<Vec3>{};
      // Before the first step the contact list does not exist yet: the forces are unknown, not zero.
      for (std::size_t wall = 0; wall < walls; ++wall)
        if (forces.empty())
          append_empty(3);
        else
          append(forces[wall]);
      break;
    }
    case ProbeModel::Kind::kFluidPressure:
      append_fluid(probe_.points.size(), [&](const FluidParticles& fluid, std::size_t k) {
        return fluid_pressure_at(fluid, fluid_, tank, probe_.points[k]);
      });
      break;
    case ProbeModel::Kind::kWaveGauge:
      append_fluid(probe_.points.size(), [&](const FluidParticles& fluid, std::size_t k) {
        return wave_gauge_height(fluid, fluid_, tank, probe_.points[k], probe_.radius);
      });
      break;
    case ProbeModel::Kind::kSurgeFront:
      append_fluid(1, [&](const FluidParticles& fluid, std::size_t) {
        return surge_front_position(fluid, fluid_, tank, probe_.direction, probe_.below);
      });
      break;
    case ProbeModel::Kind::kPressureTransducer: {
      if (window_) take_reading(world);  // a fresh run's t = 0 row: the window holds the initial state alone
      const std::vector<double> readings = window_ ? window_->mean() : transducer_readings(world);
      for (std::size_t k = 0; k < probe_.points.size(); ++k)
        append_field(row, world.fluid && k < readings.size() ? format_value(readings[k]) : std::string());
      break;
    }
    case ProbeModel::Kind::kFluidTotals:
      if (const std::optional<FluidSummary>& summary = world.fluid_summary) {
        append_field(row, std::to_string(summary->fluid_count));
        append_field(row, format_value(summary->volume));
        append_field(row, format_value(summary->kinetic_energy));
        append_field(row, format_value(summary->max_speed));
        append_field(row, format_value(summary->mean_density_ratio));
        append_field(row, std::to_string(summary->surface_count));
        append_field(row, std::to_string(summary->solver_iterations));
        append_field(row, format_value(summary->solver_residual));
        // Escaped particles removed so far (fluid_escape), each of mass rho l0^3: water + removed = laid out.
        const double removed_volume = static_cast<double>(summary->removed_count()) * fluid_.spacing *
                                      fluid_.spacing * fluid_.spacing;
        append_field(row, std::to_string(summary->removed_count()));
        append_field(row, format_value(removed_volume * fluid_.density));
        append_field(row, format_value(removed_volume));
        // By reason (systems/physics/geometry/domain.hpp, FluidEscapeKind).
        append_field(row, std::to_string(summary->removed_left_domain));
        append_field(row, std::to_string(summary->removed_lone_droplet));
      } else {
        append_empty(13);
      }
      break;
    case ProbeModel::Kind::kMovingFraction:
    case ProbeModel::Kind::kPackingDensity:
    case ProbeModel::Kind::kBedloadFlux:
    case ProbeModel::Kind::kBedShearStress:
    case ProbeModel::Kind::kVelocityProfile:
    case ProbeModel::Kind::kMeanFlowProfile:
    case ProbeModel::Kind::kBedloadTransport:
      row += bedload_fields(world);
      break;
    case ProbeModel::Kind::kDrivenFlow:
      if (world.fluid && world.fluid_summary) {
        // The bulk velocity: the mean u_x of the fluid particles now (each stands for l0^3 of water).
        const FluidParticles& particles = *world.fluid;
        double sum = 0.0;
        std::size_t count = 0;
        for (std::size_t i = 0; i < particles.size() && particles.kind[i] == kFluidKind; ++i, ++count)
          sum += particles.velocity[i].x();
        append_field(row, format_value(world.fluid_summary->body_force));
        append_field(row, format_value(count > 0 ? sum / static_cast<double>(count) : kNaN));
        // The lid's force on the water, and the shear stress it stands for: F_x over the lid's area.
        const std::vector<Vec3>& forces = world.fluid_summary->lid_force;
        for (std::size_t k = 0; k < probe_.lid_areas.size(); ++k) {
          if (k < forces.size()) {
            append(forces[k]);
            append_field(row, format_value(forces[k].x() / probe_.lid_areas[k]));
          } else {
            append_empty(4);
          }
        }
      } else {
        append_empty(2 + 4 * probe_.lid_areas.size());
      }
      break;
  }
  file_.write_row(row);
}

}  // namespace riffle
