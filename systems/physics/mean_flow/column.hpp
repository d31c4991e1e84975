#pragma once
// The mean-flow fluid's column (docs/cases/bedload.md, "The mean-flow fluid"): a flow uniform along a bed (x and y
// periodic) is its plane average, a function of height alone. Pure functions on a uniform grid of cells in z: the
// solid fraction the grains leave in each cell, the value of a cell-centred profile at a height, the bed surface, the
// mixing length of the turbulence closure and one implicit step of the plane-averaged momentum balance of the water,
//   rho eps du/dt = d/dz (rho eps (nu + nu_t) du/dz) + rho eps f - n <f_drag>,
// the momentum equation of the fluid phase of the two-phase mean-flow models of bed load (Durán, Andreotti & Claudin
// 2012, Phys. Fluids 24; Maurin, Chauchat, Chareyre & Frey 2015, Comput. Fluids 123; YADE's HydroForceEngine).
// The systems (systems/mean_flow, systems/coupling) call these and the tests call the same ones.
#include <cstddef>
#include <vector>

#include "components/mean_flow.hpp"

namespace riffle {

/// A uniform grid of `cells` cells of height `cell_height` from `bottom` up. Cell i spans [face(i), face(i + 1)];
/// its values live at centre(i).
struct ColumnGrid {
  double bottom = 0.0;       ///< [m] the floor: a no-slip wall
  double cell_height = 0.0;  ///< [m] h
  std::size_t cells = 0;

