#include "components/step_lengths.hpp"

namespace riffle {

const char* step_limit_name(StepLimit limit) {
  switch (limit) {
    case StepLimit::kRunDt: return "run.dt";
    case StepLimit::kCourant: return "courant";
    case StepLimit::kDiffusion: return "diffusion";
    case StepLimit::kDrag: return "drag";
    case StepLimit::kHydrostatic: return "hydrostatic";
  }
  return "?";
}

}  // namespace riffle
