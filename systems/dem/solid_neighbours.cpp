#include "systems/dem/solid_neighbours.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "systems/physics/geometry/cell_index.hpp"
#include "systems/dem/solid_cell_sort.hpp"
#include "systems/physics/dem/contact_slabs.hpp"
#include "systems/physics/dem/touching_springs.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/geometry/verlet_skin.hpp"
#include "systems/physics/ranks/grain_ranks.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

namespace {

constexpr std::size_t kSearchChunk = 256;  // grains per parallel task

/// Uniform grid over the grains' box (solid_grid_shape) with the grains of each cell listed in slot order.
struct GrainBinGrid {
  Vec3 origin;
  double cell_size = 0.0;
  std::array<std::int64_t, 3> cells{};
  std::vector<std::uint32_t> cell_start;  ///< cells + 1
  std::vector<std::uint32_t> grains;      ///< slots grouped by cell, ascending within a cell

  std::array<std::int64_t, 3> cell_of(const Vec3& position) const {
    std::array<std::int64_t, 3> cell{};
    for (int axis = 0; axis < 3; ++axis) {
      // Clamped before the conversion: a grain thrown far out within a step (or a NaN) has no int64 cell index.
      const double scaled = std::floor((position[axis] - origin[axis]) / cell_size);
      const double top = static_cast<double>(cells[static_cast<std::size_t>(axis)] - 1);
      cell[static_cast<std::size_t>(axis)] = static_cast<std::int64_t>(clamp_to_cells(scaled, top));
    }
    return cell;
  }
  std::size_t linear(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return static_cast<std::size_t>((z * cells[1] + y) * cells[0] + x);
  }
};

GrainBinGrid build_grid(const std::vector<Vec3>& positions, const DomainBox& domain, double cell_size) {
  const SolidGridShape shape = solid_grid_shape(positions, domain, cell_size);
  GrainBinGrid grid;
  grid.origin = shape.origin;
  grid.cell_size = shape.cell_size;
  grid.cells = shape.cells;
  const std::size_t cell_count = static_cast<std::size_t>(grid.cells[0] * grid.cells[1] * grid.cells[2]);
  std::vector<std::uint32_t> cell_of_grain(positions.size());
  grid.cell_start.assign(cell_count + 1, 0);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const auto cell = grid.cell_of(positions[i]);
    cell_of_grain[i] = static_cast<std::uint32_t>(grid.linear(cell[0], cell[1], cell[2]));
    ++grid.cell_start[cell_of_grain[i] + 1];
  }
  for (std::size_t cell = 0; cell < cell_count; ++cell) grid.cell_start[cell + 1] += grid.cell_start[cell];
  grid.grains.resize(positions.size());
  std::vector<std::uint32_t> fill(grid.cell_start.begin(), grid.cell_start.end() - 1);
  for (std::size_t i = 0; i < positions.size(); ++i) grid.grains[fill[cell_of_grain[i]]++] = static_cast<std::uint32_t>(i);
  return grid;
}

/// The grains as the search sees them: reals [0, N) and, in a periodic box, their ghosts [N, N + G) after them
/// (components/halo.hpp); `owner_of` maps a slot to its real grain.
struct SearchGrains {
  const std::vector<Vec3>& position;
  const std::vector<double>& radius;
  const Halo* halo = nullptr;  ///< null without periodic axes: every slot is real
  /// A run over MPI ranks: slots from ranks->real_count on are other ranks' grains (null otherwise).
  const RankHalo* ranks = nullptr;
  const std::vector<EntityId>* ids = nullptr;  ///< the reals' ids (with `ranks`)
  std::uint32_t owner_of(std::uint32_t j) const { return halo ? halo->owner_of(j) : j; }
  bool is_rank_ghost(std::uint32_t j) const { return ranks && j >= ranks->real_count; }
  /// The id of slot j: a real's, or another rank's grain's.
  EntityId id_of(std::uint32_t j) const {
    return is_rank_ghost(j) ? ranks->ghost_id[j - ranks->real_count] : (*ids)[owner_of(j)];
  }
  /// Whether this rank lists the pair of real i and slot j: within the reals (or a periodic halo) the side whose
  /// first grain has the lower slot; with another rank's grain the rank that owns the lower id (each pair on one rank).
  bool lists(std::size_t i, std::uint32_t j) const {
    if (is_rank_ghost(j)) return (*ids)[i] < ranks->ghost_id[j - ranks->real_count];
    return owner_of(j) > i;
  }
};

