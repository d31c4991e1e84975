// Verification of the viscous term (numerics 1.4: nu times the lambda0 Laplacian, walls carry the wall velocity):
// the viscous decay of a shear mode in a closed, completely filled box without gravity. The box has no periodic
// faces, so the mode is chosen to need no net flow through any cross-section x = const:
//   u_x = U sin(pi y / W) sin(2 pi z / h),  u_y = u_z = 0,
// divergence-free, zero on the four walls y = 0, W, z = 0, h (no slip) and an exact eigenmode of the unsteady Stokes
// equations away from the x-end walls: u decays as exp(-nu k^2 t), k^2 = pi^2 (1/W^2 + 4/h^2). At the x ends the
// flow turns; that disturbance decays into the box like exp(-k x) (Laplace/Stokes in the cross-section), so the
// mode is measured over the middle third only, at least 7 l0 from each end (exp(-k 7 l0) < 2 %).
//
// Sizes (CTest time): l0 = 10 mm, W = 8 l0, h = 16 l0, L = 20 l0 (2560 fluid particles), nu = 1e-3 m^2/s so one
// e-folding takes 0.32 s, 0.3 s at dt = 5 ms (60 steps). U = 1 mm/s keeps every particle within 0.03 l0 of the
// lattice (U t / l0), so the operators act on an (almost) perfect lattice.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "systems/physics/mps/mps_kernel.hpp"
#include "tests/support/fluid_support.hpp"

namespace riffle {
namespace {


/// The decay rate of the mode under nu times the lambda0 Laplacian on the infinite cubic lattice, written out from
/// the Wendland kernel of numerics 1.2 (independent of the simulation code): the symbol
///   sigma(k) = 2D / (lambda0 n0) sum_j w(r_j) (1 - cos(k_y y_j) cos(k_z z_j))
/// (the product mode's lattice sum; the sine parts cancel by symmetry), with n0, lambda0 the lattice sums.
double lattice_symbol(double ky, double kz, double l0, double re) {
  const int reach = static_cast<int>(std::ceil(re / l0));
  double n0 = 0.0, r2w = 0.0, sum = 0.0;
  for (int i = -reach; i <= reach; ++i)
    for (int j = -reach; j <= reach; ++j)
      for (int m = -reach; m <= reach; ++m) {
        if (i == 0 && j == 0 && m == 0) continue;
        const double x = i * l0, y = j * l0, z = m * l0, r = std::sqrt(x * x + y * y + z * z);
        if (r >= re) continue;
        const double q = r / re, w = std::pow(1.0 - q, 4) * (1.0 + 4.0 * q);
        n0 += w;
        r2w += r * r * w;
        sum += w * (1.0 - std::cos(ky * y) * std::cos(kz * z));
      }
  const double lambda0 = r2w / n0;
  return 2.0 * 3.0 / (lambda0 * n0) * sum;
}

}  // namespace

TEST_CASE("viscous decay of a shear mode in a closed box matches exp(-nu k^2 t)") {
  const double l0 = 0.01, width = 8 * l0, height = 16 * l0, length = 20 * l0;
  const double nu = 1.0e-3, speed = 1.0e-3;
  Model model = test::fluid_model(Vec3(length, width, height), l0,
                                  {ParticleBoxModel{Vec3::Zero(), Vec3(length, width, height)}});
  model.tank.open_faces.clear();
  model.gravity = Vec3::Zero();
  model.fluid.kinematic_viscosity = nu;
  model.dt = 5.0e-3;  // below the diffusion limit 0.2 l0^2 / nu = 20 ms
  const double re = model.fluid.effective_radius();
  const double ky = std::numbers::pi / width, kz = 2.0 * std::numbers::pi / height;
  test::FluidRun run(std::move(model), [&](World& world) {
    FluidParticles& fluid = *world.fluid;
    for (std::size_t i = 0; i < fluid_slot_count(fluid); ++i) {
      const Vec3& r = fluid.position[i];
      fluid.velocity[i] = Vec3(speed * std::sin(ky * r.y()) * std::sin(kz * r.z()), 0.0, 0.0);
    }
  });
  REQUIRE(run.fluid_count() == 20 * 8 * 16);

  // Mode amplitude by projection over the middle third in x.
  auto amplitude = [&] {
    const FluidParticles& fluid = *run.world.fluid;
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < run.fluid_count(); ++i) {
      const Vec3& r = fluid.position[i];
      if (std::abs(r.x() - 0.5 * length) > length / 6.0) continue;
      const double phi = std::sin(ky * r.y()) * std::sin(kz * r.z());
      num += fluid.velocity[i].x() * phi;
      den += phi * phi;
    }
    return num / den;
  };
  std::vector<double> times, logs;
  double dt = 0.0;
  while (run.world.time < 0.3 - 1e-12) {
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    dt = run.world.last_step.dt;
    const double a = amplitude();
    REQUIRE(a > 0.0);
    if (run.world.time > 0.02) {  // after the first projection has turned the flow at the ends
      times.push_back(run.world.time);
      logs.push_back(std::log(a));
    }
  }
  // Least-squares slope of ln A(t).
  const double n = static_cast<double>(times.size());
  double st = 0.0, sl = 0.0, stt = 0.0, stl = 0.0;
  for (std::size_t i = 0; i < times.size(); ++i) {
    st += times[i];
    sl += logs[i];
    stt += times[i] * times[i];
    stl += times[i] * logs[i];
  }
  const double rate = -(n * stl - st * sl) / (n * stt - st * st);

