#pragma once
// The immutable description of a run, parsed and validated from a scene file. Systems receive it as const; the
// mutable state lives in the World. A checkpoint stores the scene text, so the model is rebuilt on resume.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "components/grain_specs.hpp"
#include "components/mean_flow.hpp"
#include "components/vec.hpp"

namespace riffle {

struct Solids;

/// A scene choice's spellings beside the enum values they stand for, in the order messages list them: the scene's
/// word and the code's value are named once, here (the scene reader reads them with enum_choice).
template <typename Enum, std::size_t N>
using SceneNames = std::array<std::pair<const char*, Enum>, N>;

struct Material {
  std::string name;
  double density = 0.0;        ///< [kg/m^3]
  double young_modulus = 0.0;  ///< [Pa] E; needed when [contact] is present
  double poisson_ratio = 0.0;  ///< [1] nu
};

enum class ContactLaw {
  kHertzMindlin,        ///< seed 003 Sec. 2.2: Hertz normal, Mindlin no-slip tangential, restitution damping
  kLinearSpringDashpot  ///< seed 004 Sec. 2.2: linear spring-dashpot whose stiffness is set by a collision time
};

/// How rolling friction acts (Ai, Chen, Rotter & Ooi 2011, Powder Technol. 206, 269: their models A and C).
enum class RollingLaw {
  /// T = -mu_r R* F_n w_rel / |w_rel| (seed 003 Eq. 20; model A): no state, but its sign follows the spin of each
  /// sub-step, so a contact at rest chatters and a bed under a torque below mu_r R* F_n creeps at a speed of first
  /// order in the sub-step.
  kConstantTorque,
  /// An elastic-plastic spring-dashpot on the relative rotation (model C): a spring torque, incremented by
  /// -k_r w_rel dt each sub-step and capped at mu_r R* F_n, plus a dashpot while below the cap; it holds a contact at
  /// rest under any torque below the cap (systems/physics/dem/contact_law.hpp).
  kElasticPlastic
};

/// Contact constants of one pair of materials, derived once when the scene is read.
struct ContactPairParameters {
  double restitution = 1.0;       ///< [1] requested normal coefficient of restitution e, in [0, 1]
  /// [1] the restitution the damping is calibrated to: e itself, or for e = 0 (perfectly plastic, which no finite
  /// dashpot reaches) half the scene's restitution_tolerance, so that the achieved value is within the tolerance of 0.
  double calibrated_restitution = 1.0;
  double friction = 0.0;          ///< [1] Coulomb sliding friction mu
  double rolling_friction = 0.0;  ///< [1] mu_r; rolling torque -mu_r R* F_n (direction of relative spin)
  double effective_young = 0.0;   ///< [Pa] E*: 1/E* = (1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j
  double effective_shear = 0.0;   ///< [Pa] G*: 1/G* = (2 - nu_i)/G_i + (2 - nu_j)/G_j
  /// [1] dimensionless damping c of the law's normal equation x'' = -f(x) - c g(x) x', calibrated so that the
  /// achieved restitution (with the no-tension cut-off) equals `restitution` exactly; see contact_law.hpp.
  double damping = 0.0;

  // Derived by prepare_contact_pair (systems/physics/dem/contact_law.hpp), so the pair loop does no logarithms and fewer roots:
  //   Hertz:  k_n = A sqrt(R* d), gamma_n = c sqrt(k_n m*), k_t = B sqrt(R* d), gamma_t = T gamma_n
  //   linear: k_n = A m*,         gamma_n = D m*,           k_t = B k_n,         gamma_t = T gamma_n
  double normal_stiffness_coefficient = 0.0;      ///< A: Hertz 4/3 E* [Pa]; linear (pi^2 + ln^2 e)/t_c^2 [1/s^2]
  double normal_damping_coefficient = 0.0;        ///< D: linear c sqrt(A) [1/s]; unused by Hertz
  double tangential_stiffness_coefficient = 0.0;  ///< B: Hertz 8 G* [Pa]; linear 2/7
  double tangential_damping_ratio = 0.0;          ///< T: Hertz sqrt(4 G*/E*) (seed 003's ratio); linear 2/7
};

struct ContactModel {
  bool enabled = false;
  ContactLaw law = ContactLaw::kHertzMindlin;
  RollingLaw rolling_law = RollingLaw::kElasticPlastic;  ///< holds a contact at rest below its cap at every sub-step
  std::size_t material_count = 0;
  std::vector<ContactPairParameters> pairs;  ///< material_count x material_count, symmetric; [a * count + b]
  double collision_time = 0.0;     ///< [s] linear law: duration of a normal collision
  double max_impact_speed = 1.0;   ///< [m/s] impact speed for the Hertz contact-time estimate
  double rayleigh_fraction = 0.25; ///< sub-step <= this fraction of the Rayleigh time
  double steps_per_collision = 16; ///< sub-step <= contact time / this
  double skin = 0.0;               ///< [m] Verlet skin of the neighbour list
  std::int64_t sort_every_rebuild = 10;  ///< reorder grains by cell every this many neighbour rebuilds
  /// [1] the achieved restitution of a head-on impact at max_impact_speed, integrated at the chosen sub-step, must be
  /// within this of the requested one (absolute); the sub-step is shortened until it is (see stable_solid_step).
  double restitution_tolerance = 0.02;
  double stable_solid_dt = 0.0;    ///< [s] largest sub-step allowed by the estimates (filled by the scene reader)
  std::string stable_solid_dt_reason;  ///< which estimate sets stable_solid_dt (for `riffle check` and errors)
  /// [1] worst |achieved - requested| restitution at the run's sub-step over the pairs in use (filled by the reader)
  double restitution_error = 0.0;
  std::string restitution_error_pair;  ///< the pair with that worst error