  double face(std::size_t i) const { return bottom + static_cast<double>(i) * cell_height; }
  double centre(std::size_t i) const { return bottom + (static_cast<double>(i) + 0.5) * cell_height; }
  double top() const { return face(cells); }
};

/// The cells a sphere crosses, [first, last]; empty when it lies wholly below the floor or above the top.
struct CellSpan {
  std::size_t first = 0, last = 0;
  bool empty = true;
};
CellSpan sphere_cells(const ColumnGrid& grid, double centre, double radius);

/// Adds weight x (the sphere's volume in cell i, sphere_slab_volume of systems/physics/measures/bedload.hpp) to per_cell[i] for every cell the sphere crosses (per_cell sized
/// grid.cells); returns the sphere's volume inside the column (below the top, above the bottom).
double deposit_sphere(const ColumnGrid& grid, double centre, double radius, double weight,
                      std::vector<double>& per_cell);

/// What lies beyond the column's last centre: the value at the top face (a lid), or the last value (a free top).
struct ColumnEnds {
  double bottom_value = 0.0;  ///< the value at the bottom face (the floor's velocity: 0)
  bool top_given = false;     ///< true: top_value at the top face; false: flat above the last centre
  double top_value = 0.0;
};

/// The value at height z of a cell-centred profile, linear between centres and between the first (last) centre and
/// the bottom (top) face as `ends` says; clamped to the faces outside the column.
double profile_at(const ColumnGrid& grid, const std::vector<double>& values, double z, const ColumnEnds& ends);

/// [m] The bed surface: the highest height where the solid fraction falls through half its largest value in the
/// column (Maurin et al. 2015's definition), linear between centres; `grid.bottom` without grains.
double bed_surface(const ColumnGrid& grid, const std::vector<double>& solid_fraction);

/// [m] The mixing length at the grid's faces (grid.cells + 1 values, face 0 the floor) over the solid fraction
/// `solid_fraction` (per cell), with the floor's friction velocity `floor_friction_velocity` [m/s] (van Driest's
/// z+ on a smooth floor, k_s+ on a rough one; 0: the rough floor's l0 is kappa z0) and kinematic viscosity
/// `viscosity` [m^2/s].
/// `top`: a lid is a smooth no-slip wall too: the mixing length is at most kappa (top - z), damped by van Driest's
/// factor with the lid's friction velocity (the pipe-flow form of Li & Sawamoto's length, YADE's ilm = 6); a free
/// top is no wall. A smooth floor buried under a packed bed damps nothing: the bed is the water's wall, and its
/// mixing length starts at 0 at the bed's packed top.
struct TopWall {
  bool wall = false;               ///< true: a lid
  double friction_velocity = 0.0;  ///< [m/s] sqrt(|tau_lid| / rho) of the last step
};
std::vector<double> mixing_lengths(const ColumnGrid& grid, const std::vector<double>& solid_fraction,
                                   const MixingLengthClosure& closure, double floor_friction_velocity,
                                   double viscosity, const TopWall& top = {});

/// [1/s] du/dz at face j (0 the floor, cells the top) of the cell-centred profile `velocity`, as the eddy viscosity
/// and the stress take it: (u_0 - floor) / (h / 2) at the floor, (lid - u_last) / (h / 2) at a lid, 0 at a free top.
double face_gradient(const ColumnGrid& grid, const std::vector<double>& velocity, const ColumnEnds& ends,
                     std::size_t j);

/// [m^2/s] The eddy viscosity l^2 |du/dz| at the faces of the profile `velocity` (cell centres) with mixing lengths
/// `lengths` (faces); at the floor du/dz = u_0 / (h / 2), at a lid (ends.top_given) (top_value - u_last) / (h / 2),
/// at a free top 0. `velocity_y`, if not empty, is the second horizontal component: |du/dz| is the magnitude of
/// the shear (a flow that turns).
std::vector<double> eddy_viscosities(const ColumnGrid& grid, const std::vector<double>& velocity,
                                     const std::vector<double>& velocity_y, const std::vector<double>& lengths,
                                     const ColumnEnds& ends_x, const ColumnEnds& ends_y);

/// One step of the plane-averaged momentum balance of one horizontal velocity component, implicit in the stress
/// (backward Euler; the eddy viscosity lagged, as given), per unit plan area:
///   rho eps_i h (u_i' - u_i) = dt (tau_{i+1/2}' - tau_{i-1/2}') + dt rho eps_i h f - impulse_i,
///   tau_{i+1/2} = rho eps_{i+1/2} (nu + nu_t,{i+1/2}) (u_{i+1} - u_i) / h,
/// eps = 1 - phi the water's share of a cell (eps at a face: the mean of its two cells; at the floor and the top:
/// the cell's own), the floor a no-slip wall moving at ends.bottom_value, the top a lid at ends.top_value or free of
/// stress. `impulse_i` [N s/m^2] is the momentum the grains took from the water in cell i over the last step (their
/// drag impulse over the plan area, with its sign: the water loses it). Tridiagonal (Thomas): O(cells).
/// A relaxation k (u_target,i - u_i) towards a target profile adds to f (a profile forcing), implicit in u.
struct ColumnStep {
  double density = 1000.0;    ///< [kg/m^3] rho
  double viscosity = 1e-6;    ///< [m^2/s] nu
  double dt = 0.0;            ///< [s]
  double body_force = 0.0;    ///< [m/s^2] f, on the water (a pressure gradient -dp/dx = rho f, or gravity down a slope)
  double relaxation_rate = 0.0;                        ///< [1/s] k; 0: none
  const std::vector<double>* relaxation_target = nullptr;  ///< [m/s] u_target per cell (needed when k > 0)
};
struct ColumnStresses {
  double floor = 0.0;  ///< [Pa] tau at the floor after the step (the water's stress on it, along the component)
  double top = 0.0;    ///< [Pa] tau at the top face after the step (0 for a free top)
};
ColumnStresses advance_column(const ColumnGrid& grid, const std::vector<double>& solid_fraction,
                              const std::vector<double>& eddy_viscosity, const std::vector<double>& impulse,
                              const ColumnEnds& ends, const ColumnStep& step, std::vector<double>& velocity);

/// [N s/m^2] The water's momentum per plan area, sum_i rho eps_i h u_i (the closure check of the exchange).
double column_momentum(const ColumnGrid& grid, const std::vector<double>& solid_fraction,
                       const std::vector<double>& velocity, double density);

/// [Pa] The water's shear stress rho eps (nu + nu_t) du/dz at height z (at the nearest face).
double column_shear_stress(const ColumnGrid& grid, const std::vector<double>& solid_fraction,
                           const std::vector<double>& eddy_viscosity, const std::vector<double>& velocity,
                           const ColumnEnds& ends, double density, double viscosity, double z);

}  // namespace riffle
