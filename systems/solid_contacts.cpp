#include "systems/solid_contacts.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "systems/contact_law.hpp"

namespace riffle {

namespace {
constexpr std::size_t kGrain = 256;
}

void SolidContactForces::run(SystemContext& context) {
  const Solids& solids = context.read<Solids>();
  const Walls& walls = context.read<Walls>();
  Contacts& contacts = context.write<Contacts>();
  const ContactModel& law = context.model.contact;
  const double dt = context.dt;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, solids.size(), kGrain), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      // Local copies: the pair arrays written below could alias the grain arrays as far as the compiler knows.
      const Vec3 position = solids.position[i];
      const Vec3 velocity = solids.velocity[i];
      const Vec3 angular_velocity = solids.angular_velocity[i];
      const double radius = solids.radius[i];
      const double mass = solids.mass[i];
      const std::int32_t material = solids.material[i];
      for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
        const std::uint32_t j = contacts.pair_second[k];
        const Vec3 centre_line = solids.position[j] - position;
        const double touching_distance = radius + solids.radius[j];
        const double distance_squared = centre_line.squaredNorm();
        if (distance_squared >= touching_distance * touching_distance || distance_squared == 0.0) {
          // Apart: most candidates stay apart for many sub-steps, so write only when the pair has just separated.
          if (contacts.pair_overlap[k] > 0.0) {
            contacts.pair_overlap[k] = 0.0;
            contacts.pair_spring[k] = Vec3::Zero();
            contacts.pair_force[k] = Vec3::Zero();
            contacts.pair_torque_first[k] = Vec3::Zero();
            contacts.pair_torque_second[k] = Vec3::Zero();
          }
          continue;
        }
        const double distance = std::sqrt(distance_squared);
        const double overlap = touching_distance - distance;
        contacts.pair_overlap[k] = overlap;
        ContactGeometry geometry;
        geometry.normal = centre_line / distance;
        geometry.overlap = overlap;
        const Vec3 arm_first = radius * geometry.normal;
        const Vec3 arm_second = -solids.radius[j] * geometry.normal;
        geometry.contact_velocity = (solids.velocity[j] + solids.angular_velocity[j].cross(arm_second)) -
                                    (velocity + angular_velocity.cross(arm_first));
        geometry.relative_angular_velocity = angular_velocity - solids.angular_velocity[j];
        geometry.effective_radius = radius * solids.radius[j] / touching_distance;
        geometry.effective_mass = mass * solids.mass[j] / (mass + solids.mass[j]);
        const ContactResponse response = evaluate_contact(law.law, law.pair(material, solids.material[j]),
                                                          geometry, contacts.pair_spring[k], dt);
        contacts.pair_force[k] = response.force_on_first;
        contacts.pair_torque_first[k] = arm_first.cross(response.force_on_first) + response.rolling_torque_on_first;
        // The second grain receives -F at -R_j n from its centre: (-R_j n) x (-F) = R_j n x F.
        contacts.pair_torque_second[k] =
            (solids.radius[j] * geometry.normal).cross(response.force_on_first) - response.rolling_torque_on_first;
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
  });
  context.count_items(solids.size());
}

void SolidContactGather::run(SystemContext& context) {
  const Contacts& contacts = context.read<Contacts>();
  Solids& solids = context.write<Solids>();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, solids.size(), kGrain), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
      for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
        force += contacts.pair_force[k];
        torque += contacts.pair_torque_first[k];
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
      solids.contact_force[i] = force;
      solids.contact_torque[i] = torque;
    }
  });
  context.count_items(solids.size());
}

void SolidForceSum::run(SystemContext& context) {
  Solids& solids = context.write<Solids>();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, solids.size(), 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      solids.force[i] = solids.contact_force[i];
      solids.torque[i] = solids.contact_torque[i];
    }
  });
  context.count_items(solids.size());
}

}  // namespace riffle