  const ContactPairParameters& pair(std::int32_t a, std::int32_t b) const {
    return pairs[static_cast<std::size_t>(a) * material_count + static_cast<std::size_t>(b)];
  }
};

/// A tank motion read from a CSV file ([tank.motion] kind = "table"): displacement per axis at tabulated times,
/// interpolated by a not-a-knot cubic spline per axis (systems/physics/math/cubic_spline.hpp), whose second derivatives
/// the scene reader computes once. Axes the file does not list stay at zero (empty vectors).
struct MotionTable {
  std::string file;                                ///< the CSV as resolved (relative to the scene file), for messages
  std::vector<double> time;                        ///< [s] strictly increasing, at least 4
  std::array<std::vector<double>, 3> displacement; ///< [m] per axis, one per time; empty for an axis not in the file
  std::array<std::vector<double>, 3> curvature;    ///< [m/s^2] the spline's second derivatives at the times
};

/// Prescribed rigid translation of the tank.
/// Sinusoidal: x(t) = -A r(tau) sin(2 pi f tau + phase) along `direction`, tau = t - start_time (seed 000 Eq. 1 with
/// phase = start_time = 0), with r a C2 quintic ramp from 0 to 1 over `ramp_time` (the seed's "accelerated gradually
/// at the onset"); before start_time the tank rests at x(start_time).
/// Table: the spline through `table`; before its first and after its last time the tank rests at the end's
/// displacement.
struct TankMotionModel {
  enum class Kind { kNone, kSinusoidal, kTable };
  Kind kind = Kind::kNone;
  Vec3 direction = Vec3::UnitX();  ///< [1] unit vector (a table: the first axis it lists, for the diagnostics)
  double amplitude = 0.0;          ///< [m] A
  double frequency = 0.0;          ///< [Hz] f
  double ramp_time = 0.0;          ///< [s] 0 = start at full amplitude
  double phase = 0.0;              ///< [rad] (the scene gives degrees)
  double start_time = 0.0;         ///< [s] the tank rests before it
  MotionTable table;               ///< kind = kTable only
};

/// The tank's faces by name, in claiming order (a wall or dummy particle beyond several faces belongs to the first):
/// index 2 axis + side, side 0 the low face. The names of [tank] open_faces and of a transducer's face.
inline const std::array<std::string, 6> kTankFaceNames = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
inline const std::string& tank_face_name(int axis, int side) {
  return kTankFaceNames[static_cast<std::size_t>(2 * axis + side)];
}

struct TankModel {
  Vec3 size = Vec3::Zero();            ///< [m] inner size along x, y, z
  Vec3 origin = Vec3::Zero();          ///< [m] inner min corner at rest
  std::vector<std::string> open_faces; ///< faces without a wall: any of x_min, x_max, y_min, y_max, z_min, z_max
  std::int32_t wall_material = 0;      ///< index into Model::materials
  double domain_margin = 0.05;         ///< [m] a particle further than this outside the swept tank is lost
  /// [1] per axis: periodic (no walls on its two faces; the period is size[axis]); only x and y may be
  std::array<bool, 3> periodic{false, false, false};
  TankMotionModel motion;
  bool any_periodic() const { return periodic[0] || periodic[1] || periodic[2]; }
  /// Whether the face (axis, side) is listed in open_faces (a periodic axis's faces have no wall either).
  bool face_open(int axis, int side) const {
    const std::string& name = tank_face_name(axis, side);
    for (const std::string& face : open_faces)
      if (face == name) return true;
    return false;
  }
};

/// A box of particles on the fluid lattice, given by two corners (fluid blocks and solid wall blocks).
struct ParticleBoxModel {
  Vec3 low = Vec3::Zero();       ///< [m] min corner
  Vec3 high = Vec3::Zero();      ///< [m] max corner
  Vec3 velocity = Vec3::Zero();  ///< [m/s] initial velocity (fluid boxes only)
  /// Wall boxes only: an optional name (unique among them) by which a pressure transducer is put on the box's face.
  std::string name{};
  /// false: the lattice points of the tank's lattice inside [low, high] (snapped, the default); true ("extent"):
  /// a lattice of its own at spacing l0 that fills the given extent (engine/setup/fluid_layout.hpp box_grid).
  bool fit_extent = false;
  /// Wall boxes only: a moving lid (docs/FLUID.md, "Driven flows"). lid_velocity [m/s] along x; the box's particles
  /// move as an infinite plane: x wraps within the box's own x extent (lid_period, a whole number of spacings), so
  /// none ever leaves the box. No-slip: the particles' velocity enters the viscous term; free-slip: they take no
  /// part in it (the water slides along them) and lid_velocity must be 0.
  bool lid = false;
  double lid_velocity = 0.0;
  bool lid_free_slip = false;
  double lid_period = 0.0;  ///< [m] the x extent the particles wrap in: the box's particle count along x times l0
  double lid_start_x = 0.0; ///< [m] where that extent starts: the first particle's x less l0/2 (tank at rest)
  double lid_area = 0.0;    ///< [m^2] the plane's area the traction is reported over: lid_period times its y extent
  /// [m] z of the lid's two no-slip planes (tank at rest): the cell faces of its lowest and highest particle layers.
  /// A no-slip lid is horizontal: the water below or above it sees its velocity extrapolated across these planes.
  double lid_plane_low = 0.0;
  double lid_plane_high = 0.0;
};

/// A body force along x on the water (docs/FLUID.md, "Driven flows"): the stand-in for a mean pressure gradient
/// -dp/dx = rho f. Constant f, a sinusoid F sin(2 pi t / T + phase), or the output of a PI controller that holds the
/// bulk velocity of the water at a target (systems/physics/mps/driven_flow.hpp).
struct BodyForceModel {
  enum class Kind { kNone, kConstant, kSinusoidal, kBulkVelocity };
  Kind kind = Kind::kNone;
  double acceleration = 0.0;     ///< [m/s^2] constant: f; sinusoidal: the amplitude F
  double period = 0.0;           ///< [s] sinusoidal: T
  double phase = 0.0;            ///< [rad] sinusoidal (the scene gives degrees)
  double target_velocity = 0.0;  ///< [m/s] bulk_velocity: U
  double proportional_gain = 0.0;  ///< [1/s] bulk_velocity: K_p, f = K_p e + K_i int e dt, e = U - U_bulk
  double integral_gain = 0.0;      ///< [1/s^2] bulk_velocity: K_i
  /// How the grains feel it (docs/COUPLING.md, "Driven flows and the grains"): kNone: only through the MPS pressure;
  /// kPressureGradient: plus V_p rho_f f along x (the mean pressure gradient the body force stands for, which the
  /// MPS pressure does not hold); kFrame: plus m_p f (a frame acceleration or tilted gravity: it acts on all mass).
  enum class Grains { kNone, kPressureGradient, kFrame };
  Grains grains = Grains::kPressureGradient;

