#pragma once
// Samples the fluid at every grain once per fluid step, after the pressure correction (numerics.md 5.2-5.4, 5.6
// step 7): the locally averaged fluid velocity (seed Eq. 23) and pressure gradient (Shepard averages with the
// Wendland kernel on R_I = d_I/2 + r_e), the pressure force -V <grad p> (Eq. 13), and the voidage: solid volume
// over the space the fluid particles fill, both deposited on a grid of cells 0.67 R_eps wide (systems/voidage_grid.hpp;
// the fluid particles are the space quadrature, so walls and the free surface truncate both alike). The sub-steps
// then hold these fixed (solid_drag).
#include "engine/system.hpp"
#include "systems/cell_grid.hpp"
#include "systems/fluid_common.hpp"
#include "systems/voidage_grid.hpp"

namespace riffle {

class SolidFluidSampling final : public System {
 public:
  explicit SolidFluidSampling(const Model& model);
  std::string_view name() const override { return "solid_fluid_sampling"; }
  Access access() const override { return {{ComponentId::kFluid}, {ComponentId::kSolids}}; }
  void run(SystemContext& context) override;

 private:
  MpsConstants constants_;
  CouplingModel coupling_;
  double voidage_radius_;  ///< [m] R_eps
  double spacing_;         ///< [m] l0
  CellGrid fluid_grid_;
  VoidageGrid voidage_grid_;
  std::vector<double> grain_volumes_;
};

}  // namespace riffle
