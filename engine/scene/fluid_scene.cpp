#include "engine/scene/fluid_scene.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <vector>

#include "engine/setup/fluid_layout.hpp"
#include "systems/physics/mps/driven_flow.hpp"
#include "systems/physics/mps/hypre_pressure_solver.hpp"

namespace riffle {

namespace {

// As for [[solids.blocks]]: a fluid this large is a typo in spacing, and laying it out would exhaust the memory.
constexpr double kMaxParticles = 5e7;
const char* const kAxisNames[3] = {"x", "y", "z"};

std::string format_vec(const Vec3& v) {
  std::ostringstream stream;  // not "(" + string: GCC 12 warns falsely (-Wrestrict) on that operator+
  stream << '(' << v[0] << ", " << v[1] << ", " << v[2] << ')';
  return stream.str();
}

// `open_tank`: [tank] has open faces (the conservative gradient is for water without a free surface).
void read_schemes(TableReader& schemes, FluidSchemes& out, bool open_tank) {
  out.higher_order_source = schemes.boolean("hs", true);
  out.error_compensating_source = schemes.boolean("ecs", true);
  out.higher_order_laplacian = schemes.boolean("hl", true);
  out.conservative_gradient = schemes.boolean("conservative_gradient", false);
  out.gradient_correction = schemes.boolean("gc", !out.conservative_gradient);
  if (out.conservative_gradient && out.gradient_correction)
    schemes.problem("gc", "the conservative gradient replaces the gradient correction (its C_i differ between the two "
                          "ends of a pair, which would break the pair's balance): give gc = false or leave gc out");
  else if (out.conservative_gradient && open_tank)
    schemes.problem("conservative_gradient",
                    "is for water without a free surface (a sealed box full of water; docs/FLUID.md, \"A "
                    "momentum-conserving gradient\"), but [tank] has open faces");
  out.grain_gradient = enum_choice(schemes, "grain_gradient", out.grain_gradient, FluidSchemes::kGrainGradientNames);
  if (out.grain_gradient == FluidSchemes::GrainGradient::kCorrected && !out.conservative_gradient)
    schemes.problem("grain_gradient", "\"corrected\" is for conservative_gradient = true (otherwise the grains already "
                                      "sample the gradient the water moves with, GC's or the classic one)");
  out.dynamic_stabilisation = schemes.boolean("ds", true);
  schemes.finish();
}

/// One [[fluid.boxes]] or [[fluid.wall_boxes]] entry and what the checks need of it.
struct BoxEntry {
  TableReader reader;
  std::string name;         ///< full key, e.g. fluid.boxes[1], for messages naming the other box
  LatticeRange range;
  BoxGrid grid;             ///< its particles (box_grid), for the geometric overlap checks
  bool fit_extent = false;  ///< placement = "extent"
  bool laid_out = false;    ///< its lattice range is known (no earlier problem with it)
};

/// Two boxes overlap when a particle of one is closer than l0/2 to one of the other: for two snapped boxes exactly
/// "they share lattice points" (their lattice ranges intersect), which is what is checked for them.
bool boxes_overlap(const BoxEntry& a, const BoxEntry& b) {
  if (!a.fit_extent && !b.fit_extent) return a.range.overlaps(b.range);
  return grid_distance(a.grid, b.grid) < 0.5 * a.grid.spacing;
}

std::string overlap_reason(const BoxEntry& a, const BoxEntry& b) {
  if (!a.fit_extent && !b.fit_extent) return " (they share lattice points)";
  return " (their particles come within " + format_number(grid_distance(a.grid, b.grid)) +
         " m of each other, closer than spacing / 2)";
}

/// Reads one box and checks it against the tank and the lattice; `spacing` is 0 when unknown (already reported).
BoxEntry read_box(TableReader& reader, ParticleBoxModel& box, bool fluid_box, const Model& model, double spacing) {
  BoxEntry entry{reader, reader.full_key(""), {}, {}, false, false};
  if (!entry.name.empty() && entry.name.back() == '.') entry.name.pop_back();  // full_key("") ends with a '.'
  const std::size_t problems_before = reader.problem_count();
  box.low = reader.vec3("low", std::nullopt, "m", Bounds::any());
  box.high = reader.vec3("high", std::nullopt, "m", Bounds::any());
  if (fluid_box) box.velocity = reader.vec3("velocity", Vec3::Zero(), "m/s", Bounds::any());
  box.fit_extent = reader.choice("placement", "lattice", {"lattice", "extent"}) == "extent";
  entry.fit_extent = box.fit_extent;
  if (!fluid_box && reader.has("name")) {
    box.name = reader.text("name", std::nullopt);
    if (!plain_name(box.name))
      reader.problem("name", "expected a name of letters, digits, '_', '-' and '.', not starting with '.', got \"" +
                                 box.name + "\"");
  }
  if (!fluid_box && reader.has("lid")) {
    // A moving lid (docs/FLUID.md, "Driven flows"): no-slip or free-slip, moving along x only.
    box.lid = true;
    box.lid_free_slip = reader.choice("lid", std::nullopt, {"no_slip", "free_slip"}) == "free_slip";
    box.lid_velocity = reader.number("velocity", box.lid_velocity, "m/s", Bounds::any());
    if (box.lid_free_slip && box.lid_velocity != 0.0)
      reader.problem("velocity", "a free-slip lid takes no part in the viscous term, so its velocity has no effect: "
                                 "give 0 or lid = \"no_slip\"");
  }
  reader.finish();
  if (reader.problem_count() != problems_before) return entry;

  for (int axis = 0; axis < 3; ++axis)
    if (!(box.high[axis] > box.low[axis])) {
      reader.problem("high", std::string("every component of high must be > the one of low (along ") +
                                 kAxisNames[axis] + ": " + format_number(box.high[axis]) + " <= " +
                                 format_number(box.low[axis]) + ")");
      return entry;
    }
  const TankModel& tank = model.tank;
  if (!(tank.size.array() > 0.0).all()) return entry;  // a bad tank is reported at [tank]
  // Corners written as the tank's own sums may miss them by a rounding error; 1e-9 of the tank allows for that.
  const double tolerance = 1e-9 * tank.size.maxCoeff();
  const Vec3 tank_high = tank.origin + tank.size;
  const std::string tank_box =
      "the box must lie inside the tank's inner box " + format_vec(tank.origin) + " - " + format_vec(tank_high) + " m";
  if ((box.low.array() < tank.origin.array() - tolerance).any()) {
    reader.problem("low", tank_box);
    return entry;
  }
  if ((box.high.array() > tank_high.array() + tolerance).any()) {
    reader.problem("high", tank_box);
    return entry;
  }
  if (!(spacing > 0.0)) return entry;
  const Eigen::Array3d cells = box.fit_extent
                                   ? Eigen::Array3d(((box.high - box.low).array() / spacing).round().max(1.0))
                                   : Eigen::Array3d(((box.high - box.low).array() / spacing + 1e-9).floor() + 1.0);
  if (cells.prod() > kMaxParticles) {
    reader.problem("high", "the box would hold more than 5e7 particles at spacing " + format_number(spacing) + " m");
    return entry;
  }
  entry.grid = box_grid(tank.origin, box.low, box.high, spacing, box.fit_extent);
  // The lid's particles wrap within the box's own x extent: count along x times l0, so the row stays evenly spaced
  // across the seam.
  box.lid_period = static_cast<double>(entry.grid.count[0]) * spacing;
  box.lid_start_x = entry.grid.first[0] - 0.5 * spacing;
  box.lid_area = box.lid_period * static_cast<double>(entry.grid.count[1]) * spacing;
  box.lid_plane_low = entry.grid.first[2] - 0.5 * spacing;
  box.lid_plane_high = entry.grid.first[2] + (static_cast<double>(entry.grid.count[2]) - 0.5) * spacing;
  // With x periodic the lid's row must be the whole period: a row that wraps within a shorter extent makes its
  // particles jump mid-domain (and leaves the rest of the plane without a lid). Lids move along x only, so y needs
  // no such check.
  if (box.lid && box.lid_velocity != 0.0 && tank.periodic[0] &&
      (std::abs(box.lid_start_x - tank.origin.x()) > tolerance + 1e-9 * spacing ||
       std::abs(box.lid_period - tank.size.x()) > tolerance + 1e-9 * spacing)) {
    reader.problem("low", "with x periodic a moving lid must span the whole period along x: its particles cover [" +
                              format_number(box.lid_start_x) + ", " + format_number(box.lid_start_x + box.lid_period) +
                              ") m, the period is [" + format_number(tank.origin.x()) + ", " +
                              format_number(tank_high.x()) + ") m");
    return entry;
  }
  if (box.fit_extent) {  // at least one particle per axis by construction
    entry.laid_out = true;
    return entry;
  }
  entry.range = lattice_range(tank.origin, box.low, box.high, spacing);
  for (std::size_t a = 0; a < 3; ++a)
    if (entry.range.last[a] < entry.range.first[a]) {
      reader.problem("low", std::string("the box contains no lattice point: along ") + kAxisNames[a] +
                                " no particle centre tank.origin + (i + 1/2) spacing lies in [low, high]");
      return entry;
    }
  entry.laid_out = true;
  return entry;
}

/// Tank walls: tank_wall_layout needs whole lattice cells along every axis; says which axis and what size fits.
void check_tank_fits_lattice(TableReader& fluid, const Model& model) {
  const double spacing = model.fluid.spacing;
  const Vec3& size = model.tank.size;
  const std::int64_t layers = 1 + dummy_layer_count(spacing, model.fluid.effective_radius());
  double outer = 1.0, inner = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double ratio = size[axis] / spacing;
    const double cells = std::max(1.0, std::round(ratio));
    if (std::abs(ratio - cells) > 1e-6) {  // the tolerance of tank_wall_layout
      fluid.problem("spacing", std::string("with tank_walls = true the tank size along ") + kAxisNames[axis] + " (" +
                                   format_number(size[axis]) + " m) must be an integer multiple of spacing (" +
                                   format_number(spacing) + " m); nearest valid size " +
                                   format_number(cells * spacing) + " m");
      return;
    }
    outer *= cells + 2.0 * static_cast<double>(layers);
    inner *= cells;
  }
  if (outer - inner > kMaxParticles)
    fluid.problem("spacing", "the tank walls would need more than 5e7 wall and dummy particles at spacing " +
                                 format_number(spacing) + " m");
}

/// A periodic axis without tank walls: the period must still hold a whole number of lattice cells, or the water
/// meets its own image across the seam at a gap other than l0 (a density spike or hole along the seam).
void check_period_fits_lattice(TableReader& fluid, const Model& model) {
  const double spacing = model.fluid.spacing;
  for (int axis = 0; axis < 3; ++axis) {
    if (!model.tank.periodic[static_cast<std::size_t>(axis)]) continue;
    const double size = model.tank.size[axis];
    const double ratio = size / spacing;
    const double cells = std::max(1.0, std::round(ratio));
    if (std::abs(ratio - cells) > 1e-6) {  // the tolerance of tank_wall_layout
      fluid.problem("spacing", std::string("with ") + kAxisNames[axis] + " periodic the tank size along " +
                                   kAxisNames[axis] + " (" + format_number(size) +
                                   " m) must be an integer multiple of spacing (" + format_number(spacing) +
                                   " m), so the water meets its image across the seam at l0; nearest valid size " +
                                   format_number(cells * spacing) + " m");
      return;
    }
  }
}


// Particle shifting (docs/FLUID.md, "Particle shifting"): the law, its coefficient A and the cap per step; and the
// water's starting arrangement ("A packed start"), whose packing shifts the same way before the run.
void read_shifting(TableReader& fluid, FluidModel& out) {
  out.initial_arrangement = fluid.choice("initial_arrangement", "lattice", {"lattice", "packed"}) == "packed"
                                ? FluidModel::Arrangement::kPacked
                                : FluidModel::Arrangement::kLattice;
  out.shifting = fluid.choice("shifting", "off", {"off", "fickian"}) == "fickian" ? FluidModel::Shifting::kFickian
                                                                                 : FluidModel::Shifting::kOff;
  const bool constant = fluid.choice("shifting_diffusivity", "velocity", {"velocity", "constant"}) == "constant";
  out.shifting_diffusivity =
      constant ? FluidModel::ShiftingDiffusivity::kConstant : FluidModel::ShiftingDiffusivity::kVelocity;
  // A = 2 with D = A h |u| dt (Skillen et al. 2013); A = 0.25 with D = A h^2. The bounds are not a stability limit:
  // the explicit step is stable for D < 0.67 l0^2 at r_e = 2.4 l0 (docs/FLUID.md, "Particle shifting"), which the
  // defaults meet (0.36 l0^2 constant; 2 h |u| dt = 0.48 l0^2 at Courant 0.2) but A near the top of either range
  // does not; the cap (shifting_max) bounds the displacement, not the instability. A check against r_e is to come.
  out.shifting_coefficient = constant ? fluid.number("shifting_coefficient", 0.25, "1", Bounds{0.0, 1.0, false, true})
                                      : fluid.number("shifting_coefficient", 2.0, "1", Bounds{0.0, 10.0, false, true});
  out.shifting_max_ratio = fluid.number("shifting_max", out.shifting_max_ratio, "l0", Bounds{0.0, 0.25, false, true});
  out.shifting_velocity_correction = fluid.boolean("shifting_velocity_correction", true);
  if (out.shifting == FluidModel::Shifting::kOff)
    for (const char* key : {"shifting_diffusivity", "shifting_coefficient", "shifting_max", "shifting_velocity_correction"})
      if (fluid.has(key)) fluid.problem(key, "needs shifting = \"fickian\"");
}

/// [fluid.initial_velocity] (docs/SCENES.md): the water's initial velocity profile along x.
void read_initial_velocity(TableReader& reader, InitialVelocityModel& out, const TankModel& tank) {
  using Kind = InitialVelocityModel::Kind;
  out.kind = reader.choice("kind", std::nullopt, {"linear", "power"}) == "power" ? Kind::kPower : Kind::kLinear;
  // Heights in the tank's extent (scene coordinates); a profile outside it would touch no particle: a typo.
  Bounds height = tank.size.z() > 0.0 ? Bounds::closed(tank.origin.z(), tank.origin.z() + tank.size.z())
                                      : Bounds::any();
  height.name = "the tank's z extent";
  const std::size_t problems_before = reader.problem_count();
  out.bottom = reader.number("bottom", std::nullopt, "m", height);
  out.top = reader.number("top", std::nullopt, "m", height);
  if (reader.problem_count() == problems_before && !(out.top > out.bottom))
    reader.problem("top", "must be above bottom (" + format_number(out.bottom) + " m)");
  // The same bound as a body force's bulk velocity: beyond 100 m/s the key is a typo.
  out.top_velocity = reader.number("velocity", std::nullopt, "m/s", Bounds::closed(-100.0, 100.0));
  const bool exponent_given = reader.has("exponent");  // read in either case, so that it is not also "unknown"
  const double exponent = reader.number("exponent", 1.0 / 7.0, "1", Bounds{0.0, 10.0, false, true});
  if (out.kind == Kind::kPower)
    out.exponent = exponent;
  else if (exponent_given)
    reader.problem("exponent", "needs kind = \"power\"");
  reader.finish();
}

}  // namespace

