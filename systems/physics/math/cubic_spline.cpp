#include "systems/physics/math/cubic_spline.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace riffle {

std::vector<double> not_a_knot_curvatures(const std::vector<double>& knots, const std::vector<double>& values) {
  const std::size_t n = knots.size();
  if (n < 4 || values.size() != n)
    throw std::invalid_argument("not_a_knot_curvatures: needs at least 4 knots and one value per knot");
  std::vector<double> h(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    h[i] = knots[i + 1] - knots[i];
    if (!(h[i] > 0.0) || !std::isfinite(h[i]) || !std::isfinite(values[i]) || !std::isfinite(values[i + 1]))
      throw std::invalid_argument("not_a_knot_curvatures: knots must be finite and strictly increasing, values finite");
  }
  // Interior equations i = 1 .. n-2 (continuity of the slope at knot i):
  //   h[i-1] M[i-1] + 2 (h[i-1] + h[i]) M[i] + h[i] M[i+1] = 6 (d[i] - d[i-1]),  d[i] = (y[i+1] - y[i]) / h[i].
  // Not-a-knot: M[0] = ((h0 + h1) M1 - h0 M2) / h1 and the mirror at the end, substituted into the first and last
  // equation: a tridiagonal system in M[1] .. M[n-2] (n - 2 >= 2 unknowns), solved by the Thomas algorithm (the
  // substituted rows stay diagonally dominant: |h1^2 - h0^2| / h1 < (h0 + h1)(h0 + 2 h1) / h1).
  const std::size_t m = n - 2;
  std::vector<double> lower(m, 0.0), diagonal(m, 0.0), upper(m, 0.0), rhs(m, 0.0);
  for (std::size_t r = 0; r < m; ++r) {
    const std::size_t i = r + 1;
    lower[r] = h[i - 1];
    diagonal[r] = 2.0 * (h[i - 1] + h[i]);
    upper[r] = h[i];
    rhs[r] = 6.0 * ((values[i + 1] - values[i]) / h[i] - (values[i] - values[i - 1]) / h[i - 1]);
  }
  {
    const double h0 = h[0], h1 = h[1];
    diagonal[0] += h0 * (h0 + h1) / h1;  // h0 M0 with M0 substituted
    upper[0] -= h0 * h0 / h1;
    lower[0] = 0.0;
  }
  {
    const double a = h[n - 3], b = h[n - 2];  // the last two intervals
    diagonal[m - 1] += b * (a + b) / a;       // h[n-2] M[n-1] with M[n-1] = ((a + b) M[n-2] - b M[n-3]) / a
    lower[m - 1] -= b * b / a;
    upper[m - 1] = 0.0;
  }
  // Thomas algorithm.
  for (std::size_t r = 1; r < m; ++r) {
    const double factor = lower[r] / diagonal[r - 1];
    diagonal[r] -= factor * upper[r - 1];
    rhs[r] -= factor * rhs[r - 1];
  }
  std::vector<double> curvature(n, 0.0);
  curvature[m] = rhs[m - 1] / diagonal[m - 1];
  for (std::size_t r = m - 1; r-- > 0;) curvature[r + 1] = (rhs[r] - upper[r] * curvature[r + 2]) / diagonal[r];
  curvature[0] = ((h[0] + h[1]) * curvature[1] - h[0] * curvature[2]) / h[1];
  curvature[n - 1] = ((h[n - 3] + h[n - 2]) * curvature[n - 2] - h[n - 2] * curvature[n - 3]) / h[n - 3];
  return curvature;
}

namespace {

/// The interval [knots[i], knots[i+1]] holding t (t already clamped into the knot range).
std::size_t interval_of(const std::vector<double>& knots, double t) {
  const auto above = std::upper_bound(knots.begin(), knots.end(), t);
  const auto index = static_cast<std::size_t>(above - knots.begin());
  return std::min(index == 0 ? 0 : index - 1, knots.size() - 2);
}

SplinePoint piece_at(const std::vector<double>& knots, const std::vector<double>& values,
                     const std::vector<double>& curvatures, std::size_t i, double t) {
  // s = A y_i + B y_{i+1} + ((A^3 - A) M_i + (B^3 - B) M_{i+1}) h^2 / 6, A = (t_{i+1} - t) / h, B = 1 - A.
  const double h = knots[i + 1] - knots[i];
  const double b = (t - knots[i]) / h;
  const double a = 1.0 - b;
  const double mi = curvatures[i], mj = curvatures[i + 1];
  SplinePoint point;
  point.value = a * values[i] + b * values[i + 1] + ((a * a * a - a) * mi + (b * b * b - b) * mj) * h * h / 6.0;
  point.slope = (values[i + 1] - values[i]) / h - (3.0 * a * a - 1.0) * h * mi / 6.0 + (3.0 * b * b - 1.0) * h * mj / 6.0;
  point.curvature = a * mi + b * mj;
  return point;
}

}  // namespace

SplinePoint spline_at(const std::vector<double>& knots, const std::vector<double>& values,
                      const std::vector<double>& curvatures, double t) {
  const double clamped = std::clamp(t, knots.front(), knots.back());
  return piece_at(knots, values, curvatures, interval_of(knots, clamped), clamped);
}

double spline_max_abs(const std::vector<double>& knots, const std::vector<double>& values,
                      const std::vector<double>& curvatures) {
  double largest = 0.0;
  for (double value : values) largest = std::max(largest, std::abs(value));
  for (std::size_t i = 0; i + 1 < knots.size(); ++i) {
    // On the piece, with u = t - t_i: s' = c1 + 2 c2 u + 3 c3 u^2, c1 = s'(t_i), c2 = M_i / 2, c3 = (M_{i+1} - M_i) / 6h.
    const double h = knots[i + 1] - knots[i];
    const double c1 = piece_at(knots, values, curvatures, i, knots[i]).slope;
    const double c2 = 0.5 * curvatures[i];
    const double c3 = (curvatures[i + 1] - curvatures[i]) / (6.0 * h);
    double roots[2];
    int count = 0;
    if (c3 == 0.0) {
      if (c2 != 0.0) roots[count++] = -c1 / (2.0 * c2);
    } else {
      const double discriminant = 4.0 * c2 * c2 - 12.0 * c3 * c1;
      if (discriminant >= 0.0) {
        const double root = std::sqrt(discriminant);
        roots[count++] = (-2.0 * c2 + root) / (6.0 * c3);
        roots[count++] = (-2.0 * c2 - root) / (6.0 * c3);
      }
    }
    for (int k = 0; k < count; ++k)
      if (roots[k] > 0.0 && roots[k] < h)
        largest = std::max(largest, std::abs(piece_at(knots, values, curvatures, i, knots[i] + roots[k]).value));
  }
  return largest;
}

}  // namespace riffle
