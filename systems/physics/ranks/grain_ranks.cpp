#include "systems/physics/ranks/grain_ranks.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "systems/physics/dem/touching_springs.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/geometry/recursive_bisection.hpp"
#include "systems/physics/ranks/rank_boxes.hpp"
#include "systems/physics/ranks/rank_comm.hpp"
#include "systems/physics/ranks/rank_messages.hpp"

namespace riffle {

namespace {

void pack_spring(const CarriedSpring& spring, ByteWriter& out) {
  out.put(spring.lower);
  out.put(spring.higher);
  out.put(spring.spring);
  out.put(spring.rolling);
}

CarriedSpring unpack_spring(ByteReader& in) {
  CarriedSpring spring;
  spring.lower = in.get<EntityId>();
  spring.higher = in.get<EntityId>();
  spring.spring = in.get<Vec3>();
  spring.rolling = in.get<Vec3>();
  return spring;
}

std::vector<PartBox> boxes_of(const RankHalo& ranks) { return rank_boxes(ranks.box_low, ranks.box_high); }

}  // namespace

void split_grains_over_ranks(Solids& solids, Contacts& contacts, const Vec3& domain_low, const Vec3& domain_high) {
  const int me = ranks::rank(), count = ranks::size();
  // The whole world's touching springs, read before the rank halo below takes over (in a periodic box the list's
  // ghosts name their owners through the halo, which the caller has restored).
  const std::vector<CarriedSpring> pair_springs = touching_pair_springs(solids, contacts);
  const std::vector<CarriedSpring> wall_springs = touching_wall_springs(solids, contacts);
  RankHalo& halo = contacts.ranks;
  halo = RankHalo{};
  halo.active = true;
  halo.domain_low = domain_low;
  halo.domain_high = domain_high;
  const std::vector<double> weights(solids.size(), 1.0);
  const std::vector<PartBox> boxes =
      recursive_bisection(solids.position, weights, PartBox{domain_low, domain_high}, count);
  store_rank_boxes(boxes, halo.box_low, halo.box_high);
  std::vector<int> owner(solids.size());
  for (std::size_t i = 0; i < solids.size(); ++i) owner[i] = static_cast<int>(part_of(boxes, solids.position[i]));
  // The springs of the pairs this rank will list (their lower id is its own) and of its grains' walls.
  std::vector<std::pair<EntityId, int>> owner_by_id(solids.size());
  for (std::size_t i = 0; i < solids.size(); ++i) owner_by_id[i] = {solids.id[i], owner[i]};
  std::sort(owner_by_id.begin(), owner_by_id.end());
  const auto mine = [&](EntityId id) {
    const auto it = std::lower_bound(owner_by_id.begin(), owner_by_id.end(), std::make_pair(id, 0));
    return it != owner_by_id.end() && it->first == id && it->second == me;
  };
  for (const CarriedSpring& spring : pair_springs)
    if (mine(spring.lower)) halo.carried_pair_springs.push_back(spring);
  for (const CarriedSpring& spring : wall_springs)
    if (mine(spring.lower)) halo.carried_wall_springs.push_back(spring);
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < solids.size(); ++i)
    if (owner[i] == me) kept.push_back(i);
  keep_fields(solids, kept);
  // The list named the whole world's slots: the first sub-step rebuilds it (with the springs carried above).
  RankHalo keep = std::move(halo);
  contacts = Contacts{};
  contacts.ranks = std::move(keep);
}

std::vector<double> grains_per_box(const Solids& solids, const RankHalo& halo) {
  const std::vector<double> ones(solids.size(), 1.0);
  return weight_per_box(solids.position, ones, boxes_of(halo));
}

bool rebalance_grain_ranks(const Solids& solids, RankHalo& halo, double above) {
  // What each rank would own after this rebuild's migration, in the present boxes (every grain weighs 1).
  const std::vector<double> ones(solids.size(), 1.0);
  if (!boxes_out_of_balance(weight_per_box(solids.position, ones, boxes_of(halo)), above)) return false;
  store_rank_boxes(bisect_over_ranks(solids.position, ones, PartBox{halo.domain_low, halo.domain_high},
                                     static_cast<int>(halo.box_low.size())),
                   halo.box_low, halo.box_high);
  ++halo.rebalances;
  return true;
}

