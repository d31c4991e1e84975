#pragma once
// MPS particles (numerics.md Secs. 1.1 and 3.1): fluid particles and the tank's wall and dummy particles in one
// structure-of-arrays table, so one neighbour search and one number-density pass cover all of them. One entry per
// particle; slot order may change (a later cell sort), `id` never does. The table is split into roles, each written
// by its own systems; `FluidParticles` is every role at once (set-up, output, checkpoints, the cell sort).
//
// FluidNeighbours holds the neighbour lists (CSR, slots, self excluded) built by systems/fluid_neighbours.*. It is a
// separate component, like Contacts for the grains, so that the scheduler orders the build before every system
// that reads the lists, and so that it can be rebuilt from positions alone (never persistent).
#include <array>
#include <cereal/types/vector.hpp>
#include <cstdint>
#include <string_view>
#include <vector>

#include "components/component_id.hpp"
#include "components/halo.hpp"
#include "components/soa.hpp"
#include "components/vec.hpp"

namespace riffle {

/// What an MPS particle is (numerics 3.1 and the wall amendment): fluid particles move and are PPE unknowns;
/// wall particles (one layer on the boundary) and dummy particles (behind them) move with the tank, count in the
/// number density and the HS source, and are never free-surface particles.
enum class FluidKind : std::int32_t { kFluid = 0, kWall = 1, kDummy = 2 };

/// Identity, kind and motion at the step start: written by fluid_wall_motion (walls and dummies) and fluid_correct
/// (fluid); fluid_predict updates the fluid's velocity.
struct ParticleState {
  static constexpr ComponentId kId = component_id<ParticleState>;
  static constexpr std::string_view kName = "particle_state";

  std::vector<EntityId> id;                 ///< [1] stable identity
  std::vector<std::int32_t> kind;           ///< [1] FluidKind: 0 fluid, 1 wall, 2 dummy
  std::vector<Vec3> position;               ///< [m] lab frame, at the start of the step
  std::vector<Vec3> velocity;               ///< [m/s] lab frame; walls and dummies carry the wall velocity
  std::vector<Vec3> rest_position;          ///< [m] walls and dummies: position with the tank at rest (moved analytically)

  std::size_t size() const { return id.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"id", "1", true}, self.id);
    visit(FieldInfo{"kind", "1", true}, self.kind);
    visit(FieldInfo{"position", "m", false}, self.position);  // VTK points, not a point-data array
    visit(FieldInfo{"velocity", "m/s", true}, self.velocity);
    visit(FieldInfo{"rest_position", "m", false}, self.rest_position);
  }
};

/// The explicit prediction (numerics 2.1): written by fluid_predict (fluid_wall_motion for walls and dummies).
struct ParticlePrediction {
  static constexpr ComponentId kId = component_id<ParticlePrediction>;
  static constexpr std::string_view kName = "particle_prediction";

  std::vector<Vec3> predicted_position;  ///< [m] r* after the explicit prediction
  std::vector<double> density_rate;      ///< [1/s] ECS input: (Dn/Dt)^k of fluid particles at the step start
  /// [m/s^2] fluid: nu <lap u> of the prediction (with the eddy viscosity and the lids' extrapolation; without gravity,
  /// body force and drag reaction), the water's stress divergence over rho, sampled by the grains where
  /// [coupling] viscous_stress (through FluidSample, the next step: so it is checkpointed, since format 7).
  std::vector<Vec3> viscous_acceleration;

  std::size_t size() const { return predicted_position.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"predicted_position", "m", false}, self.predicted_position);
    visit(FieldInfo{"density_rate", "1/s", false}, self.density_rate);
    visit(FieldInfo{"viscous_acceleration", "m/s^2", true, 0.0, 7}, self.viscous_acceleration);
  }
};

/// The pressure solve's result: pressure written by fluid_pressure_solve, the gradient by fluid_correct.
struct ParticlePressure {
  static constexpr ComponentId kId = component_id<ParticlePressure>;
  static constexpr std::string_view kName = "particle_pressure";

  std::vector<double> pressure;           ///< [Pa] gauge pressure (0 at the free surface)
  std::vector<double> previous_pressure;  ///< [Pa] pressure of the step before (the PPE's warm start extrapolates)
  std::vector<Vec3> pressure_gradient;    ///< [Pa/m] fluid: the gradient of p^{k+1} the grains sample (without DS)
  /// [Pa/m] fluid: the gradient fluid_correct moved the water with (without DS): pressure_gradient, unless [fluid.
  /// schemes] grain_gradient = "corrected" has the grains sample GC's instead (docs/FLUID.md). Output only.
  std::vector<Vec3> applied_pressure_gradient;

