// The hydrostatic extrapolation of systems/physics/mps/hydrostatic.hpp, which fluid_correct (wall and dummy pressure)
// and the pressure probes (sensor reading) both call: exact for a hydrostatic field, in a tank at rest and in an
// accelerating one.
#include <doctest/doctest.h>

#include "systems/physics/mps/hydrostatic.hpp"

using namespace riffle;

TEST_CASE("the hydrostatic gradient is rho (g - a_tank), and carrying a pressure along it is exact for such a field") {
  const double density = 1000.0;
  const Vec3 gravity(0.0, 0.0, -9.81);
  SUBCASE("a tank at rest: the pressure grows by rho g h with depth h") {
    const Vec3 gradient = hydrostatic_gradient(density, gravity, Vec3::Zero());
    CHECK(gradient == Vec3(0.0, 0.0, -9810.0));
    CHECK(hydrostatic_extrapolation(2000.0, gradient, Vec3(0.3, -0.2, -0.1)) == doctest::Approx(2981.0).epsilon(1e-15));
    CHECK(hydrostatic_extrapolation(2000.0, gradient, Vec3(0.3, -0.2, 0.0)) == 2000.0);  // level: same pressure
  }
  SUBCASE("a tank accelerating sideways: the free surface tilts, the pressure rises towards the trailing wall") {
    const Vec3 acceleration(2.0, 0.0, 0.0);
    const Vec3 gradient = hydrostatic_gradient(density, gravity, acceleration);
    CHECK(gradient == Vec3(-2000.0, 0.0, -9810.0));
    // p(x) = p0 + G . x: from any point to any other, the extrapolation reproduces p to rounding.
    const auto field = [&](const Vec3& x) { return 5000.0 + gradient.dot(x); };
    const Vec3 from(0.1, 0.05, -0.2), to(-0.15, 0.02, -0.05);
    CHECK(hydrostatic_extrapolation(field(from), gradient, to - from) == doctest::Approx(field(to)).epsilon(1e-14));
    CHECK(hydrostatic_extrapolation(0.0, gradient, Vec3(-0.1, 0.0, 0.0)) == doctest::Approx(200.0).epsilon(1e-15));
  }
}
