#include "engine/run/registry.hpp"

#include "systems/mps/fluid_cell_sort.hpp"
#include "systems/mps/fluid_checks.hpp"
#include "systems/mps/fluid_correct.hpp"
#include "systems/mps/fluid_escape.hpp"
#include "systems/coupling/fluid_drag_reaction.hpp"
#include "systems/coupling/mean_flow_grains.hpp"
#include "systems/mean_flow/mean_flow_momentum.hpp"
#include "systems/coupling/solid_drag.hpp"
#include "systems/coupling/solid_drag_law.hpp"
#include "systems/coupling/solid_fluid_sampling.hpp"
#include "systems/coupling/solid_lubrication.hpp"
#include "systems/coupling/solid_history_force.hpp"
#include "systems/mps/fluid_free_surface.hpp"
#include "systems/coupling/fluid_sample_copy.hpp"
#include "systems/mps/fluid_neighbours.hpp"
#include "systems/mps/fluid_predict.hpp"
#include "systems/mps/fluid_rank_migration.hpp"
#include "systems/physics/ranks/rank_comm.hpp"
#include "systems/mps/fluid_pressure.hpp"
#include "systems/mps/fluid_shift.hpp"
#include "systems/mps/fluid_wall_motion.hpp"
#include "systems/dem/solid_cell_sort.hpp"
#include "systems/dem/solid_domain_check.hpp"
#include "systems/dem/solid_summarize.hpp"
#include "systems/dem/solid_contacts.hpp"
#include "systems/dem/solid_force_sum.hpp"
#include "systems/dem/solid_neighbours.hpp"
#include "systems/coupling/solid_voidage.hpp"
#include "systems/dem/solid_integrate.hpp"
#include "systems/dem/wall_motion.hpp"