std::size_t migrate_grains(Solids& solids, RankHalo& halo, std::vector<CarriedSpring>& pair_springs,
                           std::vector<CarriedSpring>& wall_springs) {
  const auto count = static_cast<std::size_t>(ranks::size());
  const auto me = static_cast<std::size_t>(ranks::rank());
  const std::vector<PartBox> boxes = boxes_of(halo);
  std::vector<std::size_t> destination(solids.size());
  std::vector<std::vector<std::size_t>> leaving(count);
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    destination[i] = part_of(boxes, solids.position[i]);
    if (destination[i] == me) kept.push_back(i);
    else leaving[destination[i]].push_back(i);
  }
  // Where each leaving grain's springs go: by its id.
  std::vector<std::pair<EntityId, std::size_t>> leaver_rank;
  for (std::size_t r = 0; r < count; ++r)
    for (const std::size_t i : leaving[r]) leaver_rank.emplace_back(solids.id[i], r);
  std::sort(leaver_rank.begin(), leaver_rank.end());
  const auto rank_of_leaver = [&](EntityId id) -> std::size_t {
    const auto it = std::lower_bound(leaver_rank.begin(), leaver_rank.end(), std::make_pair(id, std::size_t{0}));
    return it != leaver_rank.end() && it->first == id ? it->second : me;
  };
  std::vector<std::vector<CarriedSpring>> pair_out(count), wall_out(count);
  std::vector<CarriedSpring> pair_stay, wall_stay;
  for (const CarriedSpring& spring : pair_springs) {
    const std::size_t r = rank_of_leaver(spring.lower);
    (r == me ? pair_stay : pair_out[r]).push_back(spring);
  }
  for (const CarriedSpring& spring : wall_springs) {
    const std::size_t r = rank_of_leaver(spring.lower);
    (r == me ? wall_stay : wall_out[r]).push_back(spring);
  }
  std::vector<std::vector<std::byte>> outgoing(count);
  std::size_t left = 0;
  for (std::size_t r = 0; r < count; ++r) {
    if (r == me) continue;
    ByteWriter out(outgoing[r]);
    out.put(static_cast<std::uint64_t>(leaving[r].size()));
    for (const std::size_t i : leaving[r]) pack_entity(solids, i, out);
    out.put(static_cast<std::uint64_t>(pair_out[r].size()));
    for (const CarriedSpring& spring : pair_out[r]) pack_spring(spring, out);
    out.put(static_cast<std::uint64_t>(wall_out[r].size()));
    for (const CarriedSpring& spring : wall_out[r]) pack_spring(spring, out);
    left += leaving[r].size();
  }
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange(outgoing);
  keep_fields(solids, kept);
  pair_springs = std::move(pair_stay);
  wall_springs = std::move(wall_stay);
  for (std::size_t r = 0; r < count; ++r) {
    if (r == me || incoming[r].empty()) continue;
    ByteReader in(incoming[r]);
    const auto arriving = static_cast<std::size_t>(in.get<std::uint64_t>());
    const std::size_t first = solids.size();
    resize_fields(solids, first + arriving);
    for (std::size_t k = 0; k < arriving; ++k) unpack_entity(solids, first + k, in);
    for (auto* springs : {&pair_springs, &wall_springs}) {
      const auto n = static_cast<std::size_t>(in.get<std::uint64_t>());
      for (std::size_t k = 0; k < n; ++k) springs->push_back(unpack_spring(in));
    }
    if (!in.done()) throw std::logic_error("grain_ranks: a migration message from rank " + std::to_string(r) + " has trailing bytes");
  }
  halo.grains_sent += left;
  return left;
}

void build_rank_ghosts(const Solids& solids, Contacts& contacts, double reach, const PeriodicBox& box) {
  const auto count = static_cast<std::size_t>(ranks::size());
  const auto me = static_cast<std::size_t>(ranks::rank());
  RankHalo& halo = contacts.ranks;
  halo.real_count = static_cast<std::uint32_t>(solids.size());
  halo.send_slots.assign(count, {});
  halo.send_shift.assign(count, {});
  // The images a grain may have: every sum of -1, 0 or +1 period along the periodic axes (the zero shift first).
  const std::vector<Vec3> shifts = periodic_image_shifts(box);
  std::vector<std::vector<std::byte>> outgoing(count);
  for (std::size_t r = 0; r < count; ++r) {
    std::vector<std::uint32_t>& slots = halo.send_slots[r];
    std::vector<Vec3>& sent_shift = halo.send_shift[r];
    for (std::size_t i = 0; i < solids.size(); ++i)
      for (const Vec3& shift : shifts) {
        if (r == me && shift.isZero(0.0)) continue;  // its own grains are reals here
        if (distance_outside_box(halo.box_low[r], halo.box_high[r], solids.position[i] + shift) < reach) {
          slots.push_back(static_cast<std::uint32_t>(i));
          sent_shift.push_back(shift);
        }
      }
    ByteWriter out(outgoing[r]);
    for (std::size_t n = 0; n < slots.size(); ++n) {
      const std::uint32_t i = slots[n];
      out.put(solids.id[i]);
      out.put(Vec3(solids.position[i] + sent_shift[n]));
      out.put(solids.velocity[i]);
      out.put(solids.angular_velocity[i]);
      out.put(solids.radius[i]);
      out.put(solids.mass[i]);
      out.put(solids.material[i]);
      out.put(solids.fixed[i]);
    }
  }
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange(outgoing);
  GrainGhosts& ghosts = contacts.ghosts;
  ghosts = GrainGhosts{};
  halo.ghost_id.clear();
  halo.ghost_fixed.clear();
  halo.receive_offsets = read_ghost_records(incoming, [&](ByteReader& in) {
    halo.ghost_id.push_back(in.get<EntityId>());
    ghosts.position.push_back(in.get<Vec3>());
    ghosts.velocity.push_back(in.get<Vec3>());
    ghosts.angular_velocity.push_back(in.get<Vec3>());
    ghosts.radius.push_back(in.get<double>());
    ghosts.mass.push_back(in.get<double>());
    ghosts.material.push_back(in.get<std::int32_t>());
    halo.ghost_fixed.push_back(in.get<std::int32_t>());
  });
}