/// Calls visit(j) for every grain j whose owner is > i within r_i + r_j + skin of grain i (plus the lubrication
/// cut-off when on), in a fixed order. A pair across the seam is met from both sides (i with j's ghost, j with i's
/// ghost); only the side whose first grain has the lower slot keeps it, so each contact is listed once.
template <class Visit>
void for_each_candidate(const SearchGrains& solids, const GrainBinGrid& grid, double largest_radius, double skin,
                        const CouplingModel& coupling, std::size_t i, Visit&& visit) {
  const Vec3& position = solids.position[i];
  // a* < r_i: the reach of r_i bounds every pair of grain i.
  const double reach = solids.radius[i] + largest_radius + skin + lubrication_reach(coupling, solids.radius[i],
                                                                                     std::numeric_limits<double>::infinity());
  const auto low = grid.cell_of(position - Vec3::Constant(reach));
  const auto high = grid.cell_of(position + Vec3::Constant(reach));
  for (std::int64_t z = low[2]; z <= high[2]; ++z)
    for (std::int64_t y = low[1]; y <= high[1]; ++y)
      for (std::int64_t x = low[0]; x <= high[0]; ++x) {
        const std::size_t cell = grid.linear(x, y, z);
        for (std::uint32_t k = grid.cell_start[cell]; k < grid.cell_start[cell + 1]; ++k) {
          const std::uint32_t j = grid.grains[k];
          if (!solids.lists(i, j)) continue;
          const double cutoff = solids.radius[i] + solids.radius[j] + skin +
                                lubrication_reach(coupling, solids.radius[i], solids.radius[j]);
          if ((solids.position[j] - position).squaredNorm() < cutoff * cutoff) visit(j);
        }
      }
}

/// The springs saved at a rebuild, sorted by (lower, higher), with an index by the lower id: a lookup is one read and
/// a scan of that grain's few touching pairs, not a binary search over every saved pair. Ids are dense in practice
/// (given in creation order, never reused); where they are not (the largest id far above the count), the index is
/// left empty and the lookup searches the sorted list.
class SavedSprings {
 public:
  explicit SavedSprings(std::vector<CarriedSpring> saved, std::size_t grains) : saved_(std::move(saved)) {
    std::sort(saved_.begin(), saved_.end(), spring_order);
    if (saved_.empty()) return;
    EntityId largest = 0;
    for (const CarriedSpring& spring : saved_) largest = std::max(largest, spring.lower);
    if (largest > 16 * static_cast<EntityId>(grains) + 65536) return;
    start_.assign(static_cast<std::size_t>(largest) + 2, 0);
    for (const CarriedSpring& spring : saved_) ++start_[static_cast<std::size_t>(spring.lower) + 1];
    for (std::size_t id = 0; id + 1 < start_.size(); ++id) start_[id + 1] += start_[id];
  }
  bool empty() const { return saved_.empty(); }
  const CarriedSpring* find(EntityId lower, EntityId higher) const {
    if (start_.empty()) {
      const CarriedSpring probe{lower, higher, Vec3::Zero()};
      auto it = std::lower_bound(saved_.begin(), saved_.end(), probe, spring_order);
      return it != saved_.end() && it->lower == lower && it->higher == higher ? &*it : nullptr;
    }
    if (lower + 1 >= start_.size()) return nullptr;
    for (std::uint32_t s = start_[lower]; s < start_[lower + 1]; ++s)
      if (saved_[s].higher == higher) return &saved_[s];
    return nullptr;
  }

 private:
  std::vector<CarriedSpring> saved_;
  std::vector<std::uint32_t> start_;  ///< lower id -> first saved spring; empty when the ids are too sparse
};

}  // namespace

void exchange_grain_halo_motion(const Solids& solids, Contacts& contacts) {
  const Halo& halo = contacts.halo;
  GrainGhosts& ghosts = contacts.ghosts;
  halo_copy_positions(halo, solids.position, ghosts.position);
  halo_copy(halo, solids.velocity, ghosts.velocity);
  halo_copy(halo, solids.angular_velocity, ghosts.angular_velocity);
}

