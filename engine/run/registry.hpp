#pragma once
// The one place that decides which systems a scene runs, and in which phase. A scene enables only what it
// declares: no [solids] table, no solid systems.
#include <memory>
#include <vector>

#include "components/model.hpp"
#include "engine/core/system.hpp"

namespace riffle {

struct Pipeline {
  /// Once per engine step, before the two branches below start: copies what one branch reads while the other
  /// writes it (the water the grains sample).
  std::vector<std::unique_ptr<System>> step_start;
  std::vector<std::unique_ptr<System>> step;         ///< once per engine (fluid) step: the fluid's branch
  std::vector<std::unique_ptr<System>> solid_step;   ///< once per engine step, first in the grains' branch
  std::vector<std::unique_ptr<System>> substep;      ///< solid_substeps times per engine step, after solid_step
  std::vector<std::unique_ptr<System>> end_of_step;  ///< once per engine step, after the sub-steps: checks, sums
  /// Once before the first step of a new run: the force systems, so that velocity Verlet's first half kick uses the
  /// forces of the initial state (a bed that starts touching would otherwise get one force-free half kick).
  std::vector<std::unique_ptr<System>> initial_forces;
};

Pipeline build_pipeline(const Model& model);

}  // namespace riffle