  /// f(t) [m/s^2] of a constant or sinusoidal body force: f, or F sin(2 pi t / T + phase); 0 for kNone. A
  /// bulk-velocity controller's force is its state (BulkVelocityController), not a function of time: refused here.
  double prescribed(double time) const {
    switch (kind) {
      case Kind::kNone: return 0.0;
      case Kind::kConstant: return acceleration;
      case Kind::kSinusoidal: return acceleration * std::sin(2.0 * std::numbers::pi * time / period + phase);
      case Kind::kBulkVelocity: break;
    }
    throw std::logic_error("prescribed body force: a bulk-velocity force is the controller's state");
  }
};

/// [fluid.initial_velocity]: an initial velocity profile along x added to the fluid boxes' velocities
/// (systems/physics/mps/initial_profile.hpp); kind none = absent.
struct InitialVelocityModel {
  enum class Kind { kNone, kLinear, kPower };
  Kind kind = Kind::kNone;
  double bottom = 0.0;        ///< [m] z0: no velocity at and below it (scene coordinates, the tank at rest)
  double top = 0.0;           ///< [m] z1 > z0: top_velocity at and above it
  double top_velocity = 0.0;  ///< [m/s] u_top along x
  double exponent = 1.0 / 7.0;  ///< [1] kPower: u = u_top ((z - z0) / (z1 - z0))^exponent
};

/// The enhanced MPS schemes of seed 000 Sec. 3.1, each switchable so that its cost and benefit can be measured.
/// Off means the classic Koshizuka-Oka counterpart (numerics.md 1.4): HS off = density-deviation source
/// (n* - n0)/(n0 dt^2); HL off = lambda0 Laplacian; GC off = plain gradient with p_j - min_j p_j; ECS, DS off = absent.
struct FluidSchemes {
  bool higher_order_source = true;        ///< HS, Eq. 5
  bool error_compensating_source = true;  ///< ECS, Eq. 6
  bool higher_order_laplacian = true;     ///< HL, Eq. 7 with the closure a = -2 w'/r (numerics 2.5)
  bool gradient_correction = true;        ///< GC, Eqs. 8-9
  bool dynamic_stabilisation = true;      ///< DS, Eqs. 10-12 (repulsive, numerics 2.7)
  /// Not of seed 000: in place of GC, the hydrostatic gradient G plus a sum form (q_i + q_j) of the rest of the
  /// pressure, q = p - G . r - min, which conserves the water's momentum pair by pair (GC does not: docs/COUPLING.md
  /// "Where the total momentum goes"); for sealed boxes full of water (docs/FLUID.md, "A momentum-conserving
  /// gradient").
  bool conservative_gradient = false;
  /// fluid.schemes.grain_gradient: with conservative_gradient, what the grains sample (pressure_gradient): kApplied
  /// ("applied", the default) the gradient that moved the water, so that the grains take the share of every stress the water carries, the
  /// sum form's own included, and a sheared bed takes the lid's drag; kCorrected ("corrected") GC's gradient of the same
  /// pressure, first-order accurate at each grain but blind to the momentum the sum form carries through the water
  /// (docs/FLUID.md, "What the grains sample").
  enum class GrainGradient { kApplied, kCorrected };
  static constexpr SceneNames<GrainGradient, 2> kGrainGradientNames{
      {{"applied", GrainGradient::kApplied}, {"corrected", GrainGradient::kCorrected}}};
  GrainGradient grain_gradient = GrainGradient::kApplied;
};

/// What the MPS operators derive from l0 and r_e / l0 (numerics.md 1.1), worked out once when the scene has been read
/// (fill_mps_constants, systems/physics/mps/mps_common.hpp) and read by the fluid and coupling systems and the probes.
/// It keeps the l0 and r_e / l0 it was derived from: mps_constants() refuses a model changed after (a stale copy).
struct MpsConstants {
  double spacing = 0.0;                 ///< [m] l0 they were derived from
  double effective_radius_ratio = 0.0;  ///< [1] r_e / l0 they were derived from
  double effective_radius = 0.0;        ///< [m] r_e = (r_e / l0) l0, one radius for every operator (amendment 6)
  double reference_density = 0.0;       ///< [1] n0 of the interior of the initial cubic lattice
  double laplacian_lambda = 0.0;        ///< [m^2] lambda0 (viscosity, and the classic Laplacian when HL is off)
  double particle_volume = 0.0;         ///< [m^3] l0^3
};

/// The incompressible free-surface fluid (MPS, seed 000 Sec. 3.1; numerics.md with the prototype's amendments).
struct FluidModel {
  bool enabled = false;
  double spacing = 0.0;                  ///< [m] l0, the initial lattice spacing
  double effective_radius_ratio = 2.4;   ///< [1] r_e / l0, one radius for every operator
  double density = 1000.0;               ///< [kg/m^3] rho
  double kinematic_viscosity = 1.0e-6;   ///< [m^2/s] nu
  std::vector<ParticleBoxModel> boxes;       ///< fluid blocks
  std::vector<ParticleBoxModel> wall_boxes;  ///< solid blocks of wall particles that move with the tank
  bool tank_walls = true;                ///< wall and dummy particles on the closed faces of [tank]
  FluidSchemes schemes;
  bool clamp_negative_pressure = true;   ///< p < 0 -> 0 after the solve (numerics 2.8)
  double surface_threshold = 0.93;       ///< [1] beta: free surface where n* < beta n0 (amendment: not 0.97)
  /// [1/s] gamma / dt of the density term gamma (n* - n0)/(n0 dt^2). The prototype's 12 /s let a shaken 3D slab
  /// compress by 1.8 % and still water deeper than 12 layers drift away; 48 /s holds 24 layers still and keeps the
  /// shaken slab within 0.3 % (docs/BENCHMARKS.md, tests/verification/fluid_*).
  double density_relaxation_rate = 48.0;
  double compressibility = 1.0e-9;       ///< [1/Pa] alpha_c, keeps every PPE cluster well posed
  /// [m/s] c of the quasi-compressible pressure equation (docs/FLUID.md, "Impact pressure"): the row of an unknown
  /// gains n0 (p - p^k) / (c^2 dt^2), the continuity equation (1/(rho c^2)) Dp/Dt = -div u of a fluid with sound
  /// speed c (Tanaka & Masunaga 2010; Ikari et al. 2015). 0 = off: the incompressible equation.
  double sound_speed = 0.0;
  double courant = 0.2;                  ///< [1] C_r: dt <= C_r l0 / |u|max; alpha_DS = 1 - C_r (seed)
  double diffusion_number = 0.2;         ///< [1] dt <= this l0^2 / nu
  /// [1] dt <= this sqrt(l0 / |g|) l0 / H, H the water's depth (its particles' extent along gravity plus l0): still
  /// water deeper than about 4 / (dt sqrt(|g| / l0)) layers grows a motion from its surface down and blows up, from
  /// 2.5 it is noisy (docs/FLUID.md, "Deep water's step limit"); 2 keeps it still.
  double hydrostatic_number = 2.0;
  double min_dt = 1.0e-6;                ///< [s] a step below this stops the run as unstable
  double solver_tolerance = 1.0e-8;      ///< [1] PCG stops at |r| <= tol |b| (1e-6 shifts the sloshing frequency by 1 %)
  std::int64_t solver_max_iterations = 2000;
  enum class Preconditioner { kJacobi, kTwoLevel, kBoomerAmg };
  /// Jacobi, Jacobi plus an aggregation coarse solve (in-house), or hypre's PCG with BoomerAMG (builds with hypre)
  Preconditioner preconditioner = Preconditioner::kTwoLevel;
  double neighbour_skin_ratio = 0.3;     ///< [1] Verlet skin / l0 of the neighbour lists
  double narrow_neighbour_skin_ratio = 0.1;  ///< [1] the skin / l0 when the last lists lasted one step (<= the skin)
  std::int64_t sort_every = 20;          ///< [steps] reorder fluid particles by cell this often (memory locality); 0 = never
  /// [steps] ... and this often while the fastest particle moves more than 0.15 l0 in a step: then hardly a list
  /// outlives a step (half the default skin of 0.3 l0; the next fastest moves about as far), so a sort costs no extra
  /// rebuild; 0 = only sort_every
  std::int64_t sort_every_fast = 5;
  /// What happens to a fluid particle that escapes (systems/mps/fluid_escape.hpp): kRemove takes it out of the
  /// water (counted, logged, reported; the run stops only when more than escape_fraction_limit of the fluid has
  /// gone), kStop stops the run with the left-domain diagnosis at the first one.
  enum class EscapePolicy { kRemove, kStop };
  EscapePolicy escape = EscapePolicy::kRemove;
  /// [m] with kRemove, a lone fluid particle (no other MPS particle within r_e) farther than this outside the tank's
  /// inner box (moving with the tank) is removed too; infinity = only particles that leave the domain box.
  double escape_distance = std::numeric_limits<double>::infinity();
  /// [1] the run stops with a diagnosis once more than this fraction of the fluid laid out has been removed.
  double escape_fraction_limit = 0.01;
  BodyForceModel body_force;  ///< [fluid.body_force]; kind none = absent
  InitialVelocityModel initial_velocity;  ///< [fluid.initial_velocity]; kind none = absent
  /// The sub-particle-scale eddy viscosity (docs/FLUID.md, "Turbulence"): nu_t = (C_s l0)^2 |S| added to nu in the
  /// viscous term (Gotoh, Shibahara & Sakai 2001; Shao & Gotoh 2005). Off by default.
  enum class Turbulence { kNone, kSps };
  Turbulence turbulence = Turbulence::kNone;
  double smagorinsky_constant = 0.12;  ///< [1] C_s
  /// [1] C_p of the particle-scale viscosity nu_p = C_p l0 s, s a particle's velocity scatter about the linear fit
  /// through its neighbours (0: off; docs/FLUID.md, "Disordered water's particle-scale noise").
  double scatter_viscosity = 0.0;
  /// Particle shifting after each step (docs/FLUID.md, "Particle shifting"; systems/mps/fluid_shift.hpp): each fluid
  /// particle moves by delta r = -D grad C (Lind et al. 2012), its velocity carried along to first order. Off by
  /// default (and then the step graph has no fluid_shift).
  enum class Shifting { kOff, kFickian };
  Shifting shifting = Shifting::kOff;
  /// kVelocity: D = A h |u| dt (Skillen et al. 2013); kConstant: D = A h^2 (Lind et al. 2012); h = r_e / 2.
  enum class ShiftingDiffusivity { kVelocity, kConstant };
  ShiftingDiffusivity shifting_diffusivity = ShiftingDiffusivity::kVelocity;
  double shifting_coefficient = 2.0;  ///< [1] A (the scene's default: 2 for kVelocity, 0.25 for kConstant)
  double shifting_max_ratio = 0.1;    ///< [1] the largest shift per step / l0
  bool shifting_velocity_correction = true;  ///< u += (delta r . grad) u after the shift (Lind et al. 2012)
  /// The water's starting arrangement (docs/FLUID.md, "A packed start"; systems/physics/mps/particle_packing.hpp):
  /// the cubic lattice, or packed off it into a disordered arrangement of uniform number density.
  enum class Arrangement { kLattice, kPacked };
  Arrangement initial_arrangement = Arrangement::kLattice;
  /// Derived from spacing and effective_radius_ratio by fill_mps_constants once they are final (the scene reader
  /// calls it; so must code that builds a model by hand); zero while the fluid is off.
  MpsConstants constants;

