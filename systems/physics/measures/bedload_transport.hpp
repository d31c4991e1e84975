#pragma once
// The bed-load measures a user of the mean-flow fluid reads without a script ([[output.probes]] kind =
// "bedload_transport", docs/cases/bedload.md): the Shields number of the bed shear stress, the friction velocity,
// the dimensionless flux q* = q / sqrt((s - 1) g d^3), the fraction of the mobile grains that move, the moving
// grains' mean speed over u* (all of them, and those above the bed surface) and their mean height over the bed. Pure: the tests set grains and a column directly.
#include <cstddef>

#include "components/mean_flow.hpp"
#include "components/model.hpp"
#include "components/solids.hpp"

namespace riffle {

/// The grain the dimensionless numbers are made with: shields_diameter and shields_material's density when the
/// scene drives by a Shields number, else the mean diameter and density of the mobile (not fixed) grains.
struct ShieldsGrain {
  double diameter = 0.0;  ///< [m] d
  double density = 0.0;   ///< [kg/m^3] rho_s
};
ShieldsGrain shields_grain(const Model& model, const Solids& grains);

struct BedloadTransport {
  double bed_stress = 0.0;        ///< [Pa] tau_b = rho f (top - z_bed) + tau_lid: the stress the water above the bed carries into it
  double shields = 0.0;           ///< [1] Theta = tau_b / ((rho_s - rho) g d)
  double friction_velocity = 0.0;  ///< [m/s] u* = sqrt(tau_b / rho)
  double bed_surface = 0.0;       ///< [m] z_bed (the column's)
  double flux = 0.0;              ///< [m^2/s] q = sum over mobile grains of V u_x, over the plan area
  double flux_star = 0.0;         ///< [1] q* = q / sqrt((s - 1) g d^3)
  double moving_fraction = 0.0;   ///< [1] mobile grains with |v| > threshold over all mobile grains (0 without any)
  double moving_speed = 0.0;      ///< [m/s] the moving grains' mean u_x (0 without any)
  double moving_height = 0.0;     ///< [m] the moving grains' mean centre height above z_bed (0 without any)
  std::size_t moving = 0;         ///< grains moving
  /// [m/s] the mean u_x of the moving grains whose centres lie above z_bed: the bed-load layer, as a camera over a
  /// flume sees it (Lajeunesse et al. 2010), without the bed's creeping top layer (0 without any)
  double moving_above_bed_speed = 0.0;
  std::size_t moving_above_bed = 0;  ///< grains moving with their centres above z_bed
};

/// The measures of `grains` over `column` now; `threshold` [m/s] (seed 003's 0.01 m/s) decides which grains move.
/// The tank stands still (the mean-flow fluid refuses a moving tank).
BedloadTransport bedload_transport(const Model& model, const Solids& grains, const MeanFlowColumn& column,
                                   const ShieldsGrain& grain, double threshold);

}  // namespace riffle
