#pragma once
// Fluid test scenes built in code: a box tank with fluid blocks, stepped by the engine's own pipeline.
#include <memory>

#include "engine/fluid_layout.hpp"
#include "engine/initial_state.hpp"
#include "engine/model.hpp"
#include "engine/stepper.hpp"
#include "systems/registry.hpp"

namespace riffle::test {

/// A model with a fluid in a closed-bottom, open-top box tank of inner size `tank_size` at the origin.
inline Model fluid_model(const Vec3& tank_size, double spacing, const std::vector<ParticleBoxModel>& boxes) {
  Model model;
  model.name = "fluid_test";
  model.scene_file = "fluid_test.toml";
  model.end_time = 1.0;
  model.dt = 1.0e-3;
  model.materials.push_back(Material{"glass", 2500.0, 0.0, 0.0});
  model.tank.size = tank_size;
  model.tank.open_faces = {"z_max"};
  model.tank.domain_margin = 0.05;
  model.fluid.enabled = true;
  model.fluid.spacing = spacing;
  model.fluid.boxes = boxes;
  return model;
}

/// The engine's world and stepper for `model` (kept alive together).
struct FluidRun {
  Model model;
  World world;
  std::unique_ptr<Stepper> stepper;

  explicit FluidRun(Model fluid_scene) : model(std::move(fluid_scene)), world(initial_world(model)) {
    if (!world.fluid) {  // the initial state does not lay out the fluid yet: do it here
      world.fluid.emplace();
      for (const ParticleBoxModel& box : model.fluid.boxes) {
        const std::size_t first = append_layout(*world.fluid, fluid_box_layout(model.tank.origin, box.low, box.high,
                                                                               model.fluid.spacing));
        for (std::size_t i = first; i < world.fluid->size(); ++i) world.fluid->velocity[i] = box.velocity;
      }
      append_layout(*world.fluid, tank_wall_layout(model.tank.origin, model.tank.size, model.tank.open_faces,
                                                   model.fluid.spacing, model.fluid.effective_radius()));
      world.fluid_neighbours.emplace();
      world.fluid_summary.emplace();
    }
    stepper = std::make_unique<Stepper>(build_pipeline(model), world, model);
  }

  /// Steps until `time` (or a failure); returns false on failure.
  bool run_until(double time) {
    while (world.time < time - 1e-12) {
      stepper->step();
      if (!world.step_status.ok()) return false;
    }
    return true;
  }
};

}  // namespace riffle::test