  bool has_lids() const {
    for (const ParticleBoxModel& box : wall_boxes)
      if (box.lid) return true;
    return false;
  }
  /// fluid_predict also writes FluidSummary (the applied body force, the lids' traction) only when a scene has these.
  bool reports_driving() const { return body_force.kind != BodyForceModel::Kind::kNone || has_lids(); }

  double effective_radius() const { return spacing * effective_radius_ratio; }
  double stabilisation_distance() const { return (1.0 - courant) * spacing; }  ///< d_ij = alpha_DS l0
};

/// Unresolved fluid-grain coupling (seed 000 Secs. 3.2-3.3; numerics.md 5). On whenever a scene has both grains and
/// a fluid; [coupling] tunes it.
struct CouplingModel {
  bool enabled = false;
  bool drag = true;                      ///< Ergun / Wen-Yu drag and its reaction on the fluid (Eqs. 20-26)
  bool pressure_gradient = true;         ///< -V <grad p> on each grain (Eq. 13): buoyancy and pressure forces
  /// V rho <nu lap u> on each grain: the water's viscous (and eddy) stress divergence over the grain's volume, the
  /// other half of Anderson & Jackson's generalised buoyancy -V grad p + V div tau (docs/COUPLING.md, "The viscous
  /// stress on the grains"). With the mixture reading it closes the momentum the water gives a sheared bed: the water
  /// takes the drag over eps, the grains the drag plus this share (1 - eps)/eps of it in steady shear.
  bool viscous_stress = false;
  double voidage_radius = 0.0;           ///< [m] R_eps of the voidage kernel; 0 = max(3 l0, 2 d_max) (numerics 5.3)
  /// [m] R_eps across the bed (along z); 0 = voidage_radius. A thin bed needs a kernel narrower across it than along
  /// it (docs/COUPLING.md, "A thin bed's voidage").
  double voidage_vertical_radius = 0.0;
  /// coupling.voidage_volume, what the grains' volume is divided by: kFluidParticles ("fluid_particles") the volume
  /// the fluid particles fill, deposited on the same grid (walls and the free surface truncate both alike); kTank
  /// ("tank") the volume of the tank box each node covers, exact and free of the lattice's aliasing, for water that
  /// fills the tank around the grains.
  enum class VoidageVolume { kFluidParticles, kTank };
  static constexpr SceneNames<VoidageVolume, 2> kVoidageVolumeNames{
      {{"fluid_particles", VoidageVolume::kFluidParticles}, {"tank", VoidageVolume::kTank}}};
  VoidageVolume voidage_volume = VoidageVolume::kFluidParticles;
  double min_voidage = 0.26;             ///< [1] epsilon is clipped to [min_voidage, 1]
  /// [1] The step is at most drag_number / lambda, lambda the fastest rate at which the grains' drag relaxes the water
  /// around them (systems/physics/time/time_step.hpp, water_drag_rate; docs/COUPLING.md "The drag's step limit"). The
  /// reaction is explicit and a step late in the water: u_{n+2} = u_{n+1} - a u_n with a = lambda_tangent dt grows for
  /// a > 1; the tangent is at most twice the secant lambda, so 0.5 keeps a <= 1. 0 = no limit.
  double drag_number = 0.5;
  /// coupling.voidage_estimate: kSelfCorrected ("self_corrected", docs/COUPLING.md "The voidage at a grain") a
  /// smoothed grid, the grain's own volume taken out exactly and put back times 1 - S(0) (a lone grain reads 1);
  /// kCloudInCell ("cloud_in_cell") the trilinear grid reading with the grain's own volume included (a lone grain
  /// reads 0.93-0.96, rippling with its place in a cell).
  enum class VoidageEstimate { kSelfCorrected, kCloudInCell };
  static constexpr SceneNames<VoidageEstimate, 2> kVoidageEstimateNames{
      {{"self_corrected", VoidageEstimate::kSelfCorrected}, {"cloud_in_cell", VoidageEstimate::kCloudInCell}}};
  VoidageEstimate voidage_estimate = VoidageEstimate::kSelfCorrected;
  double ergun_inertial_exponent = 1.5;  ///< [1] n in F_ch = 1.75 / (sqrt(150) eps^n): 1.5 = Ergun/Gidaspow; the seed prints 3 (numerics 5.1)
  double newton_drag_coefficient = 0.44; ///< [1] C_D above Re_p = 1000 (the seed prints 0.4)
  /// coupling.dense_drag: kErgun ("ergun", the seed's Gidaspow switch) Ergun at eps <= 0.8, Wen & Yu above; kWenYu
  /// ("wen_yu") Wen & Yu at every voidage (their eps^-4.7 was fitted to fluidised beds and suspensions over
  /// 0.4 < eps < 1; Ergun's packed-bed law makes a suspension at eps = 0.7 settle 28 % slower than Richardson & Zaki;
  /// docs/COUPLING.md).
  enum class DenseDrag { kErgun, kWenYu };
  static constexpr SceneNames<DenseDrag, 2> kDenseDragNames{{{"ergun", DenseDrag::kErgun},
                                                             {"wen_yu", DenseDrag::kWenYu}}};
  DenseDrag dense_drag = DenseDrag::kErgun;
  /// coupling.fluid_velocity, what the MPS velocity u stands for inside the bed (docs/COUPLING.md, "The water inside
  /// the bed"); systems/physics/coupling/drag_law.hpp flux_share says what it changes.
  /// kPore ("pore", the seed's reading): the pore water's velocity; the water filling all space then passes 1/eps^2
  /// too much Darcy flux for a pressure gradient and loads the grains with (2 - eps) times the seepage force.
  /// kMixture ("mixture"): the volume flux of the mixture, eps u_pore + (1 - eps) u_s, which is what an incompressible
  /// fluid filling all space (div u = 0, wall velocity at the walls) can carry exactly. The pore water moves
  /// relative to a grain at (u - u_s) / eps (the drag's slip), and the water receives the drag per volume over eps,
  /// so steady Darcy-Forchheimer flow and the seepage force are right; the pore water's relative inertia is eps
  /// too small. The default is the mixture reading: it passes hindered settling (docs/COUPLING.md,
  /// "Hindered settling"), where the pore reading's water does not flow back up and the suspension falls 1/eps too
  /// fast.
  enum class FluidVelocity { kPore, kMixture };
  static constexpr SceneNames<FluidVelocity, 2> kFluidVelocityNames{{{"pore", FluidVelocity::kPore},
                                                                     {"mixture", FluidVelocity::kMixture}}};
  FluidVelocity fluid_velocity = FluidVelocity::kMixture;
  /// Normal lubrication of the water squeezed between grains and between a grain and a wall (docs/COUPLING.md,
  /// "Lubrication"): the excess over the drag law's Stokes drag, for gaps below the cut-off, the gap held at the
  /// roughness below it. Both lengths are in reduced radii a* = a_1 a_2 / (a_1 + a_2) (a grain's radius for a wall),
  /// or in metres when the scene gives them in metres (`*_absolute`).
  bool lubrication = false;
  double lubrication_cutoff = 1.0;            ///< [1] gap cut-off / a*, or [m] if lubrication_cutoff_absolute
  bool lubrication_cutoff_absolute = false;
  double roughness = 1.0e-3;                  ///< [1] roughness / a*, or [m] if roughness_absolute
  bool roughness_absolute = false;