void exchange_grain_halo(const Solids& solids, Contacts& contacts) {
  const Halo& halo = contacts.halo;
  GrainGhosts& ghosts = contacts.ghosts;
  exchange_grain_halo_motion(solids, contacts);
  halo_copy(halo, solids.radius, ghosts.radius);
  halo_copy(halo, solids.mass, ghosts.mass);
  halo_copy(halo, solids.material, ghosts.material);
}

bool neighbour_list_stale(const Solids& solids, const Contacts& contacts, const TankMotion& tank,
                          bool tank_frame) {
  if (!contacts.valid || contacts.build_position.size() != solids.size()) return true;
  // A list holds while no pair's gap has closed by more than the skin: the two largest displacements since the build
  // add up to no more than it (systems/physics/geometry/verlet_skin.hpp), measured in any frame that translates. In
  // the tank's frame a bed that rides with a shaken tank, and the walls, stand still, so only the grains' motion
  // relative to the tank uses the skin (a wall's gap changes by the grain's displacement relative to it). Over MPI
  // ranks or periodic faces the ranks' boxes and the halo are fixed in the lab, so the lab frame is kept there.
  const Vec3 wall_shift = tank.displacement - contacts.build_tank_displacement;
  const LargestMoves moves =
      largest_moves(solids.position, contacts.build_position, tank_frame ? wall_shift : Vec3::Zero());
  if (!skin_holds(moves, contacts.skin, contacts.ranks.active)) return true;
  return !tank_frame && moves.first + wall_shift.norm() > contacts.skin;
}

namespace {
/// The grains' order at a reordering rebuild: by the contact pass's slab (contact_slabs.hpp: the slabs these positions
/// give), then by cell within it. Each slab is then a run of slots, walked by the pass in memory order, and its
/// neighbours' data lie in a few runs near it.
std::vector<std::size_t> slab_cell_order(const Solids& solids, const Model& model, double skin, const DomainBox& domain,
                                         const PeriodicBox& box, double largest_radius) {
  std::vector<std::size_t> order = cell_order(solids, domain.low, 2.0 * largest_radius);
  const ContactSlabs slabs = contact_slabs(solids.position, halo_width(solids, model, skin), box);
  if (slabs.count() <= 1) return order;
  std::vector<std::uint32_t> slab_of(solids.size());
  for (std::uint32_t s = 0; s < slabs.count(); ++s)
    for (std::uint32_t n = slabs.offsets[s]; n < slabs.offsets[s + 1]; ++n) slab_of[slabs.grains[n]] = s;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return slab_of[a] < slab_of[b]; });
  return order;
}
}  // namespace

void slice_contact_slabs(const Solids& solids, Contacts& contacts, const Model& model) {
  ContactSlabs slabs =
      contact_slabs(contacts.build_position, halo_width(solids, model, contacts.skin), periodic_box(model));
  contacts.slab_offsets = std::move(slabs.offsets);
  contacts.slab_grains = std::move(slabs.grains);
  contacts.slab_periodic = slabs.periodic;
}

void restore_halo_and_slabs(const Solids& solids, Contacts& contacts, const Model& model) {
  if (!contacts.valid || contacts.build_position.size() != solids.size()) return;
  const PeriodicBox box = periodic_box(model);
  // (Over MPI ranks the periodic images come as ghosts from the ranks: no halo of its own.)
  if (box.any() && !contacts.halo.valid && !contacts.ranks.active) {
    build_halo(contacts.build_position, solids.id, box, halo_width(solids, model, contacts.skin), contacts.halo);
    exchange_grain_halo(solids, contacts);
  }
  if (contacts.slab_grains.size() != solids.size()) slice_contact_slabs(solids, contacts, model);
}

