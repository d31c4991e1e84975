#pragma once
// The mean-flow fluid (docs/cases/bedload.md): a flow uniform along a bed, x and y periodic, held as its plane
// average, a column of cells in z (systems/physics/mean_flow/column.hpp). The closure's parameters are model data;
// MeanFlowColumn is the state a run advances and checkpoints.
#include <cereal/types/vector.hpp>
#include <string_view>
#include <vector>

#include "components/component_id.hpp"

namespace riffle {

/// The mixing-length closure nu_t = l^2 |du/dz| (Prandtl) of the turbulent water above and inside a bed.
struct MixingLengthClosure {
  double von_karman = 0.41;  ///< [1] kappa
  /// [1] phi_max of Li & Sawamoto (1995): the mixing length grows as kappa (phi_max - phi) / phi_max with height, so
  /// it is kappa z in clear water and vanishes in a packed bed; everything below the highest cell at or above
  /// phi_max counts as packed (turbulence fully damped inside the bed, as YADE's HydroForceEngine does).
  double max_solid_fraction = 0.61;
  /// Smooth floor: van Driest's damping 1 - exp(-z+ / A+) of the mixing length over the floor (z+ = z u*_floor / nu,
  /// A+ = 26, van Driest 1956), which gives the viscous sublayer and the smooth-wall log law (B = 5.28 with kappa =
  /// 0.41: the model's own constant). Rough floor: the mixing length starts at l0 at the floor and grows as kappa z,
  /// l0 the length that gives u/u* = ln(z / k_s) / kappa + B_r (B_r = 8.5, Nikuradse's fully rough wall) far above
  /// the floor with the molecular viscosity included; l0 -> kappa z0, z0 = k_s exp(-kappa B_r), when k_s u* / nu is
  /// large, and l0 = 0 below k_s u* / nu ~ 55 (not fully rough). A floor under a packed bed adds nothing.
  enum class Floor { kSmooth, kRough };
  Floor floor = Floor::kSmooth;
  double van_driest = 26.0;          ///< [1] A+
  double roughness = 0.0;            ///< [m] k_s of a rough floor (Nikuradse's equivalent sand roughness)
  double rough_wall_constant = 8.5;  ///< [1] B_r
};

/// The column's state: the water's plane-averaged velocity per cell, what the grains leave in each cell, and the
/// last step's closure and stresses. Written by mean_flow_momentum (velocities, eddy viscosity, stresses),
/// mean_flow_solid_fraction (solid fraction, bed surface) and mean_flow_drag_reaction (the grains' impulse).
struct MeanFlowColumn {
  static constexpr ComponentId kId = component_id<MeanFlowColumn>;
  static constexpr std::string_view kName = "mean_flow_column";
  static constexpr bool kPersistent = true;

  std::vector<double> velocity_x;      ///< [m/s] the water's (pore) velocity along x at the cell centres
  std::vector<double> velocity_y;      ///< [m/s] along y
  std::vector<double> solid_fraction;  ///< [1] phi: the grains' volume in the cell over the cell's volume
  /// [N s/m^2] the momentum the grains took from the water in each cell over the last step (their drag impulse over
  /// the plan area), which the next step takes from the water
  std::vector<double> impulse_x, impulse_y;
  std::vector<double> eddy_viscosity;  ///< [m^2/s] nu_t at the faces (cells + 1) in the last step
  double body_force = 0.0;             ///< [m/s^2] the body force along x on the water in the last step
  double bed_surface = 0.0;            ///< [m] where phi falls through half its largest value (column.hpp)
  double floor_stress = 0.0;           ///< [Pa] the water's stress on the floor along x after the last step
  double top_stress = 0.0;             ///< [Pa] the lid's stress on the water along x (0 for a free top)
  /// The grains are spread over MPI ranks: each rank holds the same column, and the grains' volume and drag impulse
  /// in it are summed over the ranks in rank order (not checkpointed: a run is split anew).
  bool over_ranks = false;

  std::size_t size() const { return velocity_x.size(); }

  template <class Archive>
  void serialize(Archive& archive) {
    archive(velocity_x, velocity_y, solid_fraction, impulse_x, impulse_y, eddy_viscosity, body_force, bed_surface,
            floor_stress, top_stress);
  }
};

}  // namespace riffle