  double lubrication_cutoff_gap(double reduced_radius) const {
    return lubrication_cutoff_absolute ? lubrication_cutoff : lubrication_cutoff * reduced_radius;
  }
  double roughness_gap(double reduced_radius) const {
    return roughness_absolute ? roughness : roughness * reduced_radius;
  }
  /// Added mass C_a(eps) rho V (Du/Dt - dv/dt), C_a = 1/2 (1 + 2 phi)/(1 - phi) (Zuber 1964), integrated
  /// implicitly in the grains' kicks; the water takes it back (docs/COUPLING.md, "Added mass and history force").
  bool added_mass = false;
  /// The history force with a windowed kernel of exponential modes (solid_history_force), on dilute grains (voidage
  /// above 0.8: a lone sphere's kernel); inside a bed it is zero and its memory restarts when the grain leaves.
  /// A scene turns it on unless it says otherwise wherever added mass and the self-induced correction are both on
  /// (the unsteady forces of Maxey & Riley on the undisturbed slip: engine/scene/scene.cpp); a Model built in code
  /// starts with it off.
  bool history_force = false;
  /// coupling.history_kernel: kMeiAdrian ("mei_adrian", the default) Mei & Adrian's (1992) finite-Re kernel, t^(-1/2)
  /// for t << t_H and t^(-2) beyond, t_H = 1.08 nu f_H^2 / |w|^2 (systems/physics/coupling/added_mass.hpp); kBasset
  /// ("basset") Basset's t^(-1/2), exact only for Re_p << 1.
  enum class HistoryKernel { kMeiAdrian, kBasset };
  static constexpr SceneNames<HistoryKernel, 2> kHistoryKernelNames{{{"mei_adrian", HistoryKernel::kMeiAdrian},
                                                                     {"basset", HistoryKernel::kBasset}}};
  HistoryKernel history_kernel = HistoryKernel::kMeiAdrian;
  /// [s] the modes' longest memory: the kernel is itself up to about window/30 and decays as exp(-t/window) beyond.
  /// With Mei & Adrian's kernel a numerical bound only (t_H is 0.01-0.3 s for grains at Re_p 1-100 in water and oil).
  double history_window = 1.0;
  /// Drag and pressure force from the water the grain would see without its own disturbance (docs/COUPLING.md,
  /// "The undisturbed fluid velocity"): the drag reaction is spread with the sampling kernel, and the grain's own
  /// regularised Stokes/Oseen disturbance (Balachandar et al. 2019), built up over time and held back by the tank's
  /// walls (Blake's image system), is taken out of the sampled velocity and pressure gradient. Dilute grains only
  /// (voidage above 0.8, Wen & Yu's branch). A scene turns it on unless it says otherwise wherever it holds (the MPS
  /// water with the isotropic sampling kernel: engine/scene/scene.cpp); a Model built in code starts with it off.
  bool self_induced_velocity = false;
  /// How each grain's drag impulse goes back to the water (docs/COUPLING.md, "Where the drag reaction lands").
  /// false ("grid", the calibrated default): through a cloud-in-cell grid of cells 0.668 (r_max + r_e). true
  /// ("sampling_kernel"): to the fluid particles within R = r + r_e with the normalised Wendland weights the grain
  /// samples the water with, so a grain pushes the water it reads and the reaction's power on the water is
  /// -beta |u_bar|^2 <= 0 for a held grain (the grid's pushes the pore water under a bed backwards).
  bool sampling_kernel_reaction = false;
  /// [m] R_v, the sampling kernel's radius across the bed (along z); 0 = isotropic (docs/COUPLING.md, "A thin bed's
  /// sampling"). Each grain reads (and, with sampling_kernel_reaction, pushes) the water with the ellipsoidal
  /// Wendland kernel w(s R_h), s^2 = (dx^2 + dy^2) / R_h^2 + dz^2 / min(R_v, R_h)^2, R_h = r + r_e as before.
  double sampling_vertical_radius = 0.0;
  /// The shear lift on each grain from the velocity difference across it (Wiberg & Smith 1985; systems/physics/
  /// mean_flow/grain_forces.hpp shear_lift), with the mean-flow fluid only (docs/cases/bedload.md, "Lift and velocity
  /// fluctuations").
  bool lift = false;
  double lift_coefficient = 0.2;  ///< [1] C_L (Wiberg & Smith 1987 after Chepil 1958)
};

struct SolidsModel {
  bool enabled = false;
  std::string initial_state;           ///< checkpoint whose grains start this run (resolved path), or empty
  /// The grains of initial_state, read and validated once when the scene is read, material indices mapped to this
  /// scene's materials and masses to its densities (engine/setup/initial_state.hpp read_initial_grains); null
  /// without initial_state or when it could not be read (a scene problem then).
  std::shared_ptr<const Solids> initial_grains;
  std::vector<SphereSpec> spheres;     ///< [[solids.spheres]], in scene order
  /// The generated grains, as the scene describes them; laid out once when a run starts (engine/setup), in this
  /// order after the spheres: blocks, layered beds, fills, each in scene order.
  std::vector<SphereBlockSpec> blocks;      ///< [[solids.blocks]]
  std::vector<LayeredBedSpec> layered_beds; ///< [[solids.layered_beds]]
  std::vector<FillSpec> fills;              ///< [[solids.fills]]
  std::int64_t sort_every = 0;         ///< [steps] reorder grains by grid cell this often; 0 = never
  /// Grains carried rigidly with the tank (a fixed bed: forces are still computed and written, the grains do not
  /// respond). For fixed-bed flows and for separating what the water does from what the bed does (docs/RESULTS.md).
  bool fixed_to_tank = false;
  /// [s] the grains are held as with fixed_to_tank during the sub-steps that start before this time, then released
  /// (seed 003 Sec. 4 holds its bed while the flow develops); the default -infinity: never held.
  double hold_until = -std::numeric_limits<double>::infinity();
  /// Whether the grains are held (fixed_to_tank, or hold_until not reached) in the sub-step that starts at `time`.
  /// The run's time is a sum of steps, so a hold_until on a step boundary arrives rounded (2 s after 4000 steps of
  /// 5e-4 s is 1.99999999999984): a sub-step starting within hold_release_slack of hold_until counts as released.
  bool held(double time) const { return fixed_to_tank || time < hold_until - hold_release_slack; }
  /// [m] the grains whose centre lies below this height (z in the tank at rest) when a run starts are fixed for the
  /// whole run (GrainProperties::fixed): a rough floor of grains under a bed that moves. NaN: none.
  double fixed_below = std::numeric_limits<double>::quiet_NaN();
  /// [s] above the summed time's rounding (of order 1e-16 relative per step: 1.6e-13 s after 4000 steps to 2 s) and a
  /// thousandth of a 1 microsecond sub-step, so it never moves the release by a whole sub-step.
  static constexpr double hold_release_slack = 1e-9;
};

/// The count and sizes of the grains `solids` starts a run with, from its descriptions and initial_state's grains
/// alone, placing none (components/grain_specs.hpp): the numbers the laid-out grains give.
GrainSizes scene_grain_sizes(const SolidsModel& solids);

/// The spheres the scene's own tables make: [[solids.spheres]], blocks, layered beds and fills, initial_state's grains
/// apart. Exact, from the descriptions (a bed or fill that generates at all has its classes' counts).
std::int64_t scene_sphere_count(const SolidsModel& solids);

/// One [[output.probes]] entry: a CSV written while the run goes (engine/output/probes.hpp).
struct ProbeModel {
  enum class Kind {
    kGrains,         ///< chosen grains by id: motion, voidage, undisturbed fluid velocity, each force by source
    kWallForces,     ///< reaction force on each wall: minus the sum of its grain-wall contact forces
    kFluidPressure,  ///< pressure at sensors fixed to the tank (hydrostatically extrapolated Shepard average)
    kWaveGauge,      ///< height of the free surface above horizontal points of the tank
    kSurgeFront,     ///< furthest reach of the connected fluid along a horizontal direction
    kFluidTotals,    ///< the fluid's per-step summary (FluidSummary): count, volume, energy, PPE report
    kPressureTransducer,  ///< pressure averaged over discs on the tank's walls or a wall box's faces, optionally over a time window
    kMovingFraction,  ///< fraction of grains moving faster than `threshold` relative to the tank, all and per class
    kPackingDensity,  ///< planar packing density lambda of the bed's top layer of resting grains
    kBedloadFlux,     ///< grain volume flux per unit width per class, and its running time mean
    kVelocityProfile, ///< horizontally averaged x velocity of water and grains and solid fraction per layer
    kBedShearStress,  ///< bed shear stress from the momentum balance (and a lid's force) and Shields numbers
    kDrivenFlow,  ///< the body force applied, the water's bulk velocity, each moving lid's force on the water
    kMeanFlowProfile,   ///< the mean-flow column: velocity, solid fraction, eddy viscosity and stress per cell
    kBedloadTransport   ///< Theta, u*, q, q*, the moving fraction, speed and height over the mean-flow fluid's bed
  };
  Kind kind = Kind::kGrains;
  std::string name;                 ///< unique among the probes
  std::string file;                 ///< file name inside the output directory
  double interval = 0.0;            ///< [s] between rows; 0 = every engine step
  std::vector<std::uint64_t> ids;   ///< grains: grain ids (stable, not slots), in the order of the columns
  /// [m] fluid_pressure: sensor positions; wave_gauge: (x, y, 0) gauge positions; pressure_transducer: disc centres
  /// on the walls' inner faces. Tank frame (rest coordinates): the lab position is point + tank displacement, so a
  /// sensor on a wall moves with it.
  std::vector<Vec3> points;
  /// [1] pressure_transducer: for each disc, the unit normal of its wall pointing out of the water into the wall
  /// (the tank's x_min: -x; a wall box's x_min face: +x); the disc lies in the plane through its point normal to
  /// it. On a wall box the point is moved onto the face of the box's particle cells, the surface the water meets.
  std::vector<Vec3> normals;
  double diameter = 0.0;            ///< [m] pressure_transducer: the discs' diameter
  /// [s] pressure_transducer: each row is the time-weighted mean of the readings of the steps that ended in
  /// (t - average_window, t]; 0 = the reading at t alone
  double average_window = 0.0;
  double radius = 0.0;              ///< [m] wave_gauge: horizontal search radius around each gauge (default l0)
  Vec3 direction = Vec3::UnitX();   ///< [1] surge_front: unit horizontal direction of the front
  std::vector<double> lid_areas;    ///< [m^2] driven_flow: each moving lid's area (FluidModel::wall_boxes, lid only)
  /// [m] surge_front: only particles less than this above the tank floor count (infinity = the whole depth)
  double below = std::numeric_limits<double>::infinity();
  /// [m/s] moving_fraction, packing_density: a grain moves when |v - v_tank| exceeds this (seed 003: 0.01 m/s)
  double threshold = 0.01;
  /// [m] packing_density: depth of the top layer below the local bed top; 0 = 0.75 of the largest grain diameter
  double layer_depth = 0.0;
  /// [m] packing_density: if not NaN, the top layer is every resting grain with its centre above this height above
  /// the floor (seed 003's fixed height) instead of the local bed top less layer_depth
  double layer_bottom = std::numeric_limits<double>::quiet_NaN();
  double layer_thickness = 0.0;     ///< [m] velocity_profile: thickness of the horizontal layers
  bool lid = false;                 ///< bed_shear_stress: the scene has a lid (tau_lid_Pa is written)
};

struct OutputModel {
  double vtk_interval = 0.0;         ///< [s] 0 = no frames
  /// Over MPI ranks: kPerRank, every rank writes its own grains and water of a frame as a piece and rank 0 a .pvtp
  /// naming them (no gather); kGathered, rank 0 gathers the frame into one .vtp, as one rank writes it. One rank
  /// writes one .vtp either way.
  enum class VtkPieces { kPerRank, kGathered };
  static constexpr SceneNames<VtkPieces, 2> kVtkPiecesNames{
      {{"per_rank", VtkPieces::kPerRank}, {"gathered", VtkPieces::kGathered}}};
  VtkPieces vtk_pieces = VtkPieces::kPerRank;
  /// Where a frame's array bytes go: kAppended, raw after the XML (VTK's appended data); kInline, base64 inside each
  /// DataArray element (XML a plain parser reads whole).
  enum class VtkEncoding { kAppended, kInline };
  static constexpr SceneNames<VtkEncoding, 2> kVtkEncodingNames{
      {{"appended", VtkEncoding::kAppended}, {"inline", VtkEncoding::kInline}}};
  VtkEncoding vtk_encoding = VtkEncoding::kAppended;
  /// The frames' real values (points, velocities, pressures, forces): kSingle as Float32, kDouble as Float64.
  enum class VtkPrecision { kSingle, kDouble };
  static constexpr SceneNames<VtkPrecision, 2> kVtkPrecisionNames{
      {{"single", VtkPrecision::kSingle}, {"double", VtkPrecision::kDouble}}};
  VtkPrecision vtk_precision = VtkPrecision::kSingle;
  /// The water's frames hold the dummy particles behind the walls too (they only fill the walls' kernel).
  bool vtk_dummy_particles = false;
  /// [s] 0 = only on signal and at the end; unset in the scene: end_time / 10 for runs of at least 1000 steps of dt
  double checkpoint_interval = 0.0;
  std::int64_t checkpoint_keep = 3;  ///< newest interval checkpoints kept on disk
  std::int64_t diagnostics_every = 1;  ///< [steps] rows of diagnostics.csv
  std::vector<ProbeModel> probes;
  double bed_profile_interval = 0.0;  ///< [s] bed_profile.csv and class_centroids.csv; 0 = off
  double bed_layer_thickness = 0.0;   ///< [m] sub-layer thickness; 0 = the smallest grain diameter (bed_layer_thickness())
};

/// [mean_flow]: the mean-flow fluid, a flow uniform along the bed held as its plane average over a column of cells
/// in z (components/mean_flow.hpp, systems/physics/mean_flow/column.hpp; docs/cases/bedload.md). A fluid family beside
/// the MPS water: a scene has one or the other. The tank must be periodic along x and y.
struct MeanFlowModel {
  bool enabled = false;
  double density = 1000.0;              ///< [kg/m^3] rho of the water
  double kinematic_viscosity = 1.0e-6;  ///< [m^2/s] nu
  double bottom = 0.0;                  ///< [m] the column's floor (a no-slip wall), scene coordinates: the tank floor
  double top = 0.0;                     ///< [m] the free surface or the lid (filled by the reader: the tank top)
  double cell_size = 0.0;               ///< [m] the cells' height, as laid out (top - bottom) / cells
  std::size_t cells = 0;                ///< cells in the column (filled by the reader)
  /// The top: kFree a free surface without stress (an open channel), kLid a no-slip lid moving at lid_velocity
  /// along x (plane Couette over the bed).
  enum class Top { kFree, kLid };
  static constexpr SceneNames<Top, 2> kTopNames{{{"free", Top::kFree}, {"lid", Top::kLid}}};
  Top top_boundary = Top::kFree;
  double lid_velocity = 0.0;            ///< [m/s]
  /// kMixingLength: nu_t = l^2 |du/dz| with `closure`; kLaminar: nu alone.
  enum class Turbulence { kLaminar, kMixingLength };
  static constexpr SceneNames<Turbulence, 2> kTurbulenceNames{
      {{"laminar", Turbulence::kLaminar}, {"mixing_length", Turbulence::kMixingLength}}};
  Turbulence turbulence = Turbulence::kMixingLength;
  MixingLengthClosure closure;
  /// The water's drive along x (the same body force as the MPS water's: constant, sinusoidal; grains: how they feel
  /// it). Set by shields_number when that is given.
  BodyForceModel body_force;
  /// [1] If > 0: the drive is the slope whose bed shear stress rho f (top - z_bed) is shields_number (rho_s - rho) g d
  /// with d = shields_diameter and rho_s the density of shields_material, z_bed the column's bed surface at each step
  /// (the body force follows the bed as it erodes); the grains feel it as a tilt of gravity (BodyForceModel kFrame).
  double shields_number = 0.0;
  double shields_diameter = 0.0;        ///< [m] d of the Shields number
  double shields_density = 0.0;         ///< [kg/m^3] rho_s (from shields_material)
  /// A drive that pulls the water towards a target profile (seed 003's "corona" forcing, plane-averaged): on the
  /// water of every cell the acceleration volume_fraction (strength / |velocity|) (u_target(z) - u), a proportional
  /// controller whose gain is strength / |velocity| where it acts and which acts on volume_fraction of the water,
  /// towards u_target = velocity ((z - base) / (top - base))^exponent above base and 0 below it. The grains feel it
  /// only through the water.
  struct ProfileForcing {
    bool enabled = false;
    double velocity = 0.0;          ///< [m/s] u_target at the top (the seed's u_top)
    double exponent = 1.0 / 7.0;    ///< [1] the power law's exponent (Schlichting's 1/7)
    double base = 0.0;              ///< [m] where u_target starts from 0 (the seed's h_bed), scene coordinates
    double strength = 0.0;          ///< [m/s^2] a_0, the controller's acceleration per unit of relative slip
    double volume_fraction = 1.0;   ///< [1] the share of the water the forcing acts on (the seed's corona: 0.1)

