#pragma once
// The one place that decides which systems a scene runs, and in which phase. A scene enables only what it
// declares: no [solids] table, no solid systems. The stepper makes one graph of a step from these lists, in the
// order step_start, step, (solid_step, then substep once per sub-step) as one node, end_of_step: wherever two
// systems share a component, that order is their data order, so it decides the results bit for bit.
#include <memory>
#include <vector>

#include "components/model.hpp"
#include "systems/system.hpp"

namespace riffle {

struct Pipeline {
  /// Once per engine step, first in the list: copies what one branch reads while the other writes it (the water the
  /// grains sample).
  std::vector<std::unique_ptr<System>> step_start;
  std::vector<std::unique_ptr<System>> step;         ///< once per engine (fluid) step: the fluid's branch
  std::vector<std::unique_ptr<System>> solid_step;   ///< once per engine step, first in the grains' branch
  std::vector<std::unique_ptr<System>> substep;      ///< solid_substeps times per engine step, after solid_step
  std::vector<std::unique_ptr<System>> end_of_step;  ///< once per engine step, last in the list: checks, sums
  /// Once before the first step of a new run: the force systems, so that velocity Verlet's first half kick uses the
  /// forces of the initial state (a bed that starts touching would otherwise get one force-free half kick).
  std::vector<std::unique_ptr<System>> initial_forces;
};

Pipeline build_pipeline(const Model& model);

}  // namespace riffle
