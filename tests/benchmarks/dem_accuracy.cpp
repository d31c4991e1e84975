// Speed against error for the DEM sub-step: one 5 mm grain of the seed bed (E = 1e7 Pa, nu = 0.3, e = 0.5) hits the
// floor at 0.35 m/s (the bed's fastest grain moves at 0.22 m/s; the seed scene keeps max_impact_speed 0.5) with N
// sub-steps per Hertz collision; prints the restitution error (the worst and the mean over 8 first-touch phases, as the
// scene's check integrates it, and the one the full DEM gives at one phase) and the maximum-overlap error against
// theory, and the wall time the seed run (8,162 grains, 100 periods of 1/1.7 s) would need at a given DEM throughput.
// The scene's restitution check is relaxed here (restitution_tolerance 0.5) so that the coarse sub-steps run at all.
// riffle_dem_accuracy [particle-steps-per-second]
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include "engine/scene/scene.hpp"
#include "engine/run/simulation.hpp"
#include "systems/physics/dem/contact_law.hpp"

int main(int argc, char** argv) {
  using namespace riffle;
  spdlog::set_level(spdlog::level::warn);
  const double throughput = argc > 1 ? std::atof(argv[1]) : 9.2e6;
  const double speed = 0.35, radius = 0.0025, density = 1318.0, young = 1e7, poisson = 0.3;
  const double mass = density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double effective_young = 1.0 / (2.0 * (1.0 - poisson * poisson) / young);
  const double contact_time = hertz_contact_time(effective_young, radius, mass, speed);
  const double max_overlap = hertz_max_overlap(effective_young, radius, mass, speed);
  std::printf("Hertz grain-floor impact at %.2f m/s: t_c = %.4g s, d_max = %.4g m (elastic)\n", speed, contact_time,
              max_overlap);
  std::printf("%6s %12s %16s %16s %16s %18s %22s\n", "N", "dt_solid [s]", "e err, worst", "e err, mean",
              "e rel err, run", "overlap err (e=1)", "seed run [h] at rate");
  for (int steps : {5, 8, 10, 12, 16, 24, 32, 64}) {
    const double solid_dt = contact_time / steps;
    double errors[2] = {0.0, 0.0};
    double worst = 0.0, mean = 0.0;  // the scene's check: 8 first-touch phases
    for (int elastic = 0; elastic < 2; ++elastic) {
      const double restitution = elastic ? 1.0 : 0.5;
      // One sub-step per engine step, so the overlap is sampled every sub-step.
      const double dt = solid_dt;
      const long substeps = 1;
      char scene[2048];
      std::snprintf(scene, sizeof scene,
                    "[run]\nend_time = 1.0\ndt = %g\nsolid_substeps = %ld\ngravity = [0.0, 0.0, 0.0]\n"
                    "[materials.grain]\ndensity = %g\nyoung_modulus = %g\npoisson_ratio = %g\n"
                    "[contact]\nrestitution = %g\nfriction = 0.0\nsteps_per_collision = 4\nrayleigh_fraction = 1.0\n"
                    "max_impact_speed = %g\nrestitution_tolerance = 0.5\n"
                    "[tank]\nsize = [0.02, 0.02, 0.02]\nwall_material = \"grain\"\n[solids]\n[[solids.spheres]]\n"
                    "position = [0.01, 0.01, %.12g]\nvelocity = [0.0, 0.0, %g]\nradius = %g\nmaterial = \"grain\"\n",
                    dt, substeps, density, young, poisson, restitution, speed, radius + 0.37 * speed * solid_dt, -speed, radius);
      Model model = parse_scene(scene, "accuracy");
      const ContactPairParameters pair = model.contact.pair(0, 0);  // the grain on its wall, as the run prepares it
      if (!elastic)
        for (int k = 0; k < 8; ++k) {
          const double achieved =
              discrete_restitution(ContactLaw::kHertzMindlin, pair, radius, mass, speed, solid_dt, (k + 0.5) / 8.0);
          worst = std::max(worst, std::abs(achieved - restitution));
          mean += (achieved - restitution) / 8.0;
        }
      auto simulation = Simulation::from_model(std::move(model));
      double deepest = 0.0;
      for (int step = 0; step < 3 * steps + 4; ++step) {
        simulation->step();
        deepest = std::max(deepest, radius - simulation->world().solids->position[0].z());
      }
      const double rebound = simulation->world().solids->velocity[0].z() / speed;
      errors[elastic] = elastic ? deepest / max_overlap - 1.0 : rebound / restitution - 1.0;
    }
    const double seed_substeps = 100.0 / 1.7 / solid_dt;
    std::printf("%6d %12.4g %16.4f %+16.4f %+16.2e %+18.2e %22.2f\n", steps, solid_dt, worst, mean, errors[0],
                errors[1], 8162.0 * seed_substeps / throughput / 3600.0);
  }
  return 0;
}