namespace riffle {

Pipeline build_pipeline(const Model& model) {
  Pipeline pipeline;
  if (model.fluid.enabled) {
    // numerics.md 2.1 and 5.6; the scheduler chains these through the fluid component in this order.
    const FluidModel& fluid = model.fluid;
    const double skin = fluid.neighbour_skin_ratio * fluid.spacing;
    const double narrow_skin = fluid.narrow_neighbour_skin_ratio * fluid.spacing;
    using At = FluidNeighbourSearch::Positions;
    const PeriodicBox box = periodic_box(model);  // no periodic axis: the searches build no halo
    const bool over_ranks = ranks::distributed();
    // Over MPI ranks the particles go to the ranks whose boxes hold them before the step-start search rebuilds.
    if (over_ranks) pipeline.step.push_back(std::make_unique<FluidRankMigration>(fluid.effective_radius(), fluid.effective_radius() + skin, box));
    pipeline.step.push_back(
        std::make_unique<FluidNeighbourSearch>(fluid.effective_radius(), skin, narrow_skin, At::kCurrent, box));
    pipeline.step.push_back(std::make_unique<FluidPredict>(fluid));
    pipeline.step.push_back(std::make_unique<FluidWallMotion>());
    // After the prediction, right before the search at r*: in fast flow that search rebuilds anyway.
    if (fluid.sort_every > 0 || fluid.sort_every_fast > 0)
      pipeline.step.push_back(std::make_unique<FluidCellSort>(fluid.sort_every, fluid.sort_every_fast,
                                                              fluid.effective_radius() + skin, 0.15 * fluid.spacing));
    pipeline.step.push_back(
        std::make_unique<FluidNeighbourSearch>(fluid.effective_radius(), skin, narrow_skin, At::kPredicted, box));
    pipeline.step.push_back(std::make_unique<FluidFreeSurface>(fluid));
    pipeline.step.push_back(std::make_unique<FluidPressureSolve>(model));
    pipeline.step.push_back(std::make_unique<FluidCorrect>(fluid));
    // Particle shifting (docs/FLUID.md): only in scenes that ask for it, so the seed's step graph is unchanged.
    if (fluid.shifting != FluidModel::Shifting::kOff) pipeline.step.push_back(std::make_unique<FluidShift>(fluid));
    // Escaped spray leaves the table before the checks count the water and before the grains' voidage and drag
    // reaction look at it; with escape = "stop" fluid_checks stops the run at the first one instead.
    if (fluid.escape == FluidModel::EscapePolicy::kRemove)
      pipeline.end_of_step.push_back(std::make_unique<FluidEscape>());
    pipeline.end_of_step.push_back(std::make_unique<FluidChecks>(fluid));
    if (model.coupling.enabled) {
      // Staggered by one fluid step (docs/COUPLING.md): the grains' sub-steps of step k+1 use the water at the end
      // of step k. The grains sample a copy of it, first in their own branch, so the fluid's systems and the
      // grains' sub-step loop share no component and the scheduler lets them run side by side; the voidage, which
      // the drag reaction needs, is read at the end of the step.
      // Over MPI ranks the coupling's systems also read the other ranks' grains and water near this rank's
      // (systems/physics/ranks/coupling_ranks.hpp).
      pipeline.step_start.push_back(
          std::make_unique<FluidSampleCopy>(model.coupling.viscous_stress, over_ranks, fluid.effective_radius(),
                                            fluid.spacing, model.coupling.self_induced_velocity));
      pipeline.solid_step.push_back(std::make_unique<SolidFluidSampling>(model));
      // The history force of the step start, from the relative velocity just sampled; held over the sub-steps.
      if (model.coupling.history_force) pipeline.solid_step.push_back(std::make_unique<SolidHistoryForce>(model));
      pipeline.end_of_step.push_back(std::make_unique<SolidVoidage>(model, over_ranks));
      pipeline.end_of_step.push_back(std::make_unique<FluidDragReaction>(model, over_ranks));
    }
  }
  if (model.mean_flow.enabled) {
    // The mean-flow fluid (docs/cases/bedload.md): the column advances first, the grains read the water it leaves,
    // and at the step's end their volume and drag impulse go back into the column for the next step.
    pipeline.step.push_back(std::make_unique<MeanFlowMomentum>(model));
    if (model.coupling.enabled) {
      pipeline.solid_step.push_back(std::make_unique<SolidMeanFlowSampling>(model));
      pipeline.end_of_step.push_back(std::make_unique<MeanFlowSolidFraction>(model));
      pipeline.end_of_step.push_back(std::make_unique<MeanFlowDragReaction>(model));
    }
  }
  // What the grains' drag keeps over the step (the law at each grain's voidage), from the water just sampled.
  if (model.coupling.enabled && model.coupling.drag) pipeline.solid_step.push_back(std::make_unique<SolidDragLaw>(model));
  // Order matters only where systems share a component: the scheduler derives the edges from it.
  if (model.solids.enabled) pipeline.substep.push_back(std::make_unique<SolidKickDrift>(model));
  // The walls move once per sub-step when grains feel them, otherwise once per engine step.
  (model.solids.enabled ? pipeline.substep : pipeline.step).push_back(std::make_unique<WallMotion>());
  const bool contacts = model.solids.enabled && model.contact.enabled;
  const bool coupled = model.coupling.enabled;
  if (contacts || coupled) {
    for (auto* phase : {&pipeline.substep, &pipeline.initial_forces}) {
      if (contacts) {
        phase->push_back(std::make_unique<SolidNeighbours>());
        phase->push_back(std::make_unique<SolidContactForces>());
      }
      if (coupled && model.coupling.drag && phase == &pipeline.substep) phase->push_back(std::make_unique<SolidDrag>(model));
      // A new run's first sub-steps use the water as laid out (hydrostatic, engine/setup/initial_state.cpp): buoyancy
      // from the first sub-step on.
      if (coupled && phase == &pipeline.initial_forces && model.mean_flow.enabled) {
        phase->push_back(std::make_unique<SolidMeanFlowSampling>(model));  // the column as set up
      } else if (coupled && phase == &pipeline.initial_forces) {
        phase->push_back(std::make_unique<FluidSampleCopy>(model.coupling.viscous_stress, ranks::distributed(),
                                                           model.fluid.effective_radius(), model.fluid.spacing,
                                                           model.coupling.self_induced_velocity));
        phase->push_back(std::make_unique<SolidVoidage>(model, ranks::distributed()));
        phase->push_back(std::make_unique<SolidFluidSampling>(model));
      }
      const bool lubrication = coupled && contacts && model.coupling.lubrication;
      if (lubrication) phase->push_back(std::make_unique<SolidLubrication>(model));
      phase->push_back(std::make_unique<SolidForceSum>(lubrication));
    }
  }
  if (model.solids.enabled) {
    pipeline.substep.push_back(std::make_unique<SolidKick>(model));
    pipeline.end_of_step.push_back(std::make_unique<SolidDomainCheck>());
    pipeline.end_of_step.push_back(std::make_unique<SolidSummarize>());
    // With contacts the neighbour list reorders the grains itself, at rebuilds, where slots may change.
    if (!contacts && model.solids.sort_every > 0) pipeline.end_of_step.push_back(std::make_unique<SolidCellSort>());
  }
  return pipeline;
}

}  // namespace riffle
