#pragma once
// The one place that decides which systems a scene runs, and in which phase. A scene enables only what it
// declares: no [solids] table, no solid systems.
#include <memory>
#include <vector>

#include "engine/model.hpp"
#include "engine/system.hpp"

namespace riffle {

struct Pipeline {
  std::vector<std::unique_ptr<System>> step;         ///< once per engine (fluid) step, before the sub-steps
  std::vector<std::unique_ptr<System>> substep;      ///< solid_substeps times per engine step
  std::vector<std::unique_ptr<System>> end_of_step;  ///< once per engine step, after the sub-steps: checks, sums
  /// Once before the first step of a new run: the force systems, so that velocity Verlet's first half kick uses the
  /// forces of the initial state (a bed that starts touching would otherwise get one force-free half kick).
  std::vector<std::unique_ptr<System>> initial_forces;
};

Pipeline build_pipeline(const Model& model);

}  // namespace riffle
