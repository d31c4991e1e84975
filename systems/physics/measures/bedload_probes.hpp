#pragma once
// The bed-load measures of a sheared bed (seed 003), written by the probes of engine/output/probes.hpp:
//
//   kind = "moving_fraction"   the fraction of moving grains, all and per size class (seed 003 Eqs. 29-30);
//   kind = "packing_density"   the planar packing density lambda of the bed's top layer (seed 003 Sec. 5.2);
//   kind = "bedload_flux"      the volume flux of grains per unit width, per class, and its running time mean;
//   kind = "velocity_profile"  horizontally averaged x velocity of water and grains and the solid fraction per layer;
//   kind = "bed_shear_stress"  the bed shear stress from the momentum balance (and from a lid, where one exists) and
//                              the Shields number per class.
//
// Every measure works in the tank frame: heights above the tank floor, horizontal positions relative to the tank's
// displacement, velocities relative to the tank's velocity, so the same probe reads a shaken closed tank and a
// still (periodic) box. The horizontal footprint is the tank's inner box, treated as periodic where a disc reaches
// over a side (in a closed tank only a grain's contact overlap with a wall does, a negligible area). The functions
// are pure (no I/O): the tests set grains and particles directly and check the answers.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "components/fluid.hpp"
#include "components/model.hpp"
#include "components/solids.hpp"
#include "components/tank_motion.hpp"
#include "components/world.hpp"

