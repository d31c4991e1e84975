#pragma once
// Fluid test scenes built in code: a box tank with fluid blocks, stepped by the engine's own pipeline.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>

#include "engine/setup/fluid_layout.hpp"
#include "engine/setup/initial_state.hpp"
#include "components/model.hpp"
#include "engine/run/stepper.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "engine/run/registry.hpp"

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
  // The fluid verification tests run once more with the quasi-compressible pressure equation (tests/CMakeLists.txt,
  // fluid_verification_quasi_compressible): it must leave still water, the dam-break front and
  // sloshing as good as the incompressible projection leaves them.
  if (const char* sound_speed = std::getenv("RIFFLE_TEST_SOUND_SPEED")) model.fluid.sound_speed = std::atof(sound_speed);
  return model;
}

/// The engine's world and stepper for `model` (kept alive together).
struct FluidRun {
  Model model;
  World world;
  std::unique_ptr<Stepper> stepper;

  /// `edit` may change the initial world (velocities, added particles) before the pipeline is built.
  explicit FluidRun(Model fluid_scene, const std::function<void(World&)>& edit = {})
      : model(std::move(fluid_scene)), world(initial_world(model)) {
    // The tests build or change their models in code: derive the MPS constants from the final l0 and r_e / l0, as
    // the scene reader does once a scene is read.
    if (model.fluid.enabled) fill_mps_constants(model.fluid);
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
      world.fluid_summary->fluid_count = world.fluid_summary->initial_fluid_count = fluid_slot_count(*world.fluid);
    }
    if (edit) edit(world);
    stepper = std::make_unique<Stepper>(build_pipeline(model), world, model);
  }

  /// Number of fluid particles (they hold slots [0, F)).
  std::size_t fluid_count() const { return fluid_slot_count(*world.fluid); }

  /// The current slot of the MPS particle with this id (fluid_cell_sort reorders slots; ids never change).
  std::size_t slot_of(EntityId id) const {
    const auto found = std::find(world.fluid->id.begin(), world.fluid->id.end(), id);
    return static_cast<std::size_t>(found - world.fluid->id.begin());
  }

  /// Positions of the fluid particles indexed by id (fluid particles are laid out first: ids 0 .. F-1).
  std::vector<Vec3> fluid_positions_by_id() const {
    std::vector<Vec3> by_id(fluid_count(), Vec3::Constant(std::nan("")));
    for (std::size_t i = 0; i < fluid_count(); ++i)
      if (world.fluid->id[i] < by_id.size()) by_id[world.fluid->id[i]] = world.fluid->position[i];
    return by_id;
  }

  /// One step; false on failure.
  bool step() {
    stepper->step();
    return world.step_status.ok();
  }

  /// A readable diagnosis of the step status (empty when fine).
  std::string diagnosis() const {
    const StepStatus& s = world.step_status;
    if (s.ok()) return {};
    return "problem " + std::to_string(static_cast<int>(s.problem)) + " in " + s.phase + ", particle " +
           std::to_string(s.entity) + " at (" + std::to_string(s.position.x()) + ", " + std::to_string(s.position.y()) +
           ", " + std::to_string(s.position.z()) + "), t = " + std::to_string(world.time);
  }

  /// Fluid particles outside the tank (tank frame) by more than `tolerance` on a closed face; an open z_max face
  /// only bounds by the domain. Non-finite positions count as outside.
  std::size_t count_outside_tank(double tolerance) const {
    const FluidParticles& fluid = *world.fluid;
    const Vec3 shift = world.tank_motion ? Vec3(world.tank_motion->displacement) : Vec3::Zero();
    const Vec3 low = model.tank.origin - Vec3::Constant(tolerance);
    Vec3 high = model.tank.origin + model.tank.size + Vec3::Constant(tolerance);
    if (std::find(model.tank.open_faces.begin(), model.tank.open_faces.end(), "z_max") != model.tank.open_faces.end())
      high.z() = model.tank.origin.z() + model.tank.size.z() + model.tank.domain_margin;
    std::size_t outside = 0;
    for (std::size_t i = 0; i < fluid_count(); ++i) {
      const Vec3 r = fluid.position[i] - shift;
      const bool finite = std::isfinite(r.x()) && std::isfinite(r.y()) && std::isfinite(r.z());
      if (!finite || (r.array() < low.array()).any() || (r.array() > high.array()).any()) ++outside;
    }
    return outside;
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