  std::size_t size() const { return pressure.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"pressure", "Pa", true}, self.pressure);
    visit(FieldInfo{"previous_pressure", "Pa", false}, self.previous_pressure);
    visit(FieldInfo{"pressure_gradient", "Pa/m", true}, self.pressure_gradient);
    // Written by fluid_correct for every particle before any reader: not in checkpoints (their format stays).
    visit(FieldInfo{"applied_pressure_gradient", "Pa/m", true, 0.0, 0, false}, self.applied_pressure_gradient);
  }
};

/// Number density at the predicted positions and the free-surface flags: written by fluid_free_surface.
struct ParticleDensity {
  static constexpr ComponentId kId = component_id<ParticleDensity>;
  static constexpr std::string_view kName = "particle_density";

  std::vector<double> number_density;      ///< [1] n_i = sum_j w(r_ij) over fluid, wall and dummy neighbours
  std::vector<std::int32_t> free_surface;  ///< [1] 1 if n_i < beta n0 (fluid particles only), else 0

  std::size_t size() const { return number_density.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"number_density", "1", true}, self.number_density);
    visit(FieldInfo{"free_surface", "1", true}, self.free_surface);
  }
};

/// The grains' drag given back to the fluid: written by fluid_drag_reaction at the step end, applied and cleared by
/// the next fluid_predict.
struct ParticleDragReaction {
  static constexpr ComponentId kId = component_id<ParticleDragReaction>;
  static constexpr std::string_view kName = "particle_drag_reaction";

  std::vector<Vec3> drag_reaction;  ///< [N s/m^3] fluid: impulse per volume, applied in the next prediction

  std::size_t size() const { return drag_reaction.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"drag_reaction", "N s/m^3", true}, self.drag_reaction);
  }
};

/// Every role of the MPS particles: the whole table.
struct FluidParticles
    : EntityGroup<ParticleState, ParticlePrediction, ParticlePressure, ParticleDensity, ParticleDragReaction> {
  static constexpr std::string_view kName = "fluid";
  static constexpr bool kPersistent = true;

  /// The order in which checkpoints (frozen by format 4) and VTK frames write the fields: the order of the one table
  /// before the split into roles (for_each_field_in_order); fields added since at the end.
  static constexpr std::array<const char*, 15> kFieldOrder = {
      "id",          "kind",          "position",          "velocity",          "rest_position",
      "predicted_position", "density_rate", "pressure", "previous_pressure", "pressure_gradient",
      "drag_reaction", "number_density", "free_surface", "applied_pressure_gradient", "viscous_acceleration"};

  EntityId next_id = 0;  ///< the id the next added particle gets

  std::size_t size() const { return id.size(); }

  /// Appends one particle at zero pressure and number density, not on the surface; returns its slot.
  std::size_t add(const Vec3& position_m, const Vec3& velocity_m_s, FluidKind particle_kind) {
    const std::size_t slot = size();
    resize_fields(*this, slot + 1);
    id[slot] = next_id++;
    kind[slot] = static_cast<std::int32_t>(particle_kind);
    position[slot] = position_m;
    velocity[slot] = velocity_m_s;
    rest_position[slot] = position_m;
    predicted_position[slot] = position_m;
    return slot;
  }

  /// Fields not checkpointed (FieldInfo::checkpointed) are left out, and a field newer than the file read
  /// (FieldInfo::since_format) is not in it: a read gives either its default for every particle.
  template <class Archive>
  void serialize(Archive& archive) {
    archive(next_id);
    // `id` is the first field read, so an absent field takes its size; the others keep the sizes read, which the
    // reader's check_field_sizes then compares (a damaged file is refused, not padded).
    for_each_field_in_order(*this, [&](const FieldInfo& info, auto& field) {
      if constexpr (Archive::is_loading::value) {
        bool absent = !info.checkpointed;
        if constexpr (requires { archive.format_version(); }) absent = absent || archive.format_version() < info.since_format;
        if (absent) {
          using Value = typename std::decay_t<decltype(field)>::value_type;
          field.assign(id.size(), field_default<Value>(info));
          return;
        }
      } else {
        if (!info.checkpointed) return;
      }
      archive(field);
    });
  }
};

