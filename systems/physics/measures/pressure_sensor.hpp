#pragma once
// Pieces of the fluid pressure probes (engine/output/probes.*): when a point counts as wet, what pressure it reads,
// and the quadrature a pressure transducer integrates over its disc with. Pure formulas, tested on their own
// (tests/unit/systems/physics/measures/pressure_sensor_test.cpp).
#include <vector>

namespace riffle {

/// [1] Sum of Wendland weights w(|x - x_j|) at any point x of a continuum of particles of volume l0^3 filling all
/// space: (1/l0^3) int w dV = 4 pi r_e^3 / (42 l0^3) (int_0^1 q^2 (1-q)^4 (1+4q) dq = 1/42). The MPS lattice's own
/// sum at a point differs from it by less than 2 % at r_e = 2.4 l0 (4.09 to 4.21 against 4.14); it is the measure of
/// a full support against which a point's water is counted.
double full_support_density(double spacing, double effective_radius);

/// A point is wet when its wetted fraction is at least this. A lone fluid particle brings at most
/// w(0) / full_support_density = 0.24 of a full support (at r_e = 2.4 l0; less at a larger r_e), so spray never wets
/// a point; a point on a flat free surface (or on a wall at the water line) has 1/2, and one l0/2 above the surface
/// 0.19 (its hydrostatic extrapolation is negative there anyway). A quarter sits between a drop and the water line.
inline constexpr double kWetFractionThreshold = 0.25;

/// [1] The fraction of a point's kernel support not taken by walls that holds water: fluid_weight / (full_weight -
/// solid_weight), clipped to [0, 1] (sums of w over the fluid and over the wall and dummy particles within r_e;
/// full_weight = full_support_density). A point with no room left for water (solid_weight >= full_weight) is dry.
double wetted_fraction(double fluid_weight, double solid_weight, double full_weight);

/// [Pa] What a pressure sensor reads at a point: the Shepard average `weighted_pressure / weight` of the fluid
/// particles' hydrostatically extrapolated pressures (weight > 0), read as 0 where the point is dry (wetted fraction
/// below kWetFractionThreshold: only spray within reach) and clamped at 0 unless the fluid may hold tension. Water
/// with a free surface at p = 0 (the MPS solve clamps p < 0 to 0, numerics 2.8) has p >= 0 everywhere; a negative
/// extrapolation only appears at a point above the particles it comes from, i.e. above the water, in air, where the
/// (gauge) pressure is 0.
double sensor_pressure(double weighted_pressure, double weight, double wet_fraction, bool allow_tension);

/// One quadrature point of a disc: its offset along the disc's two tangent directions [m] and its share of the
/// disc's area [1] (the shares sum to 1).
struct DiscQuadraturePoint {
  double u = 0.0;
  double v = 0.0;
  double weight = 0.0;
};

/// A quadrature over a disc of radius `radius` [m] with points about `spacing` [m] apart: `rings` concentric annuli
/// of equal width (rings = ceil(radius / spacing), at least 1, at most max_rings), annulus k holding m_k >= 4 points
/// equally spaced in angle at its area centroid radius, each weighted by its share of the annulus's area. Every
/// annulus's points average a linear field to its value at the centre (the cosines of m >= 2 equal angles sum to
/// 0), so the rule is exact for linear fields: a transducer in still water reads the pressure at its centre. A
/// radius <= 0 gives the centre alone; a spacing <= 0, max_rings rings.
std::vector<DiscQuadraturePoint> disc_quadrature(double radius, double spacing, int max_rings);

}  // namespace riffle
