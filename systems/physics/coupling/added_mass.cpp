#include "systems/physics/coupling/added_mass.hpp"

#include "systems/physics/coupling/drag_law.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace riffle {

namespace {
}

double added_mass_coefficient(double voidage) {
  const double solid_fraction = 1.0 - std::clamp(voidage, 1e-6, 1.0);
  return 0.5 * (1.0 + 2.0 * solid_fraction) / (1.0 - solid_fraction);
}

double stable_added_mass_coefficient(double voidage, CouplingModel::FluidVelocity reading) {
  const double eps = std::clamp(voidage, 1e-6, 1.0);
  const double solid_fraction = 1.0 - eps;
  const double zuber = added_mass_coefficient(eps);
  if (solid_fraction <= 0.0) return zuber;
  const double cap = 0.5 * flux_share(reading, eps) * eps / solid_fraction;
  return std::min(zuber, cap);
}

BassetModes BassetModes::make(double window, double shortest) {
  BassetModes modes;
  const double lowest = std::log(1.0 / window);
  const double highest = std::log(20.0 / shortest);
  const double spacing = std::min(1.5, std::max(1e-3, (highest - lowest) / static_cast<double>(kCount - 1)));
  for (std::size_t k = 0; k < kCount; ++k) {
    const double x = lowest + spacing * static_cast<double>(k);
    modes.rate[k] = std::exp(x);
    modes.weight[k] = spacing * std::exp(0.5 * x) / std::sqrt(std::numbers::pi);
  }
  // Trapezoidal end weights: half a node at each end, and the nodes left out lumped into the end modes. Below
  // 1/window: pi^(-1/2) int_{-inf}^{x_0} e^{x/2} dx = 2 (s_0/pi)^(1/2), into the lowest mode (the window's
  // exponential tail). Above the top rate s_n the left-out modes matter only within 1/s_n = shortest/20 of the
  // present, through their integral over it, pi^(-1/2) int_{x_n}^{inf} e^{-x/2} dx = 2 (pi s_n)^(-1/2): the top mode
  // carries it with an extra weight 2 (s_n/pi)^(1/2).
  const double top = lowest + spacing * static_cast<double>(kCount - 1);
  modes.weight[0] = (0.5 * spacing + 2.0) * std::exp(0.5 * lowest) / std::sqrt(std::numbers::pi);
  modes.weight[kCount - 1] = (0.5 * spacing + 2.0) * std::exp(0.5 * top) / std::sqrt(std::numbers::pi);
  return modes;
}

double MeiAdrianKernel::time_scale(double slip_speed, double diameter, double kinematic_viscosity) {
  if (!(slip_speed > 0.0)) return std::numeric_limits<double>::infinity();
  const double reynolds = slip_speed * diameter / kinematic_viscosity;
  const double f_h = 0.75 + kReynoldsSlope * reynolds;
  return std::cbrt(4.0 / std::numbers::pi) * kinematic_viscosity * f_h * f_h / (slip_speed * slip_speed);
}

double MeiAdrianKernel::basset_factor(double t, double time_scale) {
  if (!(t > 0.0)) return 1.0;
  if (!std::isfinite(time_scale)) return 1.0;
  return std::pow(1.0 + std::pow(t / time_scale, 1.5 / kExponent), -kExponent);
}

MeiAdrianModeWeights::MeiAdrianModeWeights(const BassetModes& modes) : modes_(modes) {
  constexpr std::size_t n = BassetModes::kCount;
  constexpr int kTimes = 160;
  constexpr double kPull = 1e-3;  // the pull of c_k toward the factor at 1/rate_k, against 160 rows of O(1)
  // The fit's span: the shortest time the modes resolve (20 / the top rate) to the window (1 / the lowest rate).
  const double shortest = 20.0 / modes.rate[n - 1];
  const double window = 1.0 / modes.rate[0];
  Eigen::MatrixXd response(kTimes, n);  // w_k exp(-s_k t_i) / K_windowed(t_i)
  for (int i = 0; i < kTimes; ++i) {
    const double t = shortest * std::pow(window / shortest, static_cast<double>(i) / (kTimes - 1));
    double basset = 0.0;
    for (std::size_t k = 0; k < n; ++k) basset += modes.weight[k] * std::exp(-modes.rate[k] * t);
    for (std::size_t k = 0; k < n; ++k)
      response(i, static_cast<Eigen::Index>(k)) = modes.weight[k] * std::exp(-modes.rate[k] * t) / basset;
  }
  const Eigen::MatrixXd normal = response.transpose() * response + kPull * Eigen::MatrixXd::Identity(n, n);
  const Eigen::LDLT<Eigen::MatrixXd> solver(normal);
  first_log_ = std::log(shortest / 30.0);
  const double last_log = std::log(1000.0 * window);
  const auto entries = static_cast<std::size_t>(std::ceil((last_log - first_log_) / log_step_)) + 1;
  table_.resize(entries);
  for (std::size_t e = 0; e < entries; ++e) {
    const double time_scale = std::exp(first_log_ + log_step_ * static_cast<double>(e));
    Eigen::VectorXd target(kTimes), pulled(n);
    for (int i = 0; i < kTimes; ++i) {
      const double t = shortest * std::pow(window / shortest, static_cast<double>(i) / (kTimes - 1));
      target(i) = MeiAdrianKernel::basset_factor(t, time_scale);
    }
    for (std::size_t k = 0; k < n; ++k)
      pulled(static_cast<Eigen::Index>(k)) = MeiAdrianKernel::basset_factor(1.0 / modes.rate[k], time_scale);
    const Eigen::VectorXd factor = solver.solve(response.transpose() * target + kPull * pulled);
    for (std::size_t k = 0; k < n; ++k) table_[e][k] = modes.weight[k] * factor(static_cast<Eigen::Index>(k));
  }
}

std::array<double, BassetModes::kCount> MeiAdrianModeWeights::weights(double time_scale) const {
  if (table_.empty() || !std::isfinite(time_scale)) return table_.empty() ? modes_.weight : table_.back();
  const double position = (std::log(std::max(time_scale, 1e-300)) - first_log_) / log_step_;
  if (position <= 0.0) return table_.front();
  const auto below = static_cast<std::size_t>(position);
  if (below + 1 >= table_.size()) return table_.back();
  const double above_share = position - static_cast<double>(below);
  std::array<double, BassetModes::kCount> out{};
  for (std::size_t k = 0; k < BassetModes::kCount; ++k)
    out[k] = (1.0 - above_share) * table_[below][k] + above_share * table_[below + 1][k];
  return out;
}

double basset_prefactor(double diameter, double density, double viscosity) {
  return 1.5 * diameter * diameter * std::sqrt(std::numbers::pi * density * viscosity);
}

}  // namespace riffle
