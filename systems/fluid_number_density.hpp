#pragma once
// Number density and free-surface flag of the MPS particles (numerics.md Secs. 1.1 and 3.4; seed 000 Eq. 4):
// n_i = sum_j w(r_ij) over every neighbour (fluid, wall and dummy) with the Wendland kernel, for every particle;
// a fluid particle is on the free surface when n_i < beta n0, with n0 the interior value of the initial perfect
// lattice (lattice_constants) and beta = 0.93 (numerics amendments: 0.97 misflags the second layer). Wall and
// dummy particles are never surface particles (fluid-only PPE, amendment 1).
#include "engine/system.hpp"
#include "systems/mps_kernel.hpp"

namespace riffle {

struct NumberDensitySettings {
  double spacing = 0.0;             ///< [m] l0 of the initial lattice
  double effective_radius = 0.0;    ///< [m] r_e
  double surface_threshold = 0.93;  ///< [1] beta
};

/// Writes particles.number_density (all particles, from `neighbours`) and particles.free_surface (1 for fluid
/// particles with n_i < threshold * reference_density, 0 otherwise). Parallel over particles, gather only.
void compute_number_density(FluidParticles& particles, const FluidNeighbours& neighbours, const WendlandKernel& kernel,
                            double reference_density, double surface_threshold);

class FluidNumberDensity final : public System {
 public:
  /// Takes n0 from lattice_constants(3, l0, r_e).
  explicit FluidNumberDensity(const NumberDensitySettings& settings);
  std::string_view name() const override { return "fluid_number_density"; }
  Access access() const override { return {{ComponentId::kFluidNeighbours}, {ComponentId::kFluid}}; }
  void run(SystemContext& context) override;

  double reference_density() const { return reference_density_; }

 private:
  WendlandKernel kernel_;
  double reference_density_;
  double surface_threshold_;
};

}  // namespace riffle