void read_body_force(TableReader& reader, BodyForceModel& out, const TankMotionModel& tank_motion) {
  using Kind = BodyForceModel::Kind;
  const std::string kind = reader.choice("kind", std::nullopt, {"constant", "sinusoidal", "bulk_velocity"});
  out.kind = kind == "constant" ? Kind::kConstant : kind == "sinusoidal" ? Kind::kSinusoidal : Kind::kBulkVelocity;
  // Bounds: 100 g along x is no flow an incompressible particle method can follow; beyond it the key is a typo.
  const Bounds acceleration_bounds = Bounds::closed(-1000.0, 1000.0);
  if (out.kind == Kind::kConstant) out.acceleration = reader.number("acceleration", std::nullopt, "m/s^2", acceleration_bounds);
  if (out.kind == Kind::kSinusoidal) {
    out.acceleration = reader.number("amplitude", std::nullopt, "m/s^2", acceleration_bounds);
    out.period = reader.number("period", std::nullopt, "s", Bounds::positive());
    out.phase = reader.number("phase", out.phase, "deg", Bounds::closed(-360.0, 360.0)) * std::numbers::pi / 180.0;
  }
  if (out.kind == Kind::kBulkVelocity) {
    // The controller holds the mean u_x of the water in the lab frame (fluid_predict): in a tank that moves along x
    // that is not the flow's bulk velocity, so the combination is refused rather than driven towards the wrong target.
    const bool tank_moves_along_x =
        tank_motion.kind == TankMotionModel::Kind::kTable ||
        (tank_motion.kind == TankMotionModel::Kind::kSinusoidal && tank_motion.direction.x() != 0.0);
    if (tank_moves_along_x)
      reader.problem("kind", "bulk_velocity needs a tank that does not move along x (the controller holds the water's "
                             "mean velocity in the lab frame); use a constant or sinusoidal body force, or a still tank");
    out.target_velocity = reader.number("target_velocity", std::nullopt, "m/s", Bounds::closed(-100.0, 100.0));
    // Gains from the channel's time scales (pi_gains, systems/physics/mps/driven_flow.hpp), or given.
    const bool given = reader.has("proportional_gain") || reader.has("integral_gain");
    if (given) {
      out.proportional_gain = reader.number("proportional_gain", std::nullopt, "1/s", Bounds::non_negative());
      out.integral_gain = reader.number("integral_gain", std::nullopt, "1/s^2", Bounds::non_negative());
      for (const char* key : {"response_time", "damping_ratio", "viscous_time"})
        if (reader.has(key)) reader.problem(key, "give either the gains or the time scales they follow from, not both");
    } else {
      const double response = reader.number("response_time", std::nullopt, "s", Bounds::positive());
      const double damping = reader.number("damping_ratio", 1.0, "1", Bounds::closed(0.1, 10.0));
      const double plant = reader.number("viscous_time", std::numeric_limits<double>::infinity(), "s", Bounds::positive());
      if (response > 0.0 && damping > 0.0 && plant > 0.0) {
        const PiGains gains = pi_gains(plant, response, damping);
        out.proportional_gain = gains.proportional;
        out.integral_gain = gains.integral;
      }
    }
  }
  const std::string grains = reader.choice("grains", "pressure_gradient", {"pressure_gradient", "none", "frame"});
  out.grains = grains == "none"    ? BodyForceModel::Grains::kNone
               : grains == "frame" ? BodyForceModel::Grains::kFrame
                                   : BodyForceModel::Grains::kPressureGradient;
  reader.finish();
}

