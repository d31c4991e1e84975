#include "systems/dem/solid_contacts.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "systems/physics/contact_law.hpp"

namespace riffle {

namespace {
constexpr std::size_t kGrain = 256;

// Touching grain-grain pairs are evaluated in batches: pass 1 walks the candidates, tests the distance and copies
// the inputs of the touching ones into structure-of-arrays scratch; pass 2 evaluates the batch with straight-line,
// branch-free code (selects only) that the compiler can vectorise; pass 3 writes the pair arrays back in pair order.
// Separated candidates (about half of them in a settled bed) cost only the distance test.
constexpr std::size_t kBatch = 64;

struct PairBatch {
  // Inputs.
  alignas(64) double dx[kBatch], dy[kBatch], dz[kBatch];     // centre line, first to second
  alignas(64) double vix[kBatch], viy[kBatch], viz[kBatch];  // centre velocity of the first
  alignas(64) double vjx[kBatch], vjy[kBatch], vjz[kBatch];  // centre velocity of the second
  alignas(64) double wix[kBatch], wiy[kBatch], wiz[kBatch];  // angular velocity of the first
  alignas(64) double wjx[kBatch], wjy[kBatch], wjz[kBatch];  // angular velocity of the second
  alignas(64) double sx[kBatch], sy[kBatch], sz[kBatch];     // tangential spring (in: old, out: new)
  alignas(64) double ri[kBatch], rj[kBatch], mi[kBatch], mj[kBatch];
  alignas(64) double stiffness_a[kBatch], stiffness_b[kBatch], damping[kBatch], damping_ratio[kBatch];
  alignas(64) double friction[kBatch], rolling[kBatch];
  // Outputs.
  alignas(64) double overlap[kBatch];
  alignas(64) double fx[kBatch], fy[kBatch], fz[kBatch];     // force on the first
  alignas(64) double tix[kBatch], tiy[kBatch], tiz[kBatch];  // torque on the first
  alignas(64) double tjx[kBatch], tjy[kBatch], tjz[kBatch];  // torque on the second
  std::uint32_t pair[kBatch];
  std::uint32_t first[kBatch];
  std::uint32_t second[kBatch];
  std::size_t count = 0;
};

// evaluate_contact (contact_law.hpp) restated on the batch; keep the two in step. The branches of the scalar law
// become selects with both sides computed (the compiler will not speculate a possibly trapping division into a
// select); a division by zero on the discarded side yields inf or NaN that is never used.
template <ContactLaw kLaw, bool kRolling>
[[gnu::always_inline]] inline void evaluate_batch(PairBatch& b, double dt) {
  const std::size_t count = b.count;
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC ivdep
#endif
  for (std::size_t p = 0; p < count; ++p) {
    const double distance_squared = b.dx[p] * b.dx[p] + b.dy[p] * b.dy[p] + b.dz[p] * b.dz[p];
    const double distance = std::sqrt(distance_squared);
    // Divisions rather than multiplications by reciprocals, and the operations in the scalar code's order: the
    // results are bit-identical to the one-pair-at-a-time kernel (a settled bed is chaotic enough that rounding
    // differences move tests that sit near their tolerances).
    const double nx = b.dx[p] / distance, ny = b.dy[p] / distance, nz = b.dz[p] / distance;
    const double radius_i = b.ri[p], radius_j = b.rj[p];
    const double touching_distance = radius_i + radius_j;
    const double overlap = touching_distance - distance;
    // Contact velocity (v_j + w_j x a_j) - (v_i + w_i x a_i) with lever arms a_i = R_i n, a_j = -R_j n.
    const double aix = radius_i * nx, aiy = radius_i * ny, aiz = radius_i * nz;
    const double minus_radius_j = -radius_j;
    const double ajx = minus_radius_j * nx, ajy = minus_radius_j * ny, ajz = minus_radius_j * nz;
    const double wix = b.wix[p], wiy = b.wiy[p], wiz = b.wiz[p];
    const double wjx = b.wjx[p], wjy = b.wjy[p], wjz = b.wjz[p];
    const double cvx = (b.vjx[p] + (wjy * ajz - wjz * ajy)) - (b.vix[p] + (wiy * aiz - wiz * aiy));
    const double cvy = (b.vjy[p] + (wjz * ajx - wjx * ajz)) - (b.viy[p] + (wiz * aix - wix * aiz));
    const double cvz = (b.vjz[p] + (wjx * ajy - wjy * ajx)) - (b.viz[p] + (wix * aiy - wiy * aix));
    const double effective_radius = radius_i * radius_j / touching_distance;
    const double effective_mass = b.mi[p] * b.mj[p] / (b.mi[p] + b.mj[p]);

    const double normal_speed = cvx * nx + cvy * ny + cvz * nz;  // < 0 while approaching
    const double vtx = cvx - normal_speed * nx, vty = cvy - normal_speed * ny, vtz = cvz - normal_speed * nz;
    double normal_stiffness, normal_damping, tangential_stiffness;
    if constexpr (kLaw == ContactLaw::kHertzMindlin) {
      const double root = std::sqrt(effective_radius * overlap);
      normal_stiffness = b.stiffness_a[p] * root;
      normal_damping = b.damping[p] * std::sqrt(normal_stiffness * effective_mass);
      tangential_stiffness = b.stiffness_b[p] * root;
    } else {
      normal_stiffness = b.stiffness_a[p] * effective_mass;
      normal_damping = b.damping[p] * effective_mass;  // the linear law's D
      tangential_stiffness = b.stiffness_b[p] * normal_stiffness;
    }
    const double tangential_damping = b.damping_ratio[p] * normal_damping;
    const double normal_force = std::max(0.0, normal_stiffness * overlap - normal_damping * normal_speed);

    // Spring back into the tangent plane with its length. With no out-of-plane part this is an exact identity
    // (the ratio of equal squared lengths is 1), so the scalar law's test is not needed.
    double spring_x = b.sx[p], spring_y = b.sy[p], spring_z = b.sz[p];
    const double out_of_plane = spring_x * nx + spring_y * ny + spring_z * nz;
    const double length_squared = spring_x * spring_x + spring_y * spring_y + spring_z * spring_z;
    spring_x -= out_of_plane * nx;
    spring_y -= out_of_plane * ny;
    spring_z -= out_of_plane * nz;
    const double projected_squared = spring_x * spring_x + spring_y * spring_y + spring_z * spring_z;
    const double keep_length_any = std::sqrt(length_squared / projected_squared);
    const double keep_length = projected_squared > 0.0 ? keep_length_any : 1.0;
    spring_x = spring_x * keep_length + dt * vtx;
    spring_y = spring_y * keep_length + dt * vty;
    spring_z = spring_z * keep_length + dt * vtz;

    double ftx = tangential_stiffness * spring_x + tangential_damping * vtx;
    double fty = tangential_stiffness * spring_y + tangential_damping * vty;
    double ftz = tangential_stiffness * spring_z + tangential_damping * vtz;
    const double friction_limit = b.friction[p] * normal_force;
    const double tangential_squared = ftx * ftx + fty * fty + ftz * ftz;
    // Coulomb: when sliding, scale the force to mu F_n and reset the spring to carry it alone.
    const bool sliding = tangential_squared > friction_limit * friction_limit;
    const double slide_scale_any = friction_limit / std::sqrt(tangential_squared);
    const double slide_scale = sliding ? slide_scale_any : 1.0;
    ftx *= slide_scale;
    fty *= slide_scale;
    ftz *= slide_scale;
    const bool stiff = tangential_stiffness > 0.0;
    const double reset_x = ftx / tangential_stiffness, reset_y = fty / tangential_stiffness,
                 reset_z = ftz / tangential_stiffness;
    b.sx[p] = sliding ? (stiff ? reset_x : 0.0) : spring_x;
    b.sy[p] = sliding ? (stiff ? reset_y : 0.0) : spring_y;
    b.sz[p] = sliding ? (stiff ? reset_z : 0.0) : spring_z;

    const double fx = ftx - normal_force * nx, fy = fty - normal_force * ny, fz = ftz - normal_force * nz;

    // Rolling friction, T = -mu_r R* F_n w_rel / |w_rel|, zero without spin or without mu_r (a square root and a
    // division per pair, skipped when no material pair has mu_r).
    double rtx = 0.0, rty = 0.0, rtz = 0.0;
    if constexpr (kRolling) {
      const double rwx = wix - wjx, rwy = wiy - wjy, rwz = wiz - wjz;
      const double spin = std::sqrt(rwx * rwx + rwy * rwy + rwz * rwz);
      const double rolling_scale_any = -b.rolling[p] * effective_radius * normal_force / spin;
      const double rolling_scale = ((b.rolling[p] > 0.0) & (spin > 0.0)) ? rolling_scale_any : 0.0;
      rtx = rolling_scale * rwx;
      rty = rolling_scale * rwy;
      rtz = rolling_scale * rwz;
    }

    b.overlap[p] = overlap;
    b.fx[p] = fx;
    b.fy[p] = fy;
    b.fz[p] = fz;
    b.tix[p] = (aiy * fz - aiz * fy) + rtx;
    b.tiy[p] = (aiz * fx - aix * fz) + rty;
    b.tiz[p] = (aix * fy - aiy * fx) + rtz;
    // The second grain receives -F at -R_j n from its centre: (-R_j n) x (-F) = R_j n x F.
    const double bjx = radius_j * nx, bjy = radius_j * ny, bjz = radius_j * nz;
    b.tjx[p] = (bjy * fz - bjz * fy) - rtx;
    b.tjy[p] = (bjz * fx - bjx * fz) - rty;
    b.tjz[p] = (bjx * fy - bjy * fx) - rtz;
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
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_hertz(PairBatch& b, double dt) {
  evaluate_batch<ContactLaw::kHertzMindlin, false>(b, dt);
}
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_hertz_rolling(PairBatch& b, double dt) {
  evaluate_batch<ContactLaw::kHertzMindlin, true>(b, dt);
}
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_linear(PairBatch& b, double dt) {
  evaluate_batch<ContactLaw::kLinearSpringDashpot, false>(b, dt);
}
RIFFLE_CONTACT_KERNEL_CLONES void evaluate_linear_rolling(PairBatch& b, double dt) {
  evaluate_batch<ContactLaw::kLinearSpringDashpot, true>(b, dt);
}

void flush_batch(PairBatch& b, const GrainState& grains, const GrainProperties& properties, const ContactModel& model, bool rolling, double dt,
                 Contacts& contacts) {
  // Gather the remaining inputs of the touching pairs.
  for (std::size_t p = 0; p < b.count; ++p) {
    const std::uint32_t i = b.first[p], j = b.second[p];
    const Vec3& velocity_i = grains.velocity[i];
    const Vec3& velocity_j = grains.velocity[j];
    b.vix[p] = velocity_i.x();
    b.viy[p] = velocity_i.y();
    b.viz[p] = velocity_i.z();
    b.vjx[p] = velocity_j.x();
    b.vjy[p] = velocity_j.y();
    b.vjz[p] = velocity_j.z();
    const Vec3& angular_velocity_i = grains.angular_velocity[i];
    const Vec3& angular_velocity_j = grains.angular_velocity[j];
    b.wix[p] = angular_velocity_i.x();
    b.wiy[p] = angular_velocity_i.y();
    b.wiz[p] = angular_velocity_i.z();
    b.wjx[p] = angular_velocity_j.x();
    b.wjy[p] = angular_velocity_j.y();
    b.wjz[p] = angular_velocity_j.z();
    const Vec3& spring = contacts.pair_spring[b.pair[p]];
    b.sx[p] = spring.x();
    b.sy[p] = spring.y();
    b.sz[p] = spring.z();
    b.mi[p] = properties.mass[i];
    b.mj[p] = properties.mass[j];
    const ContactPairParameters& pair = model.pair(properties.material[i], properties.material[j]);
    b.stiffness_a[p] = pair.normal_stiffness_coefficient;
    b.stiffness_b[p] = pair.tangential_stiffness_coefficient;
    b.damping[p] = model.law == ContactLaw::kHertzMindlin ? pair.damping : pair.normal_damping_coefficient;
    b.damping_ratio[p] = pair.tangential_damping_ratio;
    b.friction[p] = pair.friction;
    b.rolling[p] = pair.rolling_friction;
  }
  if (model.law == ContactLaw::kHertzMindlin)
    rolling ? evaluate_hertz_rolling(b, dt) : evaluate_hertz(b, dt);
  else
    rolling ? evaluate_linear_rolling(b, dt) : evaluate_linear(b, dt);
  for (std::size_t p = 0; p < b.count; ++p) {
    const std::uint32_t k = b.pair[p];
    const Vec3 force(b.fx[p], b.fy[p], b.fz[p]);
    const Vec3 torque_first(b.tix[p], b.tiy[p], b.tiz[p]);
    contacts.pair_overlap[k] = b.overlap[p];
    contacts.pair_spring[k] = Vec3(b.sx[p], b.sy[p], b.sz[p]);
    contacts.pair_force[k] = force;
    contacts.pair_torque_first[k] = torque_first;
    contacts.pair_torque_second[k] = Vec3(b.tjx[p], b.tjy[p], b.tjz[p]);
    // Batch entries are in pair order, so each grain's sum runs in pair order whatever the batch boundaries.
    contacts.first_force[b.first[p]] += force;
    contacts.first_torque[b.first[p]] += torque_first;
  }
  b.count = 0;
}
}  // namespace

void SolidContactForces::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const Walls& walls = context.read<Walls>();
  Contacts& contacts = context.write<Contacts>();
  const ContactModel& law = context.model.contact;
  const double dt = context.dt;
  bool rolling = false;
  for (const ContactPairParameters& pair : law.pairs) rolling = rolling || pair.rolling_friction > 0.0;
  contacts.first_force.resize(grains.size());
  contacts.first_torque.resize(grains.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grains.size(), kGrain), [&](const tbb::blocked_range<std::size_t>& range) {
    PairBatch batch;
    std::size_t count = 0;  // batch.count, in a register while filling
    // Raw pointers held in registers: the compiler cannot tell the batch stores from the vectors' own fields.
    const std::uint32_t* const pair_offsets = contacts.pair_offsets.data();
    const std::uint32_t* const pair_second = contacts.pair_second.data();
    const double* const pair_overlap = contacts.pair_overlap.data();
    const Vec3* const positions = grains.position.data();
    const double* const radii = properties.radius.data();
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      // Local copies: the pair arrays written below could alias the grain arrays as far as the compiler knows.
      const Vec3 position = grains.position[i];
      const Vec3 velocity = grains.velocity[i];
      const Vec3 angular_velocity = grains.angular_velocity[i];
      const double radius = properties.radius[i];
      const double mass = properties.mass[i];
      const std::int32_t material = properties.material[i];
      contacts.first_force[i] = Vec3::Zero();
      contacts.first_torque[i] = Vec3::Zero();
      const std::uint32_t pair_end = pair_offsets[i + 1];
      for (std::uint32_t k = pair_offsets[i]; k < pair_end; ++k) {
        const std::uint32_t j = pair_second[k];
        const Vec3 centre_line = positions[j] - position;
        const double radius_j = radii[j];
        const double touching_distance = radius + radius_j;
        const double distance_squared = centre_line.squaredNorm();
        // Branch-free compaction: every candidate is written at the batch end, only touching ones advance it (about
        // half the candidates touch, in no predictable pattern, so a branch here would mispredict often).
        const bool touching = (distance_squared < touching_distance * touching_distance) & (distance_squared != 0.0);
        const std::size_t p = count;
        batch.pair[p] = k;
        batch.first[p] = static_cast<std::uint32_t>(i);
        batch.second[p] = j;
        batch.dx[p] = centre_line.x();
        batch.dy[p] = centre_line.y();
        batch.dz[p] = centre_line.z();
        batch.ri[p] = radius;
        batch.rj[p] = radius_j;
        count += touching;
        // Apart: most candidates stay apart for many sub-steps, so write only when the pair has just separated.
        // One comparison of the two flags: tested one after the other, the first alone would mispredict often.
        const bool was_touching = pair_overlap[k] > 0.0;
        if (__builtin_expect(static_cast<int>(was_touching) > static_cast<int>(touching), 0)) {
          contacts.pair_overlap[k] = 0.0;
          contacts.pair_spring[k] = Vec3::Zero();
          contacts.pair_force[k] = Vec3::Zero();
          contacts.pair_torque_first[k] = Vec3::Zero();
          contacts.pair_torque_second[k] = Vec3::Zero();
        }
        if (count == kBatch) {
          batch.count = count;
          flush_batch(batch, grains, properties, law, rolling, dt, contacts);
          count = 0;
        }
      }
      for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k) {
        const std::uint32_t wall = contacts.wall_pair_wall[k];
        const Vec3& wall_normal = walls.normal[wall];
        const double height = (position - walls.point[wall]).dot(wall_normal);
        const double overlap = radius - height;
        if (overlap <= 0.0) {
          if (contacts.wall_pair_overlap[k] > 0.0) {
            contacts.wall_pair_overlap[k] = 0.0;
            contacts.wall_pair_spring[k] = Vec3::Zero();
            contacts.wall_pair_force[k] = Vec3::Zero();
            contacts.wall_pair_torque[k] = Vec3::Zero();
          }
          continue;
        }
        contacts.wall_pair_overlap[k] = overlap;
        ContactGeometry geometry;
        geometry.normal = -wall_normal;  // from the grain towards the wall
        geometry.overlap = overlap;
        const Vec3 arm = radius * geometry.normal;
        geometry.contact_velocity = walls.velocity[wall] - (velocity + angular_velocity.cross(arm));
        geometry.relative_angular_velocity = angular_velocity;
        geometry.effective_radius = radius;  // a plane has zero curvature
        geometry.effective_mass = mass;      // a wall does not move in response
        const ContactResponse response = evaluate_contact(law.law, law.pair(material, walls.material[wall]),
                                                          geometry, contacts.wall_pair_spring[k], dt);
        contacts.wall_pair_force[k] = response.force_on_first;
        contacts.wall_pair_torque[k] = arm.cross(response.force_on_first) + response.rolling_torque_on_first;
      }
    }
    batch.count = count;
    flush_batch(batch, grains, properties, law, rolling, dt, contacts);
  });
  context.count_items(grains.size());
}

void SolidContactGather::run(SystemContext& context) {
  const Contacts& contacts = context.read<Contacts>();
  GrainContactForce& contact = context.write<GrainContactForce>();
  // The per-grain first sums exist once solid_contact_forces has run on this list (not yet right after a restore).
  const bool fused = contacts.first_force.size() == contact.size();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, contact.size(), kGrain), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      // The pairs where i is first were summed, in pair order, by solid_contact_forces; separated pairs carry zero.
      Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
      if (fused) {
        force = contacts.first_force[i];
        torque = contacts.first_torque[i];
      } else {
        for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
          force += contacts.pair_force[k];
          torque += contacts.pair_torque_first[k];
        }
      }
      for (std::uint32_t s = contacts.second_offsets[i]; s < contacts.second_offsets[i + 1]; ++s) {
        const std::uint32_t k = contacts.second_pairs[s];
        force -= contacts.pair_force[k];
        torque += contacts.pair_torque_second[k];
      }
      for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k) {
        force += contacts.wall_pair_force[k];
        torque += contacts.wall_pair_torque[k];
      }
      contact.contact_force[i] = force;
      contact.contact_torque[i] = torque;
    }
  });
  context.count_items(contact.size());
}

}  // namespace riffle
