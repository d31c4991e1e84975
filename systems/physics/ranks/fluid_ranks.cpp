#include "systems/physics/ranks/fluid_ranks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "systems/physics/geometry/recursive_bisection.hpp"
#include "systems/physics/ranks/rank_boxes.hpp"

namespace riffle {

namespace {

std::vector<PartBox> boxes_of(const FluidRankHalo& ranks) { return rank_boxes(ranks.box_low, ranks.box_high); }

}  // namespace

void put_fluid_first(FluidParticles& particles) {
  const auto fluid = static_cast<std::int32_t>(FluidKind::kFluid);
  if (std::is_partitioned(particles.kind.begin(), particles.kind.end(), [&](std::int32_t kind) { return kind == fluid; }))
    return;
  std::vector<std::size_t> order;
  order.reserve(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles.kind[i] == fluid) order.push_back(i);
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles.kind[i] != fluid) order.push_back(i);
  permute_fields(particles, order);
}

std::vector<double> fluid_work_weights(const ParticleState& particles, double reach) {
  const std::size_t count = particles.id.size();
  const auto fluid = static_cast<std::int32_t>(FluidKind::kFluid);
  std::vector<double> weights(count, kFluidWallWeight);
  // The cells of `reach` that hold fluid; a wall or dummy is near the water when one of the 27 around its own does.
  std::unordered_set<std::int64_t> wet;
  const auto cell_of = [&](const Vec3& position) {
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(position.x() / reach)),
                                       static_cast<std::int64_t>(std::floor(position.y() / reach)),
                                       static_cast<std::int64_t>(std::floor(position.z() / reach))};
  };
  const auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    constexpr std::int64_t kSpan = std::int64_t{1} << 20;  // cells per axis a key tells apart (wraps beyond)
    return ((x & (kSpan - 1)) << 40) | ((y & (kSpan - 1)) << 20) | (z & (kSpan - 1));
  };
  if (reach > 0.0)
    for (std::size_t i = 0; i < count; ++i)
      if (particles.kind[i] == fluid) {
        const auto c = cell_of(particles.position[i]);
        wet.insert(key(c[0], c[1], c[2]));
      }
  for (std::size_t i = 0; i < count; ++i) {
    if (particles.kind[i] == fluid) {
      weights[i] = 1.0;
      continue;
    }
    if (!(reach > 0.0)) continue;
    const auto c = cell_of(particles.position[i]);
    bool near = false;
    for (std::int64_t dz = -1; dz <= 1 && !near; ++dz)
      for (std::int64_t dy = -1; dy <= 1 && !near; ++dy)
        for (std::int64_t dx = -1; dx <= 1 && !near; ++dx) near = wet.count(key(c[0] + dx, c[1] + dy, c[2] + dz)) > 0;
    weights[i] = near ? kFluidWallWeight : kFluidFarWallWeight;
  }
  return weights;
}

void split_fluid_over_ranks(FluidParticles& particles, FluidRankHalo& halo, const Vec3& domain_low,
                            const Vec3& domain_high, double reach) {
  const int me = ranks::rank(), count = ranks::size();
  halo = FluidRankHalo{};
  halo.active = true;
  halo.domain_low = domain_low;
  halo.domain_high = domain_high;
  const std::vector<double> weights = fluid_work_weights(particles, reach);
  const std::vector<PartBox> boxes =
      recursive_bisection(particles.position, weights, PartBox{domain_low, domain_high}, count);
  store_rank_boxes(boxes, halo.box_low, halo.box_high);
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (static_cast<int>(part_of(boxes, particles.position[i])) == me) kept.push_back(i);
  keep_fields(particles, kept);  // keeps the order: the fluid stays first
}

std::vector<double> fluid_work_per_box(const ParticleState& particles, const FluidRankHalo& halo, double reach) {
  return weight_per_box(particles.position, fluid_work_weights(particles, reach), boxes_of(halo));
}

bool rebalance_fluid_ranks(const ParticleState& particles, FluidRankHalo& halo, double reach, double above) {
  // A wall by water on another rank weighs as a far one here: the weights guide the cuts, they need not be exact.
  const std::vector<double> weights = fluid_work_weights(particles, reach);
  if (!boxes_out_of_balance(weight_per_box(particles.position, weights, boxes_of(halo)), above)) return false;
  store_rank_boxes(bisect_over_ranks(particles.position, weights, PartBox{halo.domain_low, halo.domain_high},
                                     static_cast<int>(halo.box_low.size())),
                   halo.box_low, halo.box_high);
  ++halo.rebalances;
  return true;
}

std::size_t migrate_fluid_particles(FluidParticles& particles, FluidRankHalo& halo) {
  const auto count = static_cast<std::size_t>(ranks::size());
  const auto me = static_cast<std::size_t>(ranks::rank());
  const std::vector<PartBox> boxes = boxes_of(halo);
  std::vector<std::vector<std::size_t>> leaving(count);
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const std::size_t destination = part_of(boxes, particles.position[i]);
    if (destination == me) kept.push_back(i);
    else leaving[destination].push_back(i);
  }
  std::vector<std::vector<std::byte>> outgoing(count);
  std::size_t left = 0;
  for (std::size_t r = 0; r < count; ++r) {
    ByteWriter out(outgoing[r]);
    for (const std::size_t i : leaving[r]) pack_entity(particles, i, out);
    left += leaving[r].size();
  }
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange(outgoing);
  keep_fields(particles, kept);
  const std::size_t bytes_per_particle = packed_entity_bytes<FluidParticles>();
  for (std::size_t r = 0; r < count; ++r) {
    if (r == me || incoming[r].empty()) continue;
    if (incoming[r].size() % bytes_per_particle != 0)
      throw std::logic_error("fluid_ranks: a migration message from rank " + std::to_string(r) + " is not whole particles");
    const std::size_t first = particles.size(), arriving = incoming[r].size() / bytes_per_particle;
    resize_fields(particles, first + arriving);
    ByteReader in(incoming[r]);
    for (std::size_t k = 0; k < arriving; ++k) unpack_entity(particles, first + k, in);
  }
  put_fluid_first(particles);
  halo.particles_sent += left;
  return left;
}

