// evaluate_sphere_pair_batch (contact_law.hpp): the batched contact kernel, in its own file for its compile options
// (-fno-math-errno -fno-trapping-math, CMakeLists.txt: square roots inline, selects over divisions) and its AVX2 copy.
#include "systems/physics/dem/contact_law.hpp"

namespace riffle {

namespace {

template <ContactLaw kLaw, RollingTerm kRolling, bool kShared>
[[gnu::always_inline]] inline void evaluate_batch(SpherePairBatch& b, double dt) {
  const std::size_t count = b.count;
  const SpherePairCoefficients shared = b.shared;
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC ivdep
#endif
  for (std::size_t p = 0; p < count; ++p) {
    const double distance_squared = b.dx[p] * b.dx[p] + b.dy[p] * b.dy[p] + b.dz[p] * b.dz[p];
    const double distance = std::sqrt(distance_squared);
    // Divisions rather than multiplications by reciprocals: the results stay bit-identical to a one-pair-at-a-time
    // evaluation (a settled bed is chaotic enough that rounding differences move tests that sit near their
    // tolerances).
    ContactLaneInput in;
    in.nx = b.dx[p] / distance;
    in.ny = b.dy[p] / distance;
    in.nz = b.dz[p] / distance;
    const double radius_i = b.ri[p], radius_j = b.rj[p];
    const double touching_distance = radius_i + radius_j;
    in.overlap = touching_distance - distance;
    // Contact velocity (v_j + w_j x a_j) - (v_i + w_i x a_i) with lever arms a_i = R_i n, a_j = -R_j n.
    const double aix = radius_i * in.nx, aiy = radius_i * in.ny, aiz = radius_i * in.nz;
    const double minus_radius_j = -radius_j;
    const double ajx = minus_radius_j * in.nx, ajy = minus_radius_j * in.ny, ajz = minus_radius_j * in.nz;
    const double wix = b.wix[p], wiy = b.wiy[p], wiz = b.wiz[p];
    const double wjx = b.wjx[p], wjy = b.wjy[p], wjz = b.wjz[p];
    in.cvx = (b.vjx[p] + (wjy * ajz - wjz * ajy)) - (b.vix[p] + (wiy * aiz - wiz * aiy));
    in.cvy = (b.vjy[p] + (wjz * ajx - wjx * ajz)) - (b.viy[p] + (wiz * aix - wix * aiz));
    in.cvz = (b.vjz[p] + (wjx * ajy - wjy * ajx)) - (b.viz[p] + (wix * aiy - wiy * aix));
    in.rwx = wix - wjx;
    in.rwy = wiy - wjy;
    in.rwz = wiz - wjz;
    in.effective_radius = radius_i * radius_j / touching_distance;
    in.effective_mass = b.effective_mass[p];
    in.stiffness_a = kShared ? shared.stiffness_a : b.stiffness_a[p];
    in.stiffness_b = kShared ? shared.stiffness_b : b.stiffness_b[p];
    in.damping = kShared ? shared.damping : b.damping[p];
    in.damping_ratio = kShared ? shared.damping_ratio : b.damping_ratio[p];
    in.friction = kShared ? shared.friction : b.friction[p];
    in.rolling = kShared ? shared.rolling : b.rolling[p];
    in.sx = b.sx[p];
    in.sy = b.sy[p];
    in.sz = b.sz[p];
    if constexpr (kRolling == RollingTerm::kElasticPlastic) {
      in.rsx = b.rsx[p];
      in.rsy = b.rsy[p];
      in.rsz = b.rsz[p];
      in.rolling_inertia = b.rolling_inertia[p];
    } else {
      in.rsx = in.rsy = in.rsz = in.rolling_inertia = 0.0;
    }

    const ContactLaneOutput out = contact_law_lane<kLaw, kRolling>(in, dt);

    b.sx[p] = out.sx;
    b.sy[p] = out.sy;
    b.sz[p] = out.sz;
    if constexpr (kRolling == RollingTerm::kElasticPlastic) {
      b.rsx[p] = out.rsx;
      b.rsy[p] = out.rsy;
      b.rsz[p] = out.rsz;
    }
    b.overlap[p] = in.overlap;
    const double fx = out.fx, fy = out.fy, fz = out.fz;
    b.fx[p] = fx;
    b.fy[p] = fy;
    b.fz[p] = fz;
    b.tix[p] = (aiy * fz - aiz * fy) + out.rtx;
    b.tiy[p] = (aiz * fx - aix * fz) + out.rty;
    b.tiz[p] = (aix * fy - aiy * fx) + out.rtz;
    // The second sphere receives -F at -R_j n from its centre: (-R_j n) x (-F) = R_j n x F.
    const double bjx = radius_j * in.nx, bjy = radius_j * in.ny, bjz = radius_j * in.nz;
    b.tjx[p] = (bjy * fz - bjz * fy) - out.rtx;
    b.tjy[p] = (bjz * fx - bjx * fz) - out.rty;
    b.tjz[p] = (bjx * fy - bjy * fx) - out.rtz;
  }
}

// The portable build also carries an AVX2 copy of the batch kernel, picked at load time where the CPU has AVX2
// (4-wide divisions and square roots: solid_contact_forces about 20 % faster on the bench machine). AVX2 without
// FMA does the same correctly rounded operations in the same order as SSE2, so both copies give bit-identical
// results; -march=native builds (FMA, possibly contracted) and other compilers or targets get the single kernel.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__AVX2__) && !defined(__FMA__)
#define RIFFLE_CONTACT_KERNEL_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define RIFFLE_CONTACT_KERNEL_CLONES
#endif
/// The batch's coefficients shared or per pair.
template <ContactLaw kLaw, RollingTerm kRolling>
[[gnu::always_inline]] inline void evaluate(SpherePairBatch& b, double dt) {
  if (b.shared_coefficients)
    evaluate_batch<kLaw, kRolling, true>(b, dt);
  else
    evaluate_batch<kLaw, kRolling, false>(b, dt);
}
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_hertz(SpherePairBatch& b, double dt) {
  evaluate<ContactLaw::kHertzMindlin, RollingTerm::kNone>(b, dt);
}
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_hertz_rolling(SpherePairBatch& b, double dt) {
  evaluate<ContactLaw::kHertzMindlin, RollingTerm::kConstantTorque>(b, dt);
}
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_hertz_rolling_spring(SpherePairBatch& b, double dt) {
  evaluate<ContactLaw::kHertzMindlin, RollingTerm::kElasticPlastic>(b, dt);
}
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_linear(SpherePairBatch& b, double dt) {
  evaluate<ContactLaw::kLinearSpringDashpot, RollingTerm::kNone>(b, dt);
}
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_linear_rolling(SpherePairBatch& b, double dt) {
  evaluate<ContactLaw::kLinearSpringDashpot, RollingTerm::kConstantTorque>(b, dt);
}
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_linear_rolling_spring(SpherePairBatch& b, double dt) {
  evaluate<ContactLaw::kLinearSpringDashpot, RollingTerm::kElasticPlastic>(b, dt);
}

}  // namespace

void evaluate_sphere_pair_batch(SpherePairBatch& b, ContactLaw law, RollingTerm rolling, double dt) {
  const bool hertz = law == ContactLaw::kHertzMindlin;
  switch (rolling) {
    case RollingTerm::kNone: hertz ? evaluate_hertz(b, dt) : evaluate_linear(b, dt); return;
    case RollingTerm::kConstantTorque: hertz ? evaluate_hertz_rolling(b, dt) : evaluate_linear_rolling(b, dt); return;
    case RollingTerm::kElasticPlastic:
      hertz ? evaluate_hertz_rolling_spring(b, dt) : evaluate_linear_rolling_spring(b, dt);
      return;
  }
}

}  // namespace riffle