void read_fluid(TableReader& fluid, Model& model) {
  FluidModel& out = model.fluid;
  out.enabled = true;
  out.spacing = fluid.number("spacing", std::nullopt, "m", Bounds::positive());
  // numerics.md amendment 6: r_e = 2.4 l0 (3.1 l0 grows a zig-zag in the second surface layer); below 2 l0 the
  // Wendland stencil collapses to two shells, beyond 4 l0 the cost grows with no known benefit.
  out.effective_radius_ratio =
      fluid.number("effective_radius", out.effective_radius_ratio, "1", Bounds::closed(2.0, 4.0));
  out.density = fluid.number("density", out.density, "kg/m^3", Bounds::positive());
  out.kinematic_viscosity =
      fluid.number("kinematic_viscosity", out.kinematic_viscosity, "m^2/s", Bounds::non_negative());
  out.tank_walls = fluid.boolean("tank_walls", true);
  out.clamp_negative_pressure = fluid.boolean("clamp_negative_pressure", true);
  // numerics.md amendments: beta = 0.93 (0.97 misflags the second layer).
  out.surface_threshold = fluid.number("surface_threshold", out.surface_threshold, "1", Bounds{0.5, 1.0, false, false});
  out.density_relaxation_rate =
      fluid.number("density_relaxation_rate", out.density_relaxation_rate, "1/s", Bounds::non_negative());
  out.compressibility = fluid.number("compressibility", out.compressibility, "1/Pa", Bounds::non_negative());
  out.sound_speed = fluid.number("sound_speed", out.sound_speed, "m/s", Bounds::non_negative());
  out.courant = fluid.number("courant", out.courant, "1", Bounds{0.0, 0.5, false, true});
  out.diffusion_number = fluid.number("diffusion_number", out.diffusion_number, "1", Bounds{0.0, 1.0, false, true});
  out.hydrostatic_number =
      fluid.number("hydrostatic_number", out.hydrostatic_number, "1", Bounds{0.0, 100.0, false, true});
  out.min_dt = fluid.number("min_dt", out.min_dt, "s", Bounds::positive());
  out.solver_tolerance = fluid.number("solver_tolerance", out.solver_tolerance, "1", Bounds{0.0, 1.0, false, false});
  out.solver_max_iterations = fluid.integer("solver_max_iterations", out.solver_max_iterations, 1, 100000000);
  const std::string preconditioner = fluid.choice("preconditioner", "two_level", {"two_level", "jacobi", "boomeramg"});
  out.preconditioner = preconditioner == "jacobi"      ? FluidModel::Preconditioner::kJacobi
                       : preconditioner == "boomeramg" ? FluidModel::Preconditioner::kBoomerAmg
                                                       : FluidModel::Preconditioner::kTwoLevel;
  if (out.preconditioner == FluidModel::Preconditioner::kBoomerAmg && !hypre_available())
    fluid.problem("preconditioner", "\"boomeramg\" needs a riffle built with hypre: apt install libhypre-dev, then "
                                    "tools/setup.sh (this build found no hypre)");
  out.neighbour_skin_ratio = fluid.number("neighbour_skin", out.neighbour_skin_ratio, "1", Bounds::closed(0.0, 2.0));
  // Violent flow uses up any skin every step; then a narrow one shortens every pass over the lists.
  out.narrow_neighbour_skin_ratio = fluid.number("neighbour_skin_narrow", std::min(0.1, out.neighbour_skin_ratio), "1",
                                                 Bounds::closed(0.0, 2.0));
  if (out.narrow_neighbour_skin_ratio > out.neighbour_skin_ratio)
    fluid.problem("neighbour_skin_narrow",
                  "must not exceed neighbour_skin (" + format_number(out.neighbour_skin_ratio) + ")");
  out.sort_every = fluid.integer("sort_every", out.sort_every, 0, 1000000000);
  out.sort_every_fast = fluid.integer("sort_every_fast", out.sort_every_fast, 0, 1000000000);
  if (auto schemes = fluid.table("schemes", false)) read_schemes(*schemes, out.schemes, !model.tank.open_faces.empty());
  // Escaped spray (systems/mps/fluid_escape.hpp): removed and counted, or the run stops at the first particle.
  out.escape = fluid.choice("escape", "remove", {"remove", "stop"}) == "stop" ? FluidModel::EscapePolicy::kStop
                                                                              : FluidModel::EscapePolicy::kRemove;
  if (fluid.has("escape_distance")) {
    out.escape_distance = fluid.number("escape_distance", std::nullopt, "m", Bounds::non_negative());
    if (out.escape == FluidModel::EscapePolicy::kStop)
      fluid.problem("escape_distance", "needs escape = \"remove\" (with \"stop\" no particle is removed)");
  }
  out.escape_fraction_limit =
      fluid.number("escape_fraction_limit", out.escape_fraction_limit, "1", Bounds{0.0, 1.0, false, true});

  if (auto body_force = fluid.table("body_force", false)) read_body_force(*body_force, out.body_force, model.tank.motion);
  if (auto initial = fluid.table("initial_velocity", false))
    read_initial_velocity(*initial, out.initial_velocity, model.tank);
  out.turbulence = fluid.choice("turbulence", "none", {"none", "sps"}) == "sps" ? FluidModel::Turbulence::kSps
                                                                                : FluidModel::Turbulence::kNone;
  // C_s = 0.12: the value Gotoh et al. (2001) use for the SPS closure of their particle method (Smagorinsky's
  // constant is 0.1-0.2 in the literature; 0.17 from the Kolmogorov spectrum, Lilly 1967).
  out.smagorinsky_constant =
      fluid.number("smagorinsky_constant", out.smagorinsky_constant, "1", Bounds::closed(0.0, 1.0));
  out.scatter_viscosity = fluid.number("scatter_viscosity", out.scatter_viscosity, "1", Bounds::closed(0.0, 10.0));
  if (fluid.has("smagorinsky_constant") && out.turbulence != FluidModel::Turbulence::kSps)
    fluid.problem("smagorinsky_constant", "needs turbulence = \"sps\"");
  read_shifting(fluid, out);

  const double spacing = out.spacing;  // 0 if missing or invalid (reported)
  std::vector<BoxEntry> fluid_boxes, wall_boxes;
  for (TableReader& reader : fluid.tables("boxes"))
    fluid_boxes.push_back(read_box(reader, out.boxes.emplace_back(), true, model, spacing));
  for (TableReader& reader : fluid.tables("wall_boxes"))
    wall_boxes.push_back(read_box(reader, out.wall_boxes.emplace_back(), false, model, spacing));
  if (out.boxes.empty()) fluid.problem("boxes", "expected at least one [[fluid.boxes]] table");

  // Two boxes sharing a lattice point would place two particles in one spot. Wall boxes may overlap each other
  // (their shared points are placed once), but not the fluid.
  for (std::size_t k = 0; k < fluid_boxes.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (fluid_boxes[k].laid_out && fluid_boxes[j].laid_out && boxes_overlap(fluid_boxes[k], fluid_boxes[j])) {
        fluid_boxes[k].reader.problem("low", "the box overlaps " + fluid_boxes[j].name + overlap_reason(fluid_boxes[k], fluid_boxes[j]));
        break;
      }
  for (std::size_t k = 0; k < out.wall_boxes.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (!out.wall_boxes[k].name.empty() && out.wall_boxes[k].name == out.wall_boxes[j].name) {
        wall_boxes[k].reader.problem("name", "\"" + out.wall_boxes[k].name + "\" already names " + wall_boxes[j].name);
        break;
      }
  for (BoxEntry& wall : wall_boxes)
    for (const BoxEntry& box : fluid_boxes)
      if (wall.laid_out && box.laid_out && boxes_overlap(wall, box)) {
        wall.reader.problem("low", "the wall box overlaps " + box.name + overlap_reason(wall, box));
        break;
      }

  if (out.tank_walls && spacing > 0.0 && (model.tank.size.array() > 0.0).all()) check_tank_fits_lattice(fluid, model);
  else if (spacing > 0.0 && (model.tank.size.array() > 0.0).all()) check_period_fits_lattice(fluid, model);
  fluid.finish();
}

}  // namespace riffle