void exchange_rank_ghost_motion(const Solids& solids, Contacts& contacts) {
  const auto count = static_cast<std::size_t>(ranks::size());
  const RankHalo& halo = contacts.ranks;
  std::vector<std::vector<std::byte>> outgoing(count);
  for (std::size_t r = 0; r < count; ++r) {
    ByteWriter out(outgoing[r]);
    const std::vector<std::uint32_t>& slots = halo.send_slots[r];
    for (std::size_t n = 0; n < slots.size(); ++n) {
      const std::uint32_t i = slots[n];
      out.put(Vec3(solids.position[i] + halo.send_shift[r][n]));
      out.put(solids.velocity[i]);
      out.put(solids.angular_velocity[i]);
    }
  }
  // Both sides know the counts from the ghosts' build: point to point, with the neighbours only.
  constexpr std::size_t kMotionBytes = 9 * sizeof(double);  // position, velocity, spin
  std::vector<std::size_t> incoming_bytes(count);
  for (std::size_t r = 0; r < count; ++r)
    incoming_bytes[r] = kMotionBytes * (halo.receive_offsets[r + 1] - halo.receive_offsets[r]);
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange_known(outgoing, incoming_bytes);
  GrainGhosts& ghosts = contacts.ghosts;
  for (std::size_t r = 0; r < count; ++r) {
    if (halo.receive_offsets[r] == halo.receive_offsets[r + 1]) continue;
    ByteReader in(incoming[r]);
    for (std::uint32_t g = halo.receive_offsets[r]; g < halo.receive_offsets[r + 1]; ++g) {
      ghosts.position[g] = in.get<Vec3>();
      ghosts.velocity[g] = in.get<Vec3>();
      ghosts.angular_velocity[g] = in.get<Vec3>();
    }
  }
}

void return_rank_ghost_forces(const Contacts& contacts, std::vector<Vec3>& force, std::vector<Vec3>& torque) {
  const auto count = static_cast<std::size_t>(ranks::size());
  const RankHalo& halo = contacts.ranks;
  std::vector<std::vector<std::byte>> outgoing(count);
  for (std::size_t r = 0; r < count; ++r) {
    ByteWriter out(outgoing[r]);
    for (std::uint32_t g = halo.receive_offsets[r]; g < halo.receive_offsets[r + 1]; ++g) {
      Vec3 ghost_force = Vec3::Zero(), ghost_torque = Vec3::Zero();
      for (std::uint32_t n = halo.ghost_pair_offsets[g]; n < halo.ghost_pair_offsets[g + 1]; ++n) {
        const std::uint32_t k = halo.ghost_pairs[n];
        ghost_force += halo.pair_force_on_ghost[k];
        ghost_torque += halo.pair_torque_on_ghost[k];
      }
      out.put(ghost_force);
      out.put(ghost_torque);
    }
  }
  constexpr std::size_t kForceBytes = 6 * sizeof(double);  // force, torque
  std::vector<std::size_t> incoming_bytes(count);
  for (std::size_t r = 0; r < count; ++r) incoming_bytes[r] = kForceBytes * halo.send_slots[r].size();
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange_known(outgoing, incoming_bytes);
  for (std::size_t r = 0; r < count; ++r) {
    if (halo.send_slots[r].empty()) continue;
    ByteReader in(incoming[r]);
    for (const std::uint32_t i : halo.send_slots[r]) {
      force[i] += in.get<Vec3>();
      torque[i] += in.get<Vec3>();
    }
  }
}

