#pragma once
// Pure formulas of the bed-load measures (engine/output/bedload_probes.hpp, docs/SCENES.md): the volume of a sphere
// inside a horizontal slab, the length of the union of intervals on a periodic line, and the Shields number.
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

}  // namespace riffle