void build_fluid_rank_ghosts(const ParticleState& particles, const std::vector<Vec3>& positions, double reach,
                             const PeriodicBox& box, FluidRankHalo& halo, FluidGhosts& ghosts) {
  const auto count = static_cast<std::size_t>(ranks::size());
  const auto me = static_cast<std::size_t>(ranks::rank());
  const std::size_t reals = particles.id.size();
  if (positions.size() != reals)
    throw std::logic_error("build_fluid_rank_ghosts: " + std::to_string(positions.size()) + " positions for " +
                           std::to_string(reals) + " particles");
  halo.real_count = static_cast<std::uint32_t>(reals);
  halo.send_slots.assign(count, {});
  halo.send_shift.assign(count, {});
  const std::vector<Vec3> shifts = periodic_image_shifts(box);
  std::vector<std::vector<std::byte>> outgoing(count);
  for (std::size_t r = 0; r < count; ++r) {
    const PartBox target{halo.box_low[r], halo.box_high[r]};
    std::vector<std::uint32_t>& slots = halo.send_slots[r];
    std::vector<Vec3>& sent_shift = halo.send_shift[r];
    ByteWriter out(outgoing[r]);
    for (std::size_t i = 0; i < reals; ++i)
      for (const Vec3& shift : shifts) {
        if (r == me && shift.isZero(0.0)) continue;  // its own particles are reals here
        const Vec3 image = positions[i] + shift;
        if (distance_to_box(target, image) >= reach) continue;
        slots.push_back(static_cast<std::uint32_t>(i));
        sent_shift.push_back(shift);
        out.put(particles.id[i]);
        out.put(particles.kind[i]);
        out.put(image);
        out.put(particles.velocity[i]);
      }
  }
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange(outgoing);
  ghosts.position.clear();
  ghosts.velocity.clear();
  ghosts.kind.clear();
  halo.ghost_id.clear();
  halo.receive_offsets = read_ghost_records(incoming, [&](ByteReader& in) {
    halo.ghost_id.push_back(in.get<EntityId>());
    ghosts.kind.push_back(in.get<std::int32_t>());
    ghosts.position.push_back(in.get<Vec3>());
    ghosts.velocity.push_back(in.get<Vec3>());
  });
}

double fluid_box_overflow(const std::vector<Vec3>& positions, const FluidRankHalo& halo) {
  const auto me = static_cast<std::size_t>(ranks::rank());
  const PartBox own{halo.box_low[me], halo.box_high[me]};
  double overflow = 0.0;
  for (const Vec3& position : positions) overflow = std::max(overflow, distance_to_box(own, position));
  return ranks::max(overflow);
}

void check_fluid_ghost_build(std::size_t reals, const FluidRankHalo& halo) {
  const auto count = static_cast<std::size_t>(ranks::size());
  if (halo.receive_offsets.size() != count + 1 || halo.send_slots.size() != count || halo.send_shift.size() != count)
    throw std::logic_error("fluid_ranks: a ghost field sent before the ghosts were built");
  if (reals != halo.real_count)
    throw std::logic_error("fluid_ranks: a ghost field of " + std::to_string(reals) + " values for the " +
                           std::to_string(halo.real_count) + " particles the ghosts were built for");
}

void exchange_fluid_ghost_positions(const std::vector<Vec3>& real, const FluidRankHalo& halo, std::vector<Vec3>& ghost) {
  check_fluid_ghost_build(real.size(), halo);
  send_to_fluid_ghosts<Vec3>(
      halo, [&](std::size_t r, std::size_t n) { return Vec3(real[halo.send_slots[r][n]] + halo.send_shift[r][n]); }, ghost);
}

RankRows number_rows_over_ranks(const std::vector<std::int32_t>& local_row, const FluidRankHalo& halo) {
  std::size_t own = 0;
  std::int64_t largest = -1;
  for (const std::int32_t row : local_row) {
    own += row >= 0 ? 1 : 0;
    largest = std::max<std::int64_t>(largest, row);
  }
  if (largest + 1 != static_cast<std::int64_t>(own))
    throw std::logic_error("number_rows_over_ranks: the rows are not numbered 0 .. " + std::to_string(own) + " - 1");
  const std::vector<double> counts = ranks::gather_all({static_cast<double>(own)});
  RankRows rows;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    if (static_cast<int>(r) < ranks::rank()) rows.first_row += static_cast<std::size_t>(counts[r]);
    rows.global_rows += static_cast<std::size_t>(counts[r]);
  }
  std::vector<std::int64_t> global_row(local_row.size());
  for (std::size_t i = 0; i < local_row.size(); ++i)
    global_row[i] = local_row[i] >= 0 ? static_cast<std::int64_t>(rows.first_row) + local_row[i] : -1;
  exchange_fluid_ghost_field(global_row, halo, rows.ghost_row);
  return rows;
}

FluidParticles gather_fluid_at_root(const FluidParticles& particles) { return gather_entities_at_root(particles); }

}  // namespace riffle