void exchange_rank_ghost_values(const std::vector<double>& real, const Contacts& contacts, std::vector<double>& ghost) {
  const auto count = static_cast<std::size_t>(ranks::size());
  const RankHalo& halo = contacts.ranks;
  std::vector<std::vector<std::byte>> outgoing(count);
  std::vector<std::size_t> incoming_bytes(count);
  for (std::size_t r = 0; r < count; ++r) {
    ByteWriter out(outgoing[r]);
    for (const std::uint32_t i : halo.send_slots[r]) out.put(real[i]);
    incoming_bytes[r] = sizeof(double) * (halo.receive_offsets[r + 1] - halo.receive_offsets[r]);
  }
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange_known(outgoing, incoming_bytes);
  ghost.resize(halo.ghost_count());
  for (std::size_t r = 0; r < count; ++r) {
    if (halo.receive_offsets[r] == halo.receive_offsets[r + 1]) continue;
    ByteReader in(incoming[r]);
    for (std::uint32_t g = halo.receive_offsets[r]; g < halo.receive_offsets[r + 1]; ++g) ghost[g] = in.get<double>();
  }
}

void return_rank_ghost_sums(const Contacts& contacts, const std::vector<Vec3>& pair_value, double factor,
                            std::vector<Vec3>& add_to) {
  const auto count = static_cast<std::size_t>(ranks::size());
  const RankHalo& halo = contacts.ranks;
  std::vector<std::vector<std::byte>> outgoing(count);
  std::vector<std::size_t> incoming_bytes(count);
  for (std::size_t r = 0; r < count; ++r) {
    ByteWriter out(outgoing[r]);
    for (std::uint32_t g = halo.receive_offsets[r]; g < halo.receive_offsets[r + 1]; ++g) {
      Vec3 sum = Vec3::Zero();
      for (std::uint32_t n = halo.ghost_pair_offsets[g]; n < halo.ghost_pair_offsets[g + 1]; ++n)
        sum += pair_value[halo.ghost_pairs[n]];
      out.put(Vec3(factor * sum));
    }
    incoming_bytes[r] = 3 * sizeof(double) * halo.send_slots[r].size();
  }
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange_known(outgoing, incoming_bytes);
  for (std::size_t r = 0; r < count; ++r) {
    if (halo.send_slots[r].empty()) continue;
    ByteReader in(incoming[r]);
    for (const std::uint32_t i : halo.send_slots[r]) add_to[i] += in.get<Vec3>();
  }
}

void gather_contacts_at_root(const Solids& solids, const Contacts& contacts, std::vector<CarriedSpring>& pair_springs,
                             std::vector<WallContactState>& walls) {
  std::vector<std::byte> mine;
  ByteWriter out(mine);
  const std::vector<CarriedSpring> pairs = touching_pair_springs(solids, contacts);
  out.put(static_cast<std::uint64_t>(pairs.size()));
  for (const CarriedSpring& spring : pairs) pack_spring(spring, out);
  std::vector<WallContactState> touching;
  if (contacts.valid && contacts.wall_pair_offsets.size() == solids.size() + 1)
    for (std::size_t i = 0; i < solids.size(); ++i)
      for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k)
        if (contacts.wall_pair_overlap[k] > 0.0)
          touching.push_back({solids.id[i], contacts.wall_pair_wall[k], contacts.wall_pair_spring[k],
                              contacts.wall_pair_rolling_spring[k], contacts.wall_pair_force[k],
                              contacts.wall_pair_torque[k], contacts.wall_pair_overlap[k]});
  out.put(static_cast<std::uint64_t>(touching.size()));
  for (const WallContactState& wall : touching) {
    out.put(wall.grain);
    out.put(wall.wall);
    out.put(wall.spring);
    out.put(wall.rolling);
    out.put(wall.force);
    out.put(wall.torque);
    out.put(wall.overlap);
  }
  const std::vector<std::vector<std::byte>> all = ranks::gather_at_root(mine);
  pair_springs.clear();
  walls.clear();
  for (const auto& bytes : all) {
    ByteReader in(bytes);
    const auto pair_count = static_cast<std::size_t>(in.get<std::uint64_t>());
    for (std::size_t n = 0; n < pair_count; ++n) pair_springs.push_back(unpack_spring(in));
    const auto wall_count = static_cast<std::size_t>(in.get<std::uint64_t>());
    for (std::size_t n = 0; n < wall_count; ++n) {
      WallContactState wall;
      wall.grain = in.get<EntityId>();
      wall.wall = in.get<std::uint32_t>();
      wall.spring = in.get<Vec3>();
      wall.rolling = in.get<Vec3>();
      wall.force = in.get<Vec3>();
      wall.torque = in.get<Vec3>();
      wall.overlap = in.get<double>();
      walls.push_back(wall);
    }
  }
}

Solids gather_grains_at_root(const Solids& solids) { return gather_entities_at_root(solids); }

}  // namespace riffle