    /// [1/s] The relaxation rate of the plane average, volume_fraction strength / |velocity|.
    double rate() const { return volume_fraction * strength / std::abs(velocity); }
  };
  ProfileForcing profile_forcing;
  /// The start: kRest the water at rest; kLogLaw u = (u*/kappa) ln(1 + (z - z_bed) / z0) above the bed (z0 =
  /// roughness_length), u* of the drive, so a turbulent channel need not spin up from rest; kTargetProfile the
  /// profile forcing's target.
  enum class Initial { kRest, kLogLaw, kTargetProfile };
  static constexpr SceneNames<Initial, 3> kInitialNames{
      {{"rest", Initial::kRest}, {"log_law", Initial::kLogLaw}, {"target_profile", Initial::kTargetProfile}}};
  Initial initial = Initial::kLogLaw;
  double initial_roughness_length = 0.0;  ///< [m] z0 of the initial log law; 0 = shields_diameter / 30
  /// What the grains read beyond the mean velocity: kNone the plane average alone; kLangevin a velocity fluctuation
  /// per grain, a Langevin (Ornstein-Uhlenbeck) process with the log layer's intensities over the local friction
  /// velocity and the Lagrangian time 2 sigma_w^2 / (C0 eps) (systems/physics/mean_flow/grain_forces.hpp; its state
  /// is GrainSampledFluid::fluctuation_state).
  enum class Fluctuations { kNone, kLangevin };
  static constexpr SceneNames<Fluctuations, 2> kFluctuationsNames{
      {{"none", Fluctuations::kNone}, {"langevin", Fluctuations::kLangevin}}};
  Fluctuations fluctuations = Fluctuations::kNone;
  double langevin_c0 = 4.0;             ///< [1] C0, the Lagrangian structure-function constant (3 to 7: Wilson & Sawford 1996)
  std::uint64_t fluctuation_seed = 1;   ///< names the fluctuations' random draws (systems/physics/math/counter_random.hpp)

