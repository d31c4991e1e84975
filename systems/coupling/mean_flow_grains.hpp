#pragma once
// The grains and the mean-flow fluid (docs/cases/bedload.md, "The mean-flow fluid"): three systems that exchange
// what a plane-averaged column and the grains in it owe each other, so that the momentum the grains take from the
// water is the momentum the water loses, to rounding.
//   mean_flow_solid_fraction (end of step): the grains' volume in each cell, slice by slice (a sphere's exact volume
//     between the cell's faces), over the cell's volume; the bed surface.
//   mean_flow_drag_reaction (end of step): each grain's drag impulse of the step's sub-steps, spread over the cells
//     in proportion to the grain's volume in each, taken from the water at the next step.
//   solid_mean_flow_sampling (first in the grains' branch, and in the initial forces): each grain reads the water's
//     velocity and voidage at its centre height, and the water's pressure force on it: buoyancy from the hydrostatic
//     pressure and the drive (a pressure gradient on its volume, or a tilt of gravity on its mass); with [coupling]
//     lift the shear lift of the velocity across it, and with [mean_flow] fluctuations a Langevin velocity
//     fluctuation added to the velocity its drag reads (systems/physics/mean_flow/grain_forces.hpp).
#include "systems/system.hpp"

namespace riffle {

class MeanFlowSolidFraction final : public System {
 public:
  explicit MeanFlowSolidFraction(const Model& model);
  std::string_view name() const override { return "mean_flow_solid_fraction"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties>(), component_ids<MeanFlowColumn>()};
  }
  void run(SystemContext& context) override;

 private:
  const Model& model_;
  std::vector<double> volume_;  ///< [m^3] per cell, reused
};

class MeanFlowDragReaction final : public System {
 public:
  explicit MeanFlowDragReaction(const Model& model);
  std::string_view name() const override { return "mean_flow_drag_reaction"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties>(), component_ids<GrainDrag, MeanFlowColumn>()};
  }
  void run(SystemContext& context) override;

 private:
  const Model& model_;
  std::vector<double> slices_;  ///< [m^3] one grain's volume per cell, reused
};

class SolidMeanFlowSampling final : public System {
 public:
  explicit SolidMeanFlowSampling(const Model& model);
  std::string_view name() const override { return "solid_mean_flow_sampling"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties, MeanFlowColumn>(),
            component_ids<GrainSampledFluid, GrainVoidage>()};
  }
  void run(SystemContext& context) override;

 private:
  const Model& model_;
};

}  // namespace riffle