void rebuild_neighbour_list(Solids& solids, Contacts& contacts, const Walls& walls, const TankMotion& tank,
                            const Model& model, bool reorder) {
  restore_halo_and_slabs(solids, contacts, model);  // the old list's ghosts name the pairs whose springs are kept below
  // 1. Save the springs of touching pairs by id, before slots change (the old list's halo maps a ghost to its owner:
  // the history of a pair across the seam is the pair's by id).
  std::vector<CarriedSpring> saved_pairs = touching_pair_springs(solids, contacts);
  std::vector<CarriedSpring> saved_walls = touching_wall_springs(solids, contacts);
  // Springs carried in by id without an old list (a world just split over the ranks, or gathered from them for a
  // checkpoint) join the saved ones.
  RankHalo& ranks = contacts.ranks;
  saved_pairs.insert(saved_pairs.end(), ranks.carried_pair_springs.begin(), ranks.carried_pair_springs.end());
  saved_walls.insert(saved_walls.end(), ranks.carried_wall_springs.begin(), ranks.carried_wall_springs.end());
  ranks.carried_pair_springs.clear();
  ranks.carried_wall_springs.clear();
  // Over MPI ranks: the grains that left this rank's box go to their owners with their springs, and the arrivals
  // bring theirs.
  if (ranks.active) {
    // Wrapped first: a grain past a periodic face belongs to the rank whose box holds it once wrapped.
    if (const PeriodicBox periodic = periodic_box(model); periodic.any())
      for (Vec3& position : solids.position) position = periodic.wrap(position);
    // A bed that has moved far from the split (a slide, a flume's bed load) gets new boxes; the migration below moves
    // its grains to them.
    rebalance_grain_ranks(solids, ranks, kRebalanceAbove);
    migrate_grains(solids, ranks, saved_pairs, saved_walls);
  }
  const SavedSprings saved_pair_springs(std::move(saved_pairs), solids.size());
  const SavedSprings saved_wall_springs(std::move(saved_walls), solids.size());

  const std::size_t count = solids.size();
  double smallest_radius = count ? *std::min_element(solids.radius.begin(), solids.radius.end()) : 0.0;
  double largest_radius = count ? *std::max_element(solids.radius.begin(), solids.radius.end()) : 0.0;
  if (ranks.active) {  // every rank's list takes the whole bed's sizes, as one rank's would
    smallest_radius = -ranks::max(count ? -smallest_radius : -std::numeric_limits<double>::infinity());
    largest_radius = ranks::max(largest_radius);
  }
  const double skin = model.contact.skin > 0.0 ? model.contact.skin : 0.5 * smallest_radius;  // default_skin
  const DomainBox domain = domain_box(model);
  const PeriodicBox box = periodic_box(model);

  // 2. Wrap into the periodic box (a grain that left through a face comes back through the other; ids and springs
  // unchanged), then reorder by cell for locality (ids travel with their data; the springs above are keyed by id).
  if (box.any())
    for (Vec3& position : solids.position) position = box.wrap(position);
  if (reorder && count > 1) permute_fields(solids, slab_cell_order(solids, model, skin, domain, box, largest_radius));

  // 3. Grain-grain candidates: count, scan, fill; every grain's list comes out in the same order every time. In a
  // periodic box the ghosts of the grains within the list's reach of a seam join the search after the reals.
  contacts.halo.clear();
  std::vector<Vec3> search_position;
  std::vector<double> search_radius;
  if (ranks.active) {
    // Every other rank's grains within the list's longest candidate distance of this rank's box, and the periodic
    // images of any grain (its own too) that come within it.
    build_rank_ghosts(solids, contacts,
                      2.0 * largest_radius + skin +
                          lubrication_reach(model.coupling, largest_radius, std::numeric_limits<double>::infinity()),
                      box);
  } else if (box.any()) {
    build_halo(solids.position, solids.id, box, halo_width(solids, model, skin), contacts.halo);
    exchange_grain_halo(solids, contacts);
  }
  const bool ghosts = box.any() || ranks.active;
  if (ghosts) {
    search_position = solids.position;
    search_position.insert(search_position.end(), contacts.ghosts.position.begin(), contacts.ghosts.position.end());
    search_radius = solids.radius;
    search_radius.insert(search_radius.end(), contacts.ghosts.radius.begin(), contacts.ghosts.radius.end());
  }
  const SearchGrains search{ghosts ? search_position : solids.position, ghosts ? search_radius : solids.radius,
                            box.any() && !ranks.active ? &contacts.halo : nullptr, ranks.active ? &ranks : nullptr,
                            &solids.id};
  const GrainBinGrid grid = build_grid(search.position, domain, 2.0 * smallest_radius + skin);
  // One search: each block of kSearchChunk grains lists its grains' candidates (each grain's sorted) into its own buffer,
  // and the buffers are joined in grain order, so the list is the same whatever the threads.
  contacts.pair_offsets.assign(count + 1, 0);
  const std::size_t blocks = (count + kSearchChunk - 1) / kSearchChunk;
  std::vector<std::vector<std::uint32_t>> block_second(blocks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t block = range.begin(); block < range.end(); ++block) {
      std::vector<std::uint32_t>& second = block_second[block];
      second.reserve(16 * kSearchChunk);
      for (std::size_t i = block * kSearchChunk; i < std::min(count, (block + 1) * kSearchChunk); ++i) {
        const std::size_t first = second.size();
        for_each_candidate(search, grid, largest_radius, skin, model.coupling, i,
                           [&](std::uint32_t j) { second.push_back(j); });
        std::sort(second.begin() + static_cast<std::ptrdiff_t>(first), second.end());
        contacts.pair_offsets[i + 1] = static_cast<std::uint32_t>(second.size() - first);
      }
    }
  });
  for (std::size_t i = 0; i < count; ++i) contacts.pair_offsets[i + 1] += contacts.pair_offsets[i];
  const std::size_t pairs = contacts.pair_offsets[count];
  contacts.pair_second.resize(pairs);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t block = range.begin(); block < range.end(); ++block)
      std::copy(block_second[block].begin(), block_second[block].end(),
                contacts.pair_second.begin() + contacts.pair_offsets[block * kSearchChunk]);
  });
  contacts.pair_spring.assign(pairs, Vec3::Zero());
  contacts.pair_rolling_spring.assign(pairs, Vec3::Zero());
  contacts.pair_overlap.assign(pairs, 0.0);

  // 4. Reverse index: pairs where each grain is second (itself or through a ghost: the force goes to the owner),
  // ascending pair index.
  // Another rank's grain as second: those pairs are indexed by ghost instead (their forces go back to its rank).
  contacts.second_offsets.assign(count + 1, 0);
  std::size_t ghost_second = 0;
  for (std::size_t k = 0; k < pairs; ++k) {
    if (search.is_rank_ghost(contacts.pair_second[k])) ++ghost_second;
    else ++contacts.second_offsets[search.owner_of(contacts.pair_second[k]) + 1];
  }
  for (std::size_t i = 0; i < count; ++i) contacts.second_offsets[i + 1] += contacts.second_offsets[i];
  contacts.second_pairs.resize(pairs - ghost_second);
  {
    std::vector<std::uint32_t> fill(contacts.second_offsets.begin(), contacts.second_offsets.end() - 1);
    for (std::size_t k = 0; k < pairs; ++k)
      if (!search.is_rank_ghost(contacts.pair_second[k]))
        contacts.second_pairs[fill[search.owner_of(contacts.pair_second[k])]++] = static_cast<std::uint32_t>(k);
  }
  if (ranks.active) {
    const std::size_t ghost_count = ranks.ghost_count();
    ranks.ghost_pair_offsets.assign(ghost_count + 1, 0);
    for (std::size_t k = 0; k < pairs; ++k)
      if (search.is_rank_ghost(contacts.pair_second[k])) ++ranks.ghost_pair_offsets[contacts.pair_second[k] - count + 1];
    for (std::size_t g = 0; g < ghost_count; ++g) ranks.ghost_pair_offsets[g + 1] += ranks.ghost_pair_offsets[g];
    ranks.ghost_pairs.resize(ghost_second);
    std::vector<std::uint32_t> fill(ranks.ghost_pair_offsets.begin(), ranks.ghost_pair_offsets.end() - 1);
    for (std::size_t k = 0; k < pairs; ++k)
      if (search.is_rank_ghost(contacts.pair_second[k]))
        ranks.ghost_pairs[fill[contacts.pair_second[k] - count]++] = static_cast<std::uint32_t>(k);
    ranks.pair_force_on_ghost.assign(pairs, Vec3::Zero());
    ranks.pair_torque_on_ghost.assign(pairs, Vec3::Zero());
  }

  // 5. Grain-wall candidates: every wall plane within r + skin (a grain behind a wall is a candidate too).
  contacts.wall_pair_offsets.assign(count + 1, 0);
  contacts.wall_pair_wall.clear();
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t wall = 0; wall < walls.size(); ++wall) {
      const double height = (solids.position[i] - walls.point[wall]).dot(walls.normal[wall]);
      const double reach = solids.radius[i] + skin +
                           lubrication_reach(model.coupling, solids.radius[i], std::numeric_limits<double>::infinity());
      if (height < reach) contacts.wall_pair_wall.push_back(static_cast<std::uint32_t>(wall));
    }
    contacts.wall_pair_offsets[i + 1] = static_cast<std::uint32_t>(contacts.wall_pair_wall.size());
  }
  const std::size_t wall_pairs = contacts.wall_pair_wall.size();
  contacts.wall_pair_spring.assign(wall_pairs, Vec3::Zero());
  contacts.wall_pair_rolling_spring.assign(wall_pairs, Vec3::Zero());
  contacts.wall_pair_force.assign(wall_pairs, Vec3::Zero());
  contacts.wall_pair_torque.assign(wall_pairs, Vec3::Zero());
  contacts.wall_pair_overlap.assign(wall_pairs, 0.0);

  // 6. Carry the springs over by id, to the pairs that touch at the positions of this build. A pair that separated
  // since its last evaluation keeps no spring: the new list starts it at zero overlap, so the contact pass would not
  // see it separate and clear it, and its next touch would start from the old spring.
  if (!saved_pair_springs.empty() || !saved_wall_springs.empty()) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kSearchChunk), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
          const std::uint32_t j = contacts.pair_second[k];
          const double touching_distance = search.radius[i] + search.radius[j];
          if ((search.position[j] - search.position[i]).squaredNorm() >= touching_distance * touching_distance) continue;
          const EntityId first = solids.id[i], second = search.id_of(j);
          const bool first_lower = first < second;
          if (const CarriedSpring* found =
                  saved_pair_springs.find(first_lower ? first : second, first_lower ? second : first)) {
            contacts.pair_spring[k] = first_lower ? found->spring : Vec3(-found->spring);
            contacts.pair_rolling_spring[k] = first_lower ? found->rolling : Vec3(-found->rolling);
          }
        }
        for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k) {
          const std::uint32_t wall = contacts.wall_pair_wall[k];
          if ((solids.position[i] - walls.point[wall]).dot(walls.normal[wall]) >= solids.radius[i]) continue;
          if (const CarriedSpring* found = saved_wall_springs.find(solids.id[i], wall)) {
            contacts.wall_pair_spring[k] = found->spring;
            contacts.wall_pair_rolling_spring[k] = found->rolling;
          }
        }
      }
    });
  }

  contacts.build_position = solids.position;
  contacts.build_tank_displacement = tank.displacement;
  contacts.skin = skin;
  slice_contact_slabs(solids, contacts, model);
  ++contacts.rebuilds;
  contacts.valid = true;
}