  double column_height() const { return top - bottom; }
};

struct Model {
  std::string scene_file;   ///< path as given, for messages
  std::string scene_text;   ///< the full scene text (stored in checkpoints)
  std::string name;         ///< run name

  double end_time = 0.0;             ///< [s]
  double dt = 0.0;                   ///< [s] engine (fluid) step; with a fluid, the largest step (Courant limits below it)
  std::int64_t solid_substeps = 1;   ///< DEM sub-steps per engine step (derived from the contact estimates if unset)
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  ///< [m/s^2]

  std::vector<Material> materials;
  TankModel tank;
  SolidsModel solids;
  ContactModel contact;
  FluidModel fluid;
  MeanFlowModel mean_flow;
  CouplingModel coupling;
  OutputModel output;

  /// [bytes] a scene whose estimated memory (engine/setup/budget.hpp) exceeds this is refused before anything is
  /// allocated: --memory-limit, else run.memory_limit, else default_memory_limit()
  double memory_limit = 0.0;
  std::string memory_limit_source;  ///< where memory_limit came from, for messages
  double max_grains = 5e7;          ///< grains the scene may have in all (SceneLimits::max_grains)

  double solid_dt() const { return dt / static_cast<double>(solid_substeps); }
  /// [kg/m^3] The water's density, whichever fluid family the scene has.
  double water_density() const { return mean_flow.enabled ? mean_flow.density : fluid.density; }
  /// [m^2/s] The water's kinematic viscosity, whichever fluid family the scene has.
  double water_kinematic_viscosity() const {
    return mean_flow.enabled ? mean_flow.kinematic_viscosity : fluid.kinematic_viscosity;
  }
};

}  // namespace riffle
