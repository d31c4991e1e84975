#include "systems/physics/dem/contact_slabs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace riffle {

std::uint32_t contact_slab_count(double extent, double reach, bool periodic) {
  if (!(extent > 0.0) || !(reach > 0.0)) return 1;
  // A hair thicker than the reach, so that rounding in the slab index cannot put a pair two slabs apart; capped well
  // above any use (a slab is a parallel task: a few per thread suffice).
  const double fit = std::min(std::floor(extent / (reach * (1.0 + 1e-9))), 4096.0);
  std::uint32_t slabs = fit >= 1.0 ? static_cast<std::uint32_t>(fit) : 1u;
  if (slabs >= 6) return slabs - slabs % 6;
  if (periodic) return slabs >= 3 ? 3u : 1u;
  return slabs;
}

ContactSlabs contact_slabs(const std::vector<Vec3>& position, double reach, const PeriodicBox& box) {
  ContactSlabs slabs;
  slabs.grains.resize(position.size());
  for (std::size_t i = 0; i < position.size(); ++i) slabs.grains[i] = static_cast<std::uint32_t>(i);
  if (position.empty()) return slabs;
  std::array<double, 3> low{}, extent{};
  std::array<std::uint32_t, 3> count{};
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    if (box.periodic[a]) {
      low[a] = box.low[axis];
      extent[a] = box.length[axis];
    } else {
      double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
      for (const Vec3& p : position) {
        lowest = std::min(lowest, p[axis]);
        highest = std::max(highest, p[axis]);
      }
      low[a] = lowest;
      // The grains' span: the grain at its top end goes to the last slab (clamped below), so that every slab holds
      // an equal share of a uniform bed (two threads then finish each phase together).
      extent[a] = std::isfinite(highest - lowest) ? highest - lowest : 0.0;
    }
    count[a] = contact_slab_count(extent[a], reach, box.periodic[a]);
  }
  const auto best = static_cast<std::size_t>(std::max_element(count.begin(), count.end()) - count.begin());
  slabs.axis = static_cast<int>(best);
  slabs.periodic = box.periodic[best];
  const std::uint32_t slab_count = count[best];
  if (slab_count <= 1) {
    slabs.offsets = {0, static_cast<std::uint32_t>(position.size())};
    return slabs;
  }
  // Counting sort of the slots by slab (slot order kept within a slab).
  const double thickness = extent[best] / slab_count;
  std::vector<std::uint32_t> slab_of(position.size());
  slabs.offsets.assign(slab_count + 1, 0);
  for (std::size_t i = 0; i < position.size(); ++i) {
    const double scaled = std::floor((position[i][slabs.axis] - low[best]) / thickness);
    // Clamped (a grain just past a periodic face before its wrap, or a NaN, lands in an end slab).
    const double clamped = scaled >= 0.0 ? std::min(scaled, static_cast<double>(slab_count - 1)) : 0.0;
    slab_of[i] = static_cast<std::uint32_t>(clamped);
    ++slabs.offsets[slab_of[i] + 1];
  }
  for (std::uint32_t s = 0; s < slab_count; ++s) slabs.offsets[s + 1] += slabs.offsets[s];
  std::vector<std::uint32_t> fill(slabs.offsets.begin(), slabs.offsets.end() - 1);
  for (std::size_t i = 0; i < position.size(); ++i) slabs.grains[fill[slab_of[i]]++] = static_cast<std::uint32_t>(i);
  return slabs;
}

bool neighbouring_slabs(const ContactSlabs& slabs, std::uint32_t a, std::uint32_t b) {
  const std::uint32_t low = std::min(a, b), high = std::max(a, b);
  return high - low <= 1 || (slabs.periodic && low == 0 && high + 1 == slabs.count());
}

ContactSlabSchedule contact_slab_schedule(std::uint32_t slabs, bool periodic) {
  ContactSlabSchedule schedule;
  schedule.after.resize(slabs);
  schedule.waits_for.assign(slabs, 0);
  schedule.zeroes.resize(slabs);
  const auto phase = [](std::uint32_t s) { return s % kContactSlabPhases; };
  // The tasks within two slabs of s (each once: a short periodic axis has fewer than four others).
  const auto near = [&](std::uint32_t s) {
    std::vector<std::uint32_t> found;
    for (const int offset : {-2, -1, 1, 2}) {
      std::int64_t t = static_cast<std::int64_t>(s) + offset;
      if (periodic) t = (t + slabs) % slabs;
      if (t < 0 || t >= static_cast<std::int64_t>(slabs) || t == static_cast<std::int64_t>(s)) continue;
      if (std::find(found.begin(), found.end(), static_cast<std::uint32_t>(t)) == found.end())
        found.push_back(static_cast<std::uint32_t>(t));
    }
    return found;
  };
  for (std::uint32_t s = 0; s < slabs; ++s)
    for (const std::uint32_t t : near(s))
      if (phase(s) < phase(t)) {
        schedule.after[s].push_back(t);
        ++schedule.waits_for[t];
      }
  // The first writer of slab s: the lowest phase among the tasks of s and its neighbours.
  for (std::uint32_t s = 0; s < slabs; ++s) {
    std::uint32_t first = s;
    for (const std::uint32_t t : near(s)) {
      const std::uint32_t distance = periodic ? std::min((t + slabs - s) % slabs, (s + slabs - t) % slabs)
                                              : (t > s ? t - s : s - t);
      if (distance == 1 && phase(t) < phase(first)) first = t;
    }
    schedule.zeroes[first].push_back(s);
  }
  return schedule;
}

}  // namespace riffle