/// A fluid particle removed by fluid_escape, as it was when removed (for the run's log).
struct EscapedParticle {
  EntityId id = 0;
  Vec3 position = Vec3::Zero();  ///< [m]
  Vec3 velocity = Vec3::Zero();  ///< [m/s]
  bool left_domain = false;      ///< true: outside the domain box; false: a lone particle beyond fluid.escape_distance
};

/// Reductions over the fluid after each step and the pressure solver's report; diagnostics.csv and the time-step
/// control read them.
struct FluidSummary {
  static constexpr ComponentId kId = component_id<FluidSummary>;
  static constexpr std::string_view kName = "fluid_summary";
  static constexpr bool kPersistent = true;

  std::size_t fluid_count = 0;        ///< fluid particles
  std::size_t surface_count = 0;      ///< of which flagged free surface in the last solve
  double kinetic_energy = 0.0;        ///< [J] sum 1/2 rho l0^3 |u|^2 over fluid particles
  double max_speed = 0.0;             ///< [m/s] max |u| over fluid particles
  double mean_density_ratio = 1.0;    ///< [1] mean n/n0 over fluid particles not on the surface
  double volume = 0.0;                ///< [m^3] sum over fluid particles of l0^3 (n0/n_i for interior particles, 1 on the surface)
  std::int64_t solver_iterations = 0; ///< PCG iterations of the last solve
  double solver_residual = 0.0;       ///< [1] |r| / |b| at the end of the last solve
  std::size_t solver_unknowns = 0;    ///< PPE rows of the last solve
  bool solver_converged = true;
  double courant = 0.0;               ///< [1] max |u| dt / l0 of the last step
  /// Fluid particles fluid_escape removed so far, by reason (from format 12; an older file leaves both at 0, so
  /// their sum is then below the removed count by the removals before the resume).
  std::size_t removed_left_domain = 0;   ///< their centre left the domain box
  std::size_t removed_lone_droplet = 0;  ///< no MPS neighbour within r_e, beyond fluid.escape_distance from the tank

  // Not persistent, and so not in for_each_member: rebuilt from the scene on resume (Simulation::from_checkpoint_data).
  /// Fluid particles the scene laid out (initial_world). Particles are only ever removed (fluid_escape), never
  /// added, so the removed count is this less fluid_count, the same after a resume as in the run that wrote it.
  std::size_t initial_fluid_count = 0;
  /// The particles fluid_escape removed in the last step, for the run's log (cleared at every step it runs).
  std::vector<EscapedParticle> escaped;
  // Driven flows (fluid_predict; docs/FLUID.md), set at every step by scenes that have them:
  double body_force = 0.0;            ///< [m/s^2] the body force along x applied in the last step
  double bulk_velocity = 0.0;         ///< [m/s] kind bulk_velocity: the mean u_x of the fluid at the last step's start
  /// [m] kind bulk_velocity: the controller's integral of (U - U_bulk) dt (persistent from format 12; a run from
  /// an older file is not resumed: Simulation::from_checkpoint_data).
  double body_force_integral = 0.0;
  std::vector<Vec3> lid_force;        ///< [N] per moving lid (scene order): its viscous force on the water

  /// Fluid particles removed so far (fluid_escape).
  std::size_t removed_count() const { return initial_fluid_count > fluid_count ? initial_fluid_count - fluid_count : 0; }

  /// Every member once, in checkpoint order: `visit(name, persistent, member)`.
  template <class Self, class Visit>
  static void for_each_member(Self& self, Visit&& visit) {
    visit("fluid_count", true, self.fluid_count);
    visit("surface_count", true, self.surface_count);
    visit("kinetic_energy", true, self.kinetic_energy);
    visit("max_speed", true, self.max_speed);
    visit("mean_density_ratio", true, self.mean_density_ratio);
    visit("volume", true, self.volume);
    visit("solver_iterations", true, self.solver_iterations);
    visit("solver_residual", true, self.solver_residual);
    visit("solver_unknowns", true, self.solver_unknowns);
    visit("solver_converged", true, self.solver_converged);
    visit("courant", true, self.courant);
    visit("removed_left_domain", true, self.removed_left_domain);
    visit("removed_lone_droplet", true, self.removed_lone_droplet);
    visit("body_force_integral", true, self.body_force_integral);
  }

  /// The first format with the removals by reason and the controller's integral (the last three members).
  static constexpr std::uint32_t kFirstFormatWithRemovalReasons = 12;
  static bool since_removal_reasons(std::string_view name) {
    return name == "removed_left_domain" || name == "removed_lone_droplet" || name == "body_force_integral";
  }

