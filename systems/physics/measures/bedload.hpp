#pragma once
// Pure formulas of the bed-load measures (systems/physics/measures/bedload_probes.hpp, docs/SCENES.md): the volume of a sphere
// inside a horizontal slab, the length of the union of intervals on a periodic line, and the Shields number; and the
// threshold and transport laws the seed 003 beds are judged against (docs/RESULTS.md, seed 003): the dimensionless
// grain size, the Shields curve (Soulsby & Whitehouse 1997; Brownlie 1981) and the bed-load laws of Meyer-Peter &
// Mueller (1948) and Wong & Parker (2006).
#include <utility>
#include <vector>

namespace riffle {

/// [m^3] Volume of the sphere of `radius` centred at height `centre` that lies between the heights `low` and `high`
/// (low <= high): pi [r^2 s - s^3/3] over s = z - centre clamped to [-r, r] (exact). 0 outside.
double sphere_slab_volume(double radius, double centre, double low, double high);

/// [m] Length of the union of the intervals [a, b] (a <= b) on the periodic line [0, period): an interval reaching
/// over either end is wrapped to the other; an interval of length >= period covers the whole line. `intervals` is
/// reordered.
double covered_length(std::vector<std::pair<double, double>>& intervals, double period);

/// [1] Shields number Theta = tau / ((rho_p - rho_f) g d) (Shields 1936): the bed shear stress `tau` [Pa] over the
/// submerged weight per area of a grain layer of diameter `diameter` [m], grain density `grain_density` and fluid
/// density `fluid_density` [kg/m^3], gravity `gravity` [m/s^2] (its magnitude). NaN if the denominator is not > 0.
double shields_number(double tau, double grain_density, double fluid_density, double gravity, double diameter);

/// [1] Dimensionless grain size D* = d [g (s - 1) / nu^2]^(1/3) (Soulsby 1997, Dynamics of Marine Sands, Eq. 75),
/// s = rho_p / rho_f, for a grain of `diameter` [m] in a fluid of kinematic viscosity `viscosity` [m^2/s]. NaN if
/// s <= 1 or an argument is not > 0.
double dimensionless_grain_size(double diameter, double relative_density, double gravity, double viscosity);

/// [1] Particle (grain) Reynolds number Re_p = sqrt((s - 1) g d) d / nu = D*^(3/2) (Brownlie 1981's R_g). NaN as above.
double particle_reynolds_number(double diameter, double relative_density, double gravity, double viscosity);

/// [1] Friction Reynolds number Re_f = u* d / nu of the Shields diagram (seed 003's Re_f, Fig. 5) at Shields number
/// `shields`: u* = sqrt(Theta (s - 1) g d), hence Re_f = sqrt(Theta) Re_p.
double friction_reynolds_number(double shields, double particle_reynolds);

/// [1] Threshold Shields number Theta_c(D*) = 0.30 / (1 + 1.2 D*) + 0.055 [1 - exp(-0.020 D*)] (Soulsby & Whitehouse
/// 1997, Proc. Pacific Coasts and Ports '97, 149-154; Soulsby 1997, Eq. 77): the fit to the Shields data for
/// natural sands, 0.055 for coarse grains. NaN if D* is not > 0.
double shields_threshold_soulsby_whitehouse(double grain_size);

/// [1] Threshold Shields number Theta_c(Re_p) = 0.22 Re_p^-0.6 + 0.06 * 10^(-7.7 Re_p^-0.6) (Brownlie 1981,
/// "Prediction of flow depth and sediment discharge in open channels", Caltech report KH-R-43A): a fit of the Shields
/// curve in the particle Reynolds number, 0.06 (Shields' value) for coarse grains. NaN if Re_p is not > 0.
double shields_threshold_brownlie(double particle_reynolds);

/// [1] Dimensionless bed-load flux (Einstein number) q* = 8 (Theta - 0.047)^(3/2) (Meyer-Peter & Mueller 1948, Proc.
/// 2nd IAHR Congress, Stockholm), 0 at or below Theta = 0.047.
double bedload_meyer_peter_mueller(double shields);

/// [1] Dimensionless bed-load flux q* = 3.97 (Theta - 0.0495)^(3/2) (Wong & Parker 2006, J. Hydraul. Eng. 132(11),
/// 1159-1168: MPM re-fitted to its own data without the bed-form correction), 0 at or below Theta = 0.0495.
double bedload_wong_parker(double shields);

/// [m^2/s] Volume flux per unit width q_s = q* sqrt((s - 1) g d^3) of the dimensionless flux `einstein_number`.
double bedload_volume_flux(double einstein_number, double diameter, double relative_density, double gravity);

/// [1] Dimensionless flux q* = q_s / sqrt((s - 1) g d^3) of a volume flux per width `flux` [m^2/s]; NaN if s <= 1.
double einstein_number(double flux, double diameter, double relative_density, double gravity);

}  // namespace riffle
