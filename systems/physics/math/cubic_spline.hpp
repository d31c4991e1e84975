#pragma once
// A cubic spline through tabulated points (t_i, y_i), stored as its knots, values and second derivatives M_i (the
// "curvatures"), with the not-a-knot end conditions of de Boor (A Practical Guide to Splines, 1978, Ch. IV): the
// third derivative is continuous at the second and the second-to-last knot, so the first and last two intervals are
// one cubic each. Unlike the natural spline (M = 0 at the ends) it does not force the acceleration to zero at the
// ends, so a smooth function sampled at spacing h is reproduced to O(h^4) in value, O(h^3) in slope and O(h^2) in
// curvature everywhere, ends included. For the complete (clamped) spline the value error is at most
// (5/384) h^4 max|y''''| (Hall & Meyer 1976, J. Approx. Theory 16, 105-122); the not-a-knot spline reaches the same
// order with a constant close to it away from the ends (tests/unit/cubic_spline_test.cpp measures it).
//
// Pure functions on plain vectors, so that the scene's model (components/model.hpp) can hold the data.
#include <cstddef>
#include <vector>

namespace riffle {

/// Value, first and second derivative of the spline at one time: exact derivatives of the piecewise cubic.
struct SplinePoint {
  double value = 0.0, slope = 0.0, curvature = 0.0;
};

/// Second derivatives M_i at the knots of the not-a-knot cubic spline through (knots[i], values[i]). Needs at least
/// 4 knots, strictly increasing and finite (std::invalid_argument otherwise). O(n): a tridiagonal solve.
std::vector<double> not_a_knot_curvatures(const std::vector<double>& knots, const std::vector<double>& values);

/// The spline at `t` in [knots.front(), knots.back()] (clamped into it outside). `curvatures` from
/// not_a_knot_curvatures. O(log n): the interval is found by bisection.
SplinePoint spline_at(const std::vector<double>& knots, const std::vector<double>& values,
                      const std::vector<double>& curvatures, double t);

/// max |s(t)| over [knots.front(), knots.back()], exact: the knots and every interior extremum of each cubic piece
/// (a root of its quadratic derivative).
double spline_max_abs(const std::vector<double>& knots, const std::vector<double>& values,
                      const std::vector<double>& curvatures);

}  // namespace riffle
