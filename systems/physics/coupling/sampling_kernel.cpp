// squared_offsets (sampling_kernel.hpp): in its own file for its AVX2 copy.
#include "systems/physics/coupling/sampling_kernel.hpp"

namespace riffle {

// The portable build also carries an AVX2 copy, picked at load time where the CPU has AVX2; without FMA both copies
// do the same correctly rounded operations in the same order (as contact_law_batch.cpp's kernel).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__AVX2__) && !defined(__FMA__)
__attribute__((target_clones("avx2", "default")))
#endif
void squared_offsets(const double* x, const double* y, const double* z, std::size_t count, const Vec3& centre,
                     double vertical_stretch, double* out) {
  const double cx = centre.x(), cy = centre.y(), cz = centre.z();
  for (std::size_t k = 0; k < count; ++k) {
    const double dx = x[k] - cx, dy = y[k] - cy, dz = (z[k] - cz) * vertical_stretch;
    out[k] = (dx * dx + dy * dy) + dz * dz;  // Eigen's squaredNorm of (dx, dy, dz): the same order
  }
}

}  // namespace riffle