  /// Checkpoint format 4 also stored `last_dt` [s], the length of the last step, right after solver_converged. The
  /// step length is decided once and kept in World::last_step, so nothing wrote last_dt any more and
  /// format 5 dropped it. Format-4 files must still load (settled beds read as [solids] initial_state, runs to
  /// resume): the checkpoint reader's archive says which format it reads (format_version(),
  /// engine/output/checkpoint_archive.hpp), and for format 4 the slot is read, checked and let go. Writing always
  /// gives the current format; cereal's output archive has no format_version().
  static constexpr std::uint32_t kLastFormatWithLastDt = 4;

  template <class Archive>
  void serialize(Archive& archive) {
    for_each_member(*this, [&](const char* name, bool persistent, auto& member) {
      if constexpr (requires { archive.format_version(); })
        if (archive.format_version() < kFirstFormatWithRemovalReasons && since_removal_reasons(name)) return;
      if (persistent) archive(member);
      if constexpr (requires { archive.format_version(); })
        if (archive.format_version() <= kLastFormatWithLastDt && std::string_view(name) == "solver_converged")
          archive.skip_retired_real("fluid_summary.last_dt");
    });
  }
};

/// The water at the start of the engine step as the grains sample it (docs/COUPLING.md): the fluid particles'
/// positions, velocities and pressure gradients, copied before the step's two branches start, so that the grains'
/// branch samples them while the fluid's branch advances `FluidParticles` beside it. Slots [0, F) of the fluid
/// particles at the copy; never persistent (copied again from `fluid` at every step).
struct FluidSample {
  static constexpr ComponentId kId = component_id<FluidSample>;
  static constexpr std::string_view kName = "fluid_sample";
  static constexpr bool kPersistent = false;  // copied again from the particles at every step

  std::vector<Vec3> position;           ///< [m]
  std::vector<Vec3> velocity;           ///< [m/s]
  std::vector<Vec3> pressure_gradient;  ///< [Pa/m] ParticlePressure::pressure_gradient of the last solve (without DS)
  std::vector<Vec3> viscous_acceleration;  ///< [m/s^2] nu <lap u> of the last prediction ([coupling] viscous_stress only)

  std::size_t size() const { return position.size(); }
};

/// Neighbours of the fluid particles (slots [0, F)) among all MPS particles within `radius` (self excluded), CSR by
/// particle slot, each list ascending.
struct FluidNeighbours {
  static constexpr ComponentId kId = component_id<FluidNeighbours>;
  static constexpr std::string_view kName = "fluid_neighbours";
  static constexpr bool kPersistent = false;  // rebuilt from the positions

  double radius = 0.0;                  ///< [m] search radius the lists were built with (>= r_e)
  std::vector<std::uint32_t> offsets;   ///< particles + 1: neighbours of i are slots[offsets[i] .. offsets[i+1])
  std::vector<std::uint32_t> slots;     ///< neighbour slots, ascending within each particle's list
  std::uint64_t builds = 0;             ///< number of builds so far
  std::uint64_t built_step = 0;         ///< engine step of the last build (how long a list lasts picks the skin)
  std::vector<Vec3> built_positions;    ///< [m] every particle's position at the last build (skin check)
  Vec3 built_tank_displacement = Vec3::Zero();  ///< [m] the tank's displacement at the last build
  /// The particles were reordered since the build (fluid_cell_sort): the lists hold old slots and must be rebuilt,
  /// while built_positions, reordered with the particles, still tell how far each particle has moved.
  bool reordered = false;
  /// The neighbours actually within r_e at the predicted positions r* (a subset of each Verlet list, ascending),
  /// recorded by fluid_free_surface for the pressure solve and the correction: particle i's are
  /// near_slots[offsets[i] .. offsets[i] + near_count[i]).
  std::vector<std::uint32_t> near_count;
  std::vector<std::uint32_t> near_slots;
  /// In a periodic tank ([tank] periodic): the halo built with the lists (slots [N, N + G) of the lists are its
  /// ghosts) and the ghost copies the operators read (docs/ARCHITECTURE.md, "Periodic boundaries and the halo").
  /// Invalid (and empty) otherwise.
  Halo halo;
  FluidGhosts ghosts;
  /// In a run whose water is spread over MPI ranks: this rank's box, and the other ranks' particles (and a periodic
  /// tank's images) within the lists' reach, held in slots [N, N + G) with their fields in `ghosts`, in place of the
  /// periodic halo (which is then invalid). Inactive otherwise.
  FluidRankHalo ranks;

  std::size_t particle_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

}  // namespace riffle