void SolidNeighbours::run(SystemContext& context) {
  Solids& solids = whole_group<Solids>(
      context.write<GrainState>(), context.write<GrainProperties>(), context.write<GrainTotalForce>(),
      context.write<GrainContactForce>(), context.write<GrainDrag>(), context.write<GrainSampledFluid>(),
      context.write<GrainVoidage>(), context.write<GrainAddedMass>(), context.write<GrainLubrication>());
  Contacts& contacts = context.write<Contacts>();
  const TankMotion& tank = context.read<TankMotion>();
  context.count_items(solids.size());
  const PeriodicBox box = periodic_box(context.model);
  restore_halo_and_slabs(solids, contacts, context.model);
  // A grain past a periodic face is wrapped at the next rebuild, not at once: until its skin is used up its pairs
  // stay the same (ghost = owner + period, so a pair across the seam is the same pair on either side of it).
  // Over MPI ranks every rank rebuilds when any list is stale (the rebuild moves grains between them).
  const bool stale = neighbour_list_stale(solids, contacts, tank, !contacts.ranks.active && !box.any());
  if (contacts.ranks.active ? ranks::any(stale) : stale) {
    const bool reorder = contacts.rebuilds % static_cast<std::uint64_t>(context.model.contact.sort_every_rebuild) == 0;
    rebuild_neighbour_list(solids, contacts, context.read<Walls>(), tank, context.model, reorder);
  } else if (contacts.ranks.active) {
    exchange_rank_ghost_motion(solids, contacts);  // the other ranks' grains (and images), as their owners moved them
  } else if (box.any()) {
    exchange_grain_halo_motion(solids, contacts);  // the ghosts follow their owners every sub-step
  }
}

}  // namespace riffle
