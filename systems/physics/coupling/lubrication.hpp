#pragma once
// Normal lubrication between a grain and a wall or another grain in a viscous fluid (docs/COUPLING.md,
// "Lubrication"). A resistance F = -c V along the line of centres (V the approach speed), written as the excess of
// the exact resistance over the isolated Stokes drag 6 pi mu a V that the drag law already gives each grain:
//   wall:  c = 6 pi mu a (lambda(h/a) - 1), lambda from Cox & Brenner (1967, Chem. Eng. Sci. 22) near contact,
//          a/h + (1/5) ln(a/h) + 0.9713, and from Schaffer, Norrelykke & Howard (2007, Langmuir 23) beyond
//          h/a = 0.0756 (where the two are equal): within 0.15 % of Brenner's (1961, Chem. Eng. Sci. 16) exact
//          series at every gap;
//   pair:  c = 6 pi mu [a*^2/h + a* (1 + 7 b + b^2) / (5 (1 + b)^2) ln(a*/h)], the singular terms of Jeffrey (1982,
//          Mathematika 29) / Jeffrey & Onishi (1984, JFM 139) for spheres of radii a_1, a_2 = b a_1, reduced radius
//          a* = a_1 a_2 / (a_1 + a_2); its O(1) term, which depends on b, is left out (1.3 % of the exact excess for
//          two equal spheres at h = 0.01 a, 11 % at 0.1 a).
// Gaps below the roughness h_r count as h_r (the asperities touch first; the film between them stays h_r thick),
// gaps at or beyond the cut-off give nothing, and so does a contact (overlap): the contact law, calibrated to the
// dry restitution, takes over (docs/COUPLING.md says why).
#include <cmath>

namespace riffle {

/// [1] Brenner's (1961) exact resistance lambda = F / (6 pi mu a V) of a sphere moving towards a no-slip plane at
/// gap `gap_over_radius` = h/a: his bipolar-coordinate series, summed until its terms drop below 1e-15 of the sum.
double brenner_wall_resistance(double gap_over_radius);

/// [1] The same for the free-surface plane of Brenner (1961), which is also the symmetry plane between two equal
/// spheres approaching each other at equal and opposite speeds (Stimson & Jeffery 1926): each sphere at h/a from it.
double brenner_free_surface_resistance(double gap_over_radius);

/// [1] Cox & Brenner (1967): a/h + (1/5) ln(a/h) + 0.9713, the inner expansion, error O((h/a) ln(h/a)).
double cox_brenner_wall_resistance(double gap_over_radius);

/// [1] Schaffer, Norrelykke & Howard (2007): 1/(1 - 9/8 s + 1/2 s^3 - 57/100 s^4 + 1/5 s^5 + 7/200 s^11
/// - 1/25 s^12), s = a/(a + h): the method of reflections (Lorentz, Faxen) with two terms fitted to Brenner.
double reflection_wall_resistance(double gap_over_radius);

/// [1] The wall resistance riffle uses: Cox & Brenner below h/a = kWallFormSwitch, the reflection form above.
double wall_resistance(double gap_over_radius);
inline constexpr double kWallFormSwitch = 0.07555570638673673;  ///< [1] h/a where the two forms are equal

/// [1] The resistance of a sphere moving along a no-slip plane, F / (6 pi mu a V), at gap h/a: Faxen's reflection
/// series 1 / (1 - 9/16 s + 1/8 s^3 - 45/256 s^4 - 1/16 s^5), s = a / (a + h) (Faxen 1923; Happel & Brenner 1965),
/// a far-field series: near contact the resistance grows as (8/15) ln(a/h) (Goldman, Cox & Brenner 1967), which the
/// series misses, so it is held at its value at h/a = kFaxenSmallestGap below.
double faxen_wall_resistance_tangential(double gap_over_radius);
inline constexpr double kFaxenSmallestGap = 0.1;  ///< [1] h/a

/// [kg/s] c of the wall: 6 pi mu a (lambda(max(h, h_r)/a) - 1), 0 at h >= cutoff and in contact (h <= 0).
double wall_lubrication_coefficient(double radius, double gap, double viscosity, double roughness, double cutoff);

/// [kg/s] c of a pair of radii a_1, a_2 at gap h (singular terms above, clipped at 0), 0 at h >= cutoff and h <= 0.
double pair_lubrication_coefficient(double radius_1, double radius_2, double gap, double viscosity, double roughness,
                                    double cutoff);

/// [m] a* = a_1 a_2 / (a_1 + a_2): the length of the pair law (the grain's radius for a wall, a_2 -> infinity).
inline double reduced_radius(double radius_1, double radius_2) { return radius_1 * radius_2 / (radius_1 + radius_2); }

/// [kg/s] The coefficient over one sub-step centred on the gap h: the 1/h part (the stiff one) as its secant,
/// the exact mean of 1/max(h', h_r) (0 for h' <= 0) over the gaps h' the pair sweeps at its approach speed V in [t - dt/2, t + dt/2]
/// (so a sub-step that crosses much of the film, V dt >> h_r, still takes its full ln(h_0/h_1) impulse), and the
/// rest of c at h. `singular` = 6 pi mu a*^2, the coefficient of 1/h in c.
double swept_coefficient(double coefficient_at_gap, double singular, double gap, double approach_speed, double dt,
                         double roughness, double cutoff);

/// [kg/s] Backward Euler along the normal: c / (1 + c dt / m*). The force -c V with V from the sub-step's end
/// instead of its start, so the relative approach decays as 1/(1 + c dt/m*) per sub-step and never reverses or
/// grows, however stiff c is (c dt/m* = 3 for a 5 mm steel grain 1 um from a wall in glycerol at dt = 10 us, 5e3 at
/// 2.5 nm in mu = 10 Pa s).
inline double implicit_coefficient(double coefficient, double dt, double reduced_mass) {
  return coefficient / (1.0 + coefficient * dt / reduced_mass);
}

}  // namespace riffle
