#include "systems/coupling/solid_fluid_sampling.hpp"

#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/mps/driven_flow.hpp"
#include "systems/physics/mps/fluid_pair_batch.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/coupling/sampling_kernel.hpp"
#include "systems/physics/coupling/self_induced.hpp"
#include "systems/coupling/solid_drag.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace riffle {

SolidFluidSampling::SolidFluidSampling(const Model& model)
    : constants_(mps_constants(model.fluid)),
      pressure_gradient_(model.coupling.pressure_gradient),
      viscous_stress_(model.coupling.viscous_stress),
      fluid_acceleration_(model.coupling.added_mass || model.coupling.history_force),
      density_(model.fluid.density),
      self_induced_velocity_(model.coupling.self_induced_velocity),
      fluid_velocity_(model.coupling.fluid_velocity),
      vertical_radius_(model.coupling.sampling_vertical_radius),
      body_force_(model.fluid.body_force),
      overlap_(model.coupling.self_induced_velocity ? self_induced_overlap() : 0.0) {}

void SolidFluidSampling::run(SystemContext& context) {
  const FluidSample& fluid = context.read<FluidSample>();
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  GrainSampledFluid& sampled = context.write<GrainSampledFluid>();
  const std::size_t fluid_count = fluid.size();
  // The body force along x (docs/COUPLING.md, "Driven flows and the grains"): the imposed mean pressure gradient
  // -dp/dx = rho f, which the MPS pressure does not hold, pushes a grain with V rho f; a frame acceleration acts on
  // its mass, m f. A controller's force is the last step's (the grains sample beside the fluid's step).
  double body_force = 0.0;
  if (body_force_.kind == BodyForceModel::Kind::kBulkVelocity)
    body_force = context.read<FluidSummary>().body_force;
  else if (body_force_.kind != BodyForceModel::Kind::kNone)
    body_force = prescribed_body_force(body_force_, context.time);
  const bool imposed_gradient = body_force_.grains == BodyForceModel::Grains::kPressureGradient && pressure_gradient_;
  const bool frame = body_force_.grains == BodyForceModel::Grains::kFrame;
  const double effective_radius = constants_.effective_radius;
  double smallest_radius = std::numeric_limits<double>::infinity();
  for (const double radius : properties.radius) smallest_radius = std::min(smallest_radius, radius);
  // Cells of half the smallest sampling radius: a query scans about 5^3 cells holding about twice the sphere's
  // volume; cells of the largest radius made every small grain test ten times the particles it keeps.
  const DomainBox domain = domain_box(context.model);
  const PeriodicBox box = periodic_box(context.model);
  if (!properties.radius.empty())
    fluid_grid_.build(fluid.position, 0, fluid_count, 0.5 * (smallest_radius + effective_radius), domain.low,
                      domain.high);

  // The grains' last drag and voidage, read once (the self-induced correction and the water's acceleration use them).
  const bool reads_drag = self_induced_velocity_ || fluid_acceleration_;
  const GrainVoidage* const voidages = reads_drag ? &context.read<GrainVoidage>() : nullptr;
  const GrainDrag* const drags = reads_drag ? &context.read<GrainDrag>() : nullptr;
  const GrainAddedMass* const added =
      self_induced_velocity_ && pressure_gradient_ ? &context.read<GrainAddedMass>() : nullptr;

  for_each_particle(grains.size(), [&](std::size_t grain) {
    const Vec3 centre = grains.position[grain];
    // A dilute grain's kernel does not narrow below its own at l0 = r (coupling_kernel_radius); the voidage is the
    // last step's, the one the drag reads over this step (read only with the correction on: without it no grain is
    // dilute in this sense).
    const double voidage = self_induced_velocity_ ? voidages->voidage[grain] : 1.0;
    const double kernel_radius = grain_kernel_radius(self_induced_velocity_, properties.radius[grain],
                                                     effective_radius, constants_.spacing, voidage);
    const WendlandKernel sampling_kernel(kernel_radius);
    const double radius_squared = sampling_kernel.effective_radius * sampling_kernel.effective_radius;
    // An ellipsoidal kernel (sampling_vertical_radius) measures the offsets with dz stretched by R_h / R_v: the same
    // Wendland polynomial and cut on R_h; its candidates lie inside the sphere of R_h the grid search covers.
    const double stretch = sampling_vertical_stretch(sampling_kernel.effective_radius, vertical_radius_);
    double weight_sum = 0.0;
    Vec3 velocity = Vec3::Zero(), gradient = Vec3::Zero(), viscous = Vec3::Zero();
    // The fluid particles within the sampling radius, in grid order, a batch at a time: a run of cells' candidates
    // get their s^2 in one vectorised loop over the grid's copy of the positions (squared_offsets), each is written
    // and kept by advancing the end (whether it is kept is random to a branch predictor), the weights of a batch are
    // evaluated in one vectorised pass (the same operations as WendlandKernel::weight of the norm), and the sums run
    // in the same order as one candidate at a time.
    FluidPairBatch batch;
    batch.count = 0;
    std::array<double, kPairBatch> squared;  // a chunk of a run's candidates' s^2
    const auto flush = [&] {
      evaluate_pair_weights(batch, sampling_kernel);
      for (std::size_t k = 0; k < batch.count; ++k) {
        const double weight = batch.weight[k];
        weight_sum += weight;
        velocity += weight * fluid.velocity[batch.slot[k]];
        gradient += weight * fluid.pressure_gradient[batch.slot[k]];
        if (viscous_stress_) viscous += weight * fluid.viscous_acceleration[batch.slot[k]];
      }
      batch.count = 0;
    };
    // In a periodic box the sphere cut by a seam is completed by the grain's images (centre + shift, the nearest
    // image of every fluid particle across the seam; the period exceeds twice the sampling radius, so no particle
    // is met twice): exact and without a halo as wide as the sampling radius. Without a period: the centre alone.
    const auto gather = [&](const Vec3& query) {
      const auto keep = [&](const std::uint32_t* first, const std::uint32_t* last) {
        // The batch's end in a local while filling (in batch.count it would go through memory at every candidate:
        // the compiler cannot tell the batch's stores from it).
        const CellGrid::Coordinates at = fluid_grid_.member_coordinates(first);
        const auto candidates = static_cast<std::size_t>(last - first);
        std::size_t count = batch.count;
        for (std::size_t begin = 0; begin < candidates; begin += kPairBatch) {
          const std::size_t chunk = std::min(kPairBatch, candidates - begin);
          squared_offsets(at.x + begin, at.y + begin, at.z + begin, chunk, query, stretch, squared.data());
          for (std::size_t k = 0; k < chunk; ++k) {
            batch.slot[count] = first[begin + k];
            batch.distance_squared[count] = squared[k];
            count += squared[k] < radius_squared ? 1 : 0;
            if (count == kPairBatch) {
              batch.count = count;
              flush();
              count = 0;
            }
          }
        }
        batch.count = count;
      };
      fluid_grid_.for_each_candidate_run(query, sampling_kernel.effective_radius, keep);
    };
    gather(centre);
    std::array<Vec3, 3> shifts;
    const int images = box.any() ? box.image_shifts(centre, sampling_kernel.effective_radius, shifts) : 0;
    for (int image = 0; image < images; ++image) gather(centre + shifts[static_cast<std::size_t>(image)]);
    if (batch.count > 0) flush();
    sampled.fluid_weight[grain] = weight_sum;
    if (weight_sum <= 0.0) {  // out of the water: no fluid forces
      sampled.fluid_velocity[grain] = Vec3::Zero();
      sampled.pressure_force[grain] = Vec3::Zero();
      if (viscous_stress_) sampled.viscous_force[grain] = Vec3::Zero();
      if (fluid_acceleration_) sampled.fluid_acceleration[grain] = Vec3::Zero();
      return;
    }
    sampled.fluid_velocity[grain] = velocity / weight_sum;
    sampled.pressure_force[grain] =
        pressure_gradient_ ? Vec3(-grain_volume(properties.radius[grain]) * gradient / weight_sum) : Vec3::Zero();
    // The water's viscous stress over the grain's volume, V div tau = V rho <nu lap u> (docs/COUPLING.md, "The viscous
    // stress on the grains"): like the pressure force, it has no reaction in the water.
    if (viscous_stress_)
      sampled.viscous_force[grain] = (grain_volume(properties.radius[grain]) * density_ / weight_sum) * viscous;
    // Du/Dt of the water at the grain in the Maxey-Riley form (Maxey & Riley 1983): the inviscid momentum balance
    // -<grad p>/rho + g, from the same pressure gradient as the pressure force (docs/COUPLING.md, "Added mass and
    // history force"). Only when a force uses it: with both off the field stays as it was (bit-identical runs).
    if (fluid_acceleration_) {
      sampled.fluid_acceleration[grain] = context.model.gravity - gradient / (weight_sum * density_);
      // Plus the other grains' drag reaction on the water around this one, in the cell model Zuber's C_a comes
      // from (each neighbour pushes the water as this grain does, over the solid fraction 1 - eps; the water takes
      // it over the flux share): in a suspension the pressure gradient holds the grains' excess weight, which the
      // water passes on to them through the drag, so without their reaction the water would seem to accelerate
      // upward at phi (rho_s - rho) g / rho and the added mass would hold every grain up (a suspension at
      // phi = 0.1 settled 8 % slow). A lone grain (eps = 1) has none. F is the last sub-step's drag.
      const double voidage = voidages->voidage[grain];
      const double others = (1.0 - voidage) / (flux_share(fluid_velocity_, voidage) * density_ *
                                               grain_volume(properties.radius[grain]));
      sampled.fluid_acceleration[grain] -= others * drags->drag_force[grain];
    }
    if (body_force_.kind != BodyForceModel::Kind::kNone) {
      if (fluid_acceleration_) sampled.fluid_acceleration[grain].x() += body_force;
      if (imposed_gradient)
        sampled.pressure_force[grain].x() += grain_volume(properties.radius[grain]) * density_ * body_force;
      if (frame) sampled.pressure_force[grain].x() += properties.mass[grain] * body_force;
    }
    if (self_induced_velocity_ && pressure_gradient_) {
      // The water's pressure answers the irrotational part of the grain's spread reaction -F rho_s / flux_share:
      // at the centre of the isotropic blob, grad p = -F <rho_s rho_w> / 3 sampled, which adds
      // V F <rho_s rho_w> / 3 to -V <grad p> (docs/COUPLING.md). F is the last sub-step's force the water received
      // over the last step: the drag and, handed back with it, the added-mass and history forces (the whole reaction
      // the velocity's correction takes out too; with the drag alone the history force's share stayed in, a sphere
      // settling at Re 0.1, d/l0 = 3 read 0.4 % of rho g V more buoyancy, and its added and history masses turned
      // that into a water accelerating upward); only for the dilute grains whose drag the correction applies to.
      const double voidage = voidages->voidage[grain];
      if (voidage > kSelfInducedMinVoidage) {
        const double share = flux_share(fluid_velocity_, voidage);
        const double own = grain_volume(properties.radius[grain]) * overlap_ /
                           (3.0 * kernel_radius * kernel_radius * kernel_radius * share);
        const Vec3 own_force = own * (drags->drag_force[grain] + inertial_reaction_force(*added, grain));
        sampled.pressure_force[grain] -= own_force;
        // The water's acceleration the added mass and history forces use is the undisturbed one too: g - grad p / rho
        // with the same own part taken out of -V grad p, so own_force / (rho V) comes off it as well (a lone grain
        // settling steadily in still water then reads Du/Dt = 0, and its added mass pushes nothing).
        if (fluid_acceleration_)
          sampled.fluid_acceleration[grain] -= own_force / (density_ * grain_volume(properties.radius[grain]));
      }
    }
  });
  context.count_items(grains.size());
}

}  // namespace riffle