namespace riffle {

/// The tank frame the measures read in.
struct TankFrame {
  Vec3 low = Vec3::Zero();           ///< [m] the inner box's low corner at rest (tank.origin)
  Vec3 size = Vec3::Zero();          ///< [m] the inner box's size
  Vec3 displacement = Vec3::Zero();  ///< [m] the tank's displacement now
  Vec3 velocity = Vec3::Zero();      ///< [m/s] the tank's velocity now
  double floor_z() const { return low.z() + displacement.z(); }  ///< [m] lab z of the floor now
  double area() const { return size.x() * size.y(); }             ///< [m^2] the bed's plan area
};
TankFrame tank_frame(const Model& model, const TankMotion* motion);

/// The size classes of the grains (ascending) with each class's mean diameter and density (from the grains
/// themselves: a run may start from another run's grains).
struct GrainClasses {
  std::vector<std::int32_t> classes;
  std::vector<double> diameter;  ///< [m] mean diameter of the class's grains
  std::vector<double> density;   ///< [kg/m^3] total mass over total volume of the class's grains
  std::size_t index_of(std::int32_t size_class) const;  ///< position in `classes`, or classes.size()
};
GrainClasses grain_classes(const Solids& solids);

/// [1] Moving fractions: entry k for classes[k], then the last entry for all grains together. A grain moves when
/// |v - v_tank| > threshold (seed 003: 0.01 m/s). NaN for a class without grains.
std::vector<double> moving_fractions(const Solids& solids, const GrainClasses& classes, const TankFrame& frame,
                                     double threshold);

/// How the top layer is chosen (docs/SCENES.md, "packing_density").
struct TopLayerSettings {
  double threshold = 0.01;  ///< [m/s] grains faster than this relative to the tank are moving, not in the layer
  double depth = 0.0;       ///< [m] layer depth below the local bed top; 0 = 0.75 of the largest grain diameter
  std::optional<double> bottom;  ///< [m] if set: the layer is every resting grain with centre above this height
};
struct PackingDensity {
  double lambda = 0.0;     ///< [1] area covered by the layer's projection over the plan area
  std::size_t grains = 0;  ///< grains in the layer
};
/// The planar packing density of the top layer: the resting grains whose centre lies above the local bed top less
/// `depth` (the local top: the highest resting centre in the grain's column, columns about one largest diameter
/// wide), or above `bottom` when set (seed 003's fixed height); lambda = the area of the union of their discs
/// projected on the horizontal plane, over the plan area (seed 003 Eq. 31). The union is integrated row by row,
/// rows 1/64 of the smallest diameter apart, each row's covered length exact (merged chords).
PackingDensity packing_density(const Solids& solids, const TankFrame& frame, const TopLayerSettings& settings);

/// [m^2/s] Bed-load flux per unit width: for each class, (1/(L W)) sum over its grains of V_p (u_p,x - u_tank,x),
/// over every grain (the resting ones add nothing); the last entry is all grains together.
std::vector<double> bedload_flux(const Solids& solids, const GrainClasses& classes, const TankFrame& frame);

/// One horizontal layer of a velocity profile.
struct ProfileLayer {
  double z_low = 0.0, z_high = 0.0;  ///< [m] above the floor
  std::size_t fluid_particles = 0;   ///< fluid-kind particles with their centre in the layer
  double fluid_ux = 0.0;             ///< [m/s] their mean u_x - u_tank,x; NaN if none
  double grain_ux = 0.0;             ///< [m/s] grains' volume-weighted mean u_x - u_tank,x; NaN if none
  double solid_fraction = 0.0;       ///< [1] grain volume in the layer over the layer's volume L W h
};
/// Layers of `thickness` from the floor up, `count` of them. Each grain counts with the part of its sphere inside a
/// layer (sphere_slab_volume), both in the solid fraction and as the weight of its velocity. Either table may be
/// null.
std::vector<ProfileLayer> velocity_profile(const Solids* solids, const FluidParticles* fluid, const TankFrame& frame,
                                           double thickness, std::size_t count);

/// What the bed shear stress needs from [fluid].
struct ShearSettings {
  double spacing = 0.0;              ///< [m] l0 (fluid particle volume l0^3)
  double effective_radius = 0.0;     ///< [m] r_e
  double density = 0.0;              ///< [kg/m^3] rho_f
  double kinematic_viscosity = 0.0;  ///< [m^2/s] nu
  double number_density = 0.0;       ///< [1] n0
  double laplacian_lambda = 0.0;     ///< [m^2] lambda0
};
ShearSettings shear_settings(const Model& model);

struct BedShear {
  double grains_fx = 0.0;  ///< [N] x force of the water on all grains: drag + pressure + added mass + history
  double floor_fx = 0.0;   ///< [N] x force of the water on the floor: minus the viscous force of the floor's
                           ///< boundary particles on the fluid
  double tau = 0.0;        ///< [Pa] (grains_fx + floor_fx) / (L W)
};
/// The bed shear stress from the momentum balance: everything the water pushes along x below it, the grains and the
/// floor, per plan area. The floor's share is the MPS viscous term (numerics 1.4) between the fluid particles and
/// the boundary (wall and dummy) particles below the floor plane, rho l0^3 nu 2D/(lambda0 n0) (u_i - u_j) w_ij,
/// summed with the action on the fluid reversed. Either table may be null (its share is 0).
BedShear bed_shear_stress(const Solids* solids, const FluidParticles* fluid, const ShearSettings& settings,
                          const TankFrame& frame);

/// [Pa] The shear stress a moving lid drives (docs/FLUID.md, "Driven flows"): the x force the first lid with a
/// velocity exerts on the water (FluidSummary::lid_force, the viscous sum of the step) over its area; at steady state
/// the bed carries the same. nullopt without such a lid or before the first step has summed its force.
std::optional<double> lid_shear_stress(const Model& model, const World& world);
/// True when the scene has a moving lid: the bed_shear_stress probe then writes tau_lid_Pa and the lid's Shields numbers.
bool model_has_lid(const Model& model);

/// The running time mean of a probe's rows: each row's values held over the time since the previous row (the first
/// row stands alone). Restarts on resume, as no probe keeps state in checkpoints.
class RunningMean {
 public:
  /// Adds the row at `time`; returns the mean so far.
  std::vector<double> add(double time, const std::vector<double>& values);

 private:
  std::optional<double> last_time_;
  double covered_ = 0.0;
  std::vector<double> integral_, last_;
};

}  // namespace riffle
