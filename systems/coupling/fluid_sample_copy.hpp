#pragma once
// Copies the water the grains sample (positions, velocities, pressure gradients of the fluid particles) into
// FluidSample before the step's two branches start (docs/COUPLING.md): the grains' branch then samples the water
// at the step start while the fluid's branch advances it beside them. About 1 MB at l0 = 5 mm, a tenth of a
// millisecond, against the sampling itself, which this takes off the end of the step.
#include "systems/system.hpp"

namespace riffle {

class FluidSampleCopy final : public System {
 public:
  /// `viscous_stress`: also copy the last prediction's nu <lap u> ([coupling] viscous_stress; ParticlePrediction is
  /// read only then, so the step graph without it is unchanged).
  /// `over_ranks` (a run of grains in MPS water over MPI ranks): the other ranks' fluid particles within the
  /// sampling kernels' reach of this rank's grains are appended after its own (coupling_ranks.hpp), read with the
  /// grains' boxes (Contacts) and where its grains now are; `dilute_kernels` (the self-induced correction on): a
  /// dilute grain's kernel is no narrower than at l0 = r (coupling_kernel_radius, with the water's `spacing`).
  explicit FluidSampleCopy(bool viscous_stress = false, bool over_ranks = false, double effective_radius = 0.0,
                           double spacing = 0.0, bool dilute_kernels = false)
      : viscous_stress_(viscous_stress),
        over_ranks_(over_ranks),
        effective_radius_(effective_radius),
        spacing_(spacing),
        dilute_kernels_(dilute_kernels) {}
  std::string_view name() const override { return "fluid_sample_copy"; }
  Access access() const override {
    Access access{component_ids<ParticleState, ParticlePressure>(), component_ids<FluidSample>()};
    if (viscous_stress_) access.reads.push_back(ParticlePrediction::kId);
    if (over_ranks_)
      for (const ComponentId id : component_ids<GrainState, GrainProperties, Contacts>()) access.reads.push_back(id);
    return access;
  }
  void run(SystemContext& context) override;

 private:
  /// Appends the other ranks' fluid particles near this rank's grains (over ranks only). Collective.
  void append_other_ranks(SystemContext& context, FluidSample& sample) const;

  bool viscous_stress_;
  bool over_ranks_;
  double effective_radius_;  ///< [m] r_e: a grain of radius r samples the water within r + r_e
  double spacing_;           ///< [m] l0
  bool dilute_kernels_;      ///< a dilute grain's kernel is no narrower than at l0 = r (coupling_kernel_radius)
};

}  // namespace riffle
