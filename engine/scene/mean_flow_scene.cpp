#include "engine/scene/mean_flow_scene.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/scene/fluid_scene.hpp"

namespace riffle {

namespace {

/// [mean_flow.profile_forcing]: seed 003's drive (its Sec. 2.4, Eq. 25, towards its Eq. 27's profile), plane-averaged.
void read_profile_forcing(TableReader& reader, MeanFlowModel& out) {
  MeanFlowModel::ProfileForcing& forcing = out.profile_forcing;
  forcing.enabled = true;
  if (out.shields_number > 0.0)
    reader.problem("", "give the drive once: shields_number (a slope) or [mean_flow.profile_forcing]");
  if (out.body_force.kind != BodyForceModel::Kind::kNone)
    reader.problem("", "give the drive once: [mean_flow.body_force] or [mean_flow.profile_forcing]");
  forcing.velocity = reader.number("velocity", std::nullopt, "m/s", Bounds::closed(-100.0, 100.0));
  if (reader.has("velocity") && forcing.velocity == 0.0)
    reader.problem("velocity", "a target at rest pulls nothing: give the top's velocity");
  forcing.exponent = reader.number("exponent", forcing.exponent, "1", Bounds::closed(0.01, 1.0));
  forcing.base = reader.number("base", std::nullopt, "m", Bounds::any());
  if (!(forcing.base >= out.bottom && forcing.base < out.top))
    reader.problem("base", "the target profile starts inside the column, between its floor (" +
                               format_number(out.bottom) + " m) and its top (" + format_number(out.top) + " m)");
  forcing.strength = reader.number("strength", std::nullopt, "m/s^2", Bounds::positive());
  forcing.volume_fraction = reader.number("volume_fraction", forcing.volume_fraction, "1", Bounds::closed(1e-6, 1.0));
  reader.finish();
}

}  // namespace

void read_mean_flow(TableReader& flow, Model& model) {
  MeanFlowModel& out = model.mean_flow;
  out.enabled = true;
  if (model.fluid.enabled)
    flow.problem("depth", "a scene has one fluid: the MPS water [fluid] or the mean-flow fluid [mean_flow], not both");
  if (!model.tank.periodic[0] || !model.tank.periodic[1])
    flow.problem("depth", "the mean-flow fluid is a flow uniform along the bed: the tank must be periodic along x and "
                          "y (tank.periodic = [\"x\", \"y\"])");
  if (model.tank.motion.kind != TankMotionModel::Kind::kNone)
    flow.problem("depth", "the mean-flow fluid's column stands still: give the tank no [tank.motion]");
  out.density = flow.number("density", out.density, "kg/m^3", Bounds::positive());
  out.kinematic_viscosity = flow.number("kinematic_viscosity", out.kinematic_viscosity, "m^2/s", Bounds::positive());
  const double tank_height = model.tank.size.z();
  out.bottom = model.tank.origin.z();
  const double depth = flow.number("depth", tank_height, "m", Bounds::positive());
  if (depth > tank_height * (1.0 + 1e-12))
    flow.problem("depth", "the water cannot stand higher than the tank (" + format_number(tank_height) + " m)");
  out.top = out.bottom + depth;
  // A fixed count, not a size: the column is cheap (a tridiagonal solve per step), so the default resolves a 1 mm
  // grain with ten cells in a 4 cm deep channel.
  out.cells = static_cast<std::size_t>(flow.integer("cells", 400, 8, 1000000));
  out.cell_size = depth / static_cast<double>(out.cells);
  out.top_boundary = enum_choice(flow, "top", out.top_boundary, MeanFlowModel::kTopNames);
  if (out.top_boundary == MeanFlowModel::Top::kLid)
    out.lid_velocity = flow.number("lid_velocity", std::nullopt, "m/s", Bounds::closed(-100.0, 100.0));
  out.turbulence = enum_choice(flow, "turbulence", out.turbulence, MeanFlowModel::kTurbulenceNames);
  MixingLengthClosure& closure = out.closure;
  closure.von_karman = flow.number("von_karman", closure.von_karman, "1", Bounds::closed(0.1, 1.0));
  closure.max_solid_fraction =
      flow.number("max_solid_fraction", closure.max_solid_fraction, "1", Bounds::closed(0.1, 0.74));
  using Floor = MixingLengthClosure::Floor;
  const std::string floor = flow.choice("floor", "smooth", {"smooth", "rough"});
  closure.floor = floor == "rough" ? Floor::kRough : Floor::kSmooth;
  if (closure.floor == Floor::kRough) {
    closure.roughness = flow.number("floor_roughness", std::nullopt, "m", Bounds::positive());
    closure.rough_wall_constant = flow.number("rough_wall_constant", closure.rough_wall_constant, "1", Bounds::closed(0.0, 20.0));
  } else {
    closure.van_driest = flow.number("van_driest", closure.van_driest, "1", Bounds::positive());
  }

  // The drive: the Shields number of the bed, or a body force.
  out.shields_number = flow.number("shields_number", 0.0, "1", Bounds::closed(0.0, 10.0));
  if (out.shields_number > 0.0) {
    out.shields_diameter = flow.number("shields_diameter", std::nullopt, "m", Bounds::positive());
    // The grains' material, named: a scene may have several (the tank's walls, a rough floor of another).
    const std::string name = flow.text("shields_material", std::nullopt);
    for (const Material& material : model.materials)
      if (material.name == name) out.shields_density = material.density;
    if (!name.empty() && !(out.shields_density > 0.0))
      flow.problem("shields_material", "no material named \"" + name + "\" in [materials]");
    if (out.shields_density > 0.0 && out.shields_density <= out.density)
      flow.problem("shields_material", "the grains must be denser than the water for a Shields number");
    out.body_force.grains = BodyForceModel::Grains::kFrame;  // a slope: gravity tilted for water and grains alike
    if (flow.has("body_force"))
      flow.problem("body_force", "give the drive once: shields_number (a slope) or [mean_flow.body_force]");
  }
  if (auto body_force = flow.table("body_force", false)) {
    read_body_force(*body_force, out.body_force, model.tank.motion);
    if (out.body_force.kind == BodyForceModel::Kind::kBulkVelocity)
      body_force->problem("kind", "the mean-flow fluid takes a constant or sinusoidal body force (or shields_number)");
  }
  if (auto forcing = flow.table("profile_forcing", false)) read_profile_forcing(*forcing, out);
  out.initial = enum_choice(flow, "initial", out.initial, MeanFlowModel::kInitialNames);
  if (out.initial == MeanFlowModel::Initial::kTargetProfile && !out.profile_forcing.enabled)
    flow.problem("initial", "\"target_profile\" starts the water on [mean_flow.profile_forcing]'s target: give that "
                            "table, or start from \"rest\" or \"log_law\"");
  out.initial_roughness_length =
      flow.number("initial_roughness_length", out.initial_roughness_length, "m", Bounds::non_negative());
  out.fluctuations = enum_choice(flow, "fluctuations", out.fluctuations, MeanFlowModel::kFluctuationsNames);
  if (out.fluctuations == MeanFlowModel::Fluctuations::kLangevin &&
      out.turbulence != MeanFlowModel::Turbulence::kMixingLength)
    flow.problem("fluctuations", "the Langevin fluctuations scale with the mixing-length closure's stress: with "
                                 "turbulence = \"laminar\" there is none (set turbulence = \"mixing_length\")");
  if (out.fluctuations == MeanFlowModel::Fluctuations::kLangevin) {
    out.langevin_c0 = flow.number("langevin_c0", out.langevin_c0, "1", Bounds::closed(1.0, 20.0));
    out.fluctuation_seed = static_cast<std::uint64_t>(
        flow.integer("fluctuation_seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  }
  flow.finish();
}

void settle_mean_flow_coupling(TableReader& scene, Model& model) {
  if (!model.mean_flow.enabled) return;
  CouplingModel& coupling = model.coupling;
  std::optional<TableReader> table = scene.table("coupling", false);
  const auto refuse = [&](const char* key, const char* why) {
    if (table) table->problem(key, why);
  };
  if (table && table->has("fluid_velocity") && coupling.fluid_velocity != CouplingModel::FluidVelocity::kPore)
    refuse("fluid_velocity", "the mean-flow water's velocity is the pore water's: fluid_velocity = \"pore\" (or leave "
                             "it out)");
  coupling.fluid_velocity = CouplingModel::FluidVelocity::kPore;
  if (coupling.added_mass) refuse("added_mass", "not with the mean-flow fluid (the MPS water's)");
  if (coupling.history_force) refuse("history_force", "not with the mean-flow fluid (the MPS water's)");
  if (coupling.self_induced_velocity) refuse("self_induced_velocity", "not with the mean-flow fluid: a grain does "
                                                                      "not disturb the plane average it reads");
  if (coupling.viscous_stress) refuse("viscous_stress", "not with the mean-flow fluid (the MPS water's)");
  if (model.mean_flow.fluctuations != MeanFlowModel::Fluctuations::kNone && !coupling.drag && table)
    refuse("drag", "[mean_flow] fluctuations act through the drag: turn drag on or the fluctuations off");
}

}  // namespace riffle