  const double continuum = nu * (ky * ky + kz * kz);
  // Bounds: (1) the lattice symbol of the lambda0 Laplacian at the mode's wavenumbers (exact for the interior
  // lattice); (2) the no-slip plane: wall particles at l0/2 outside the boundary carry u = 0 (and so do the
  // dummies behind), so the effective no-slip plane lies between the boundary and the wall layer: W and h are
  // uncertain by up to l0 (l0/2 per wall), which lowers the rate down to the symbol at pi/(W + l0), 2 pi/(h + l0);
  // (3) explicit Euler in time: the measured -ln(1 - nu sigma dt)/dt exceeds nu sigma by at most nu sigma dt / 2
  // (+0.8 %); (4) 2 % for the end disturbance left in the middle third (exp(-k 7 l0) < 2 %).
  const double upper = nu * lattice_symbol(ky, kz, l0, re) * (1.0 + 0.5 * nu * lattice_symbol(ky, kz, l0, re) * dt) * 1.02;
  const double lower = nu * lattice_symbol(std::numbers::pi / (width + l0), 2.0 * std::numbers::pi / (height + l0), l0, re) * 0.98;
  // Effective no-slip offset implied by the measured rate (per wall, in l0): solves nu k_eff^2 = rate with the
  // continuum operator, for the report.
  double offset = 0.0;
  for (double d = 0.0; d <= 1.0; d += 0.001) {
    const double k2 = std::pow(std::numbers::pi / (width + 2 * d * l0), 2) + std::pow(2 * std::numbers::pi / (height + 2 * d * l0), 2);
    if (nu * k2 * (lattice_symbol(ky, kz, l0, re) / (ky * ky + kz * kz)) <= rate) {
      offset = d;
      break;
    }
  }
  MESSAGE("shear mode decay: measured rate " << rate << " 1/s, continuum nu k^2 " << continuum
                                             << ", lattice symbol nu sigma " << nu * lattice_symbol(ky, kz, l0, re)
                                             << ", bounds [" << lower << ", " << upper << "], measured/continuum "
                                             << rate / continuum << ", implied no-slip offset " << offset
                                             << " l0 per wall; " << times.size() << " samples, dt " << dt);
  CHECK(rate > lower);
  CHECK(rate < upper);
  CHECK(run.count_outside_tank(0.5 * l0) == 0);
}

}  // namespace riffle
