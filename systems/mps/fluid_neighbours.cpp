#include "systems/mps/fluid_neighbours.hpp"

#include "systems/physics/geometry/cell_index.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "systems/physics/geometry/verlet_skin.hpp"
#include "systems/physics/ranks/fluid_ranks.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#endif

namespace riffle {

namespace {
std::atomic<FluidSearchSimd> search_simd_cap{FluidSearchSimd::kAvx512};
}  // namespace

void set_fluid_search_simd_cap(FluidSearchSimd cap) { search_simd_cap = cap; }

FluidSearchSimd fluid_search_simd() {
  const FluidSearchSimd cap = search_simd_cap;
#if defined(__GNUC__) && defined(__x86_64__)
  if (cap >= FluidSearchSimd::kAvx512 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512bw"))
    return FluidSearchSimd::kAvx512;
  if (cap >= FluidSearchSimd::kAvx2 && __builtin_cpu_supports("avx2")) return FluidSearchSimd::kAvx2;
#endif
  (void)cap;
  return FluidSearchSimd::kPortable;
}

namespace {

constexpr std::size_t kFluidSearchChunk = 512;  // fluid particles per parallel task

struct Box {
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 high = Vec3::Constant(-std::numeric_limits<double>::infinity());
};

bool finite(const Vec3& position) { return std::isfinite(position[0]) && std::isfinite(position[1]) && std::isfinite(position[2]); }

/// Uniform grid on the lattice of `anchor` with the particles of each cell listed in slot order, and their
/// positions copied in the same order, so that a query streams through a row of cells as one contiguous run.
struct FluidBinGrid {
  Vec3 origin = Vec3::Zero();
  double cell_size = 1.0;
  double inverse_cell_size = 1.0;  ///< the queries multiply: a division per row bound costs more than the test
  std::array<std::int64_t, 3> cells{1, 1, 1};
  std::vector<std::uint32_t> cell_start;  ///< cells + 1
  std::vector<std::uint32_t> members;     ///< finite particles grouped by cell, ascending slot within a cell
  /// positions[members[k]], one array per axis: the candidate test loads 4 or 8 at a time where AVX2 or AVX-512 is there
  std::array<std::vector<double>, 3> member_coordinates;

  std::int64_t axis_cell(double coordinate, int axis) const {
    const double scaled = std::floor((coordinate - origin[axis]) * inverse_cell_size);
    const double top = static_cast<double>(cells[static_cast<std::size_t>(axis)] - 1);
    return static_cast<std::int64_t>(clamp_to_cells(scaled, top));
  }
  std::size_t linear(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return static_cast<std::size_t>((z * cells[1] + y) * cells[0] + x);
  }
};

FluidBinGrid build_grid(const std::vector<Vec3>& positions, double radius, std::size_t query_count, const Vec3& anchor,
                    double cell_radius) {
  const std::size_t count = positions.size();
  // The grid covers the queries' box widened by the radius: particles beyond it (walls far from the water) cannot be
  // anyone's neighbour and stay out of the grid.
  Box box = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, query_count, 4096), Box{},
      [&](const tbb::blocked_range<std::size_t>& range, Box box) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          if (!finite(positions[i])) continue;
          box.low = box.low.cwiseMin(positions[i]);
          box.high = box.high.cwiseMax(positions[i]);
        }
        return box;
      },
      [](Box a, const Box& b) {
        a.low = a.low.cwiseMin(b.low);
        a.high = a.high.cwiseMax(b.high);
        return a;
      });
  box.low -= Vec3::Constant(radius);
  box.high += Vec3::Constant(radius);
  const auto inside = [&](const Vec3& p) {
    return finite(p) && (p.array() >= box.low.array()).all() && (p.array() <= box.high.array()).all();
  };
  FluidBinGrid grid;
  grid.cell_size = fluid_search_cell_size(std::max(radius, cell_radius));
  if (box.low[0] <= box.high[0]) {
    // Cells at least half a radius wide; wider if a stray particle would make the grid much larger than the
    // particle count (the lists are sorted, so the cell size changes no result).
    const double cell_limit = std::max(1.0e6, 8.0 * static_cast<double>(count));
    auto cell_count = [&](double size) {
      double total = 1.0;
      for (int axis = 0; axis < 3; ++axis)
        total *= std::floor((box.high[axis] - anchor[axis]) / size) - std::floor((box.low[axis] - anchor[axis]) / size) + 1.0;
      return total;
    };
    while (cell_count(grid.cell_size) > cell_limit) grid.cell_size *= 2.0;
    for (int axis = 0; axis < 3; ++axis) {
      const double first = std::floor((box.low[axis] - anchor[axis]) / grid.cell_size);
      const double last = std::floor((box.high[axis] - anchor[axis]) / grid.cell_size);
      grid.origin[axis] = anchor[axis] + first * grid.cell_size;
      grid.cells[static_cast<std::size_t>(axis)] = static_cast<std::int64_t>(last - first) + 1;
    }
  }
  grid.inverse_cell_size = 1.0 / grid.cell_size;
  const std::size_t cell_total = static_cast<std::size_t>(grid.cells[0] * grid.cells[1] * grid.cells[2]);
  std::vector<std::uint32_t> cell_of(count, std::numeric_limits<std::uint32_t>::max());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i)
      if (inside(positions[i]))
        cell_of[i] = static_cast<std::uint32_t>(grid.linear(grid.axis_cell(positions[i][0], 0),
                                                            grid.axis_cell(positions[i][1], 1),
                                                            grid.axis_cell(positions[i][2], 2)));
  });
  grid.cell_start.assign(cell_total + 1, 0);
  for (std::size_t i = 0; i < count; ++i)
    if (cell_of[i] != std::numeric_limits<std::uint32_t>::max()) ++grid.cell_start[cell_of[i] + 1];
  for (std::size_t cell = 0; cell < cell_total; ++cell) grid.cell_start[cell + 1] += grid.cell_start[cell];
  grid.members.resize(grid.cell_start[cell_total]);
  for (std::vector<double>& axis : grid.member_coordinates) axis.resize(grid.members.size());
  std::vector<std::uint32_t> fill(grid.cell_start.begin(), grid.cell_start.end() - 1);
  for (std::size_t i = 0; i < count; ++i)
    if (cell_of[i] != std::numeric_limits<std::uint32_t>::max()) {
      const std::uint32_t k = fill[cell_of[i]]++;
      grid.members[k] = static_cast<std::uint32_t>(i);
      for (int axis = 0; axis < 3; ++axis) grid.member_coordinates[axis][k] = positions[i][axis];
    }
  return grid;
}

/// The candidates of one query: the (z, y) rows of cells that its sphere reaches, each row one contiguous run of the
/// grid's members, cut to the cells the sphere's chord spans (cells are at least radius / 2 wide, so 5 x 5 rows, 7 x 7
/// at most where rounding puts a bound just across a cell face).
struct CandidateRuns {
  struct Run {
    std::uint32_t first, last;
  };
  std::array<Run, 49> runs;
  std::size_t count = 0;
  std::size_t candidates = 0;
};

CandidateRuns candidate_runs(const Vec3& position, const FluidBinGrid& grid, double radius) {
  CandidateRuns result;
  if (!finite(position)) return result;
  const double squared_radius = radius * radius;
  const double cell = grid.cell_size;
  const std::int64_t z_low = grid.axis_cell(position[2] - radius, 2), z_high = grid.axis_cell(position[2] + radius, 2);
  const std::int64_t y_low = grid.axis_cell(position[1] - radius, 1), y_high = grid.axis_cell(position[1] + radius, 1);
  const std::int64_t x_low = grid.axis_cell(position[0] - radius, 0), x_high = grid.axis_cell(position[0] + radius, 0);
  // Distance from the query to the nearest point of cell index c along an axis (0 inside it).
  const auto gap = [&](std::int64_t c, int axis) {
    const double lower = grid.origin[axis] + static_cast<double>(c) * cell;
    return std::max({0.0, lower - position[axis], position[axis] - (lower + cell)});
  };
  // A row of cells (y, z) is cut to the cells its chord of the sphere reaches: those below the query's cell whose
  // squared gap is below the rest of the squared radius, those above it up to it (the cells that contain x -/+ the
  // half chord). Cells are at least radius / 2 wide, so the sphere reaches two cells to either side of the query's
  // own along an axis (three where rounding puts x -/+ radius just across a cell face); the squared gaps are computed
  // once per query (infinite off the grid), and a row's cut is two counts, without a square root, a floor or a
  // branch.
  constexpr std::int64_t kReach = 3;
  constexpr double kOff = std::numeric_limits<double>::infinity();
  const std::int64_t x_centre = std::clamp(grid.axis_cell(position[0], 0), x_low, x_high);
  std::array<double, 2 * kReach + 1> x_gap_squared;  // cells x_centre - kReach .. x_centre + kReach
  for (std::int64_t offset = -kReach; offset <= kReach; ++offset) {
    const std::int64_t x = x_centre + offset;
    const double g = gap(x, 0);
    x_gap_squared[static_cast<std::size_t>(offset + kReach)] = x < x_low || x > x_high ? kOff : g * g;
  }
  std::array<double, 2 * kReach + 1> y_gap_squared;
  for (std::int64_t y = y_low; y <= y_high; ++y) {
    const double g = gap(y, 1);
    y_gap_squared[static_cast<std::size_t>(y - y_low)] = g * g;
  }
  for (std::int64_t z = z_low; z <= z_high; ++z) {
    const double dz = gap(z, 2);
    const double rest_z = squared_radius - dz * dz;
    for (std::int64_t y = y_low; y <= y_high; ++y) {
      const double rest = rest_z - y_gap_squared[static_cast<std::size_t>(y - y_low)];
      if (rest < 0.0) continue;  // the sphere misses this row of cells
      std::int64_t first_x = x_centre, last_x = x_centre;
      for (std::int64_t step = 1; step <= kReach; ++step) {
        first_x -= x_gap_squared[static_cast<std::size_t>(kReach - step)] < rest ? 1 : 0;
        last_x += x_gap_squared[static_cast<std::size_t>(kReach + step)] <= rest ? 1 : 0;
      }
      const std::uint32_t first = grid.cell_start[grid.linear(first_x, y, z)];
      const std::uint32_t last = grid.cell_start[grid.linear(last_x, y, z) + 1];
      result.runs[result.count++] = {first, last};
      result.candidates += last - first;
    }
  }
  return result;
}

/// Writes every j != i within `radius` of particle i (at `position`) among `runs`, in cell order, to `queries`
/// (j < query_count, which build_fluid_neighbours keeps below 2^32) or `others` (each with room for all candidates
/// plus kGatherSlack); returns how many went to each. About half the candidates are kept, at random to a branch
/// predictor, so each candidate is written to both and the ends advance by the test's outcome instead of branching. The squared distance is summed as
/// (dx^2 + dy^2) + dz^2 in every version (no FMA: this file is compiled with -ffp-contract=off), so the AVX2 and
/// AVX-512 ones keep exactly the pairs the portable one keeps.
constexpr std::size_t kGatherSlack = 8;

std::pair<std::size_t, std::size_t> gather_neighbours_portable(const CandidateRuns& runs, const FluidBinGrid& grid,
                                                               double radius, std::size_t i, const Vec3& position,
                                                               std::size_t query_count, std::uint32_t* queries,
                                                               std::uint32_t* others) {
  const double squared_radius = radius * radius;
  const std::uint32_t self = static_cast<std::uint32_t>(i);
  const double* xs = grid.member_coordinates[0].data();
  const double* ys = grid.member_coordinates[1].data();
  const double* zs = grid.member_coordinates[2].data();
  std::size_t query_end = 0, other_end = 0;
  for (std::size_t r = 0; r < runs.count; ++r)
    for (std::size_t k = runs.runs[r].first; k < runs.runs[r].last; ++k) {
      const std::uint32_t j = grid.members[k];
      const double dx = xs[k] - position[0], dy = ys[k] - position[1], dz = zs[k] - position[2];
      const bool near = (dx * dx + dy * dy) + dz * dz < squared_radius && j != self;
      const bool query = j < query_count;
      queries[query_end] = j;
      others[other_end] = j;
      query_end += near & query;
      other_end += near & !query;
    }
  return {query_end, other_end};
}

#if defined(__GNUC__) && defined(__x86_64__)
#define RIFFLE_SEARCH_SIMD 1
/// The same test, 8 candidates at a time: masked loads cover a run's tail (runs hold 5-15 candidates), and the kept
/// slots are compressed into place, 8 written and the end advanced by the count kept.
__attribute__((target("avx512f,avx512vl,avx512bw,popcnt"))) std::pair<std::size_t, std::size_t>
gather_neighbours_avx512(const CandidateRuns& runs, const FluidBinGrid& grid, double radius, std::size_t i,
                         const Vec3& position, std::size_t query_count, std::uint32_t* queries,
                         std::uint32_t* others) {
  const __m512d squared_radius = _mm512_set1_pd(radius * radius);
  const __m512d px = _mm512_set1_pd(position[0]), py = _mm512_set1_pd(position[1]), pz = _mm512_set1_pd(position[2]);
  const __m256i self = _mm256_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(i)));
  const __m256i query_limit = _mm256_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(query_count)));
  const double* xs = grid.member_coordinates[0].data();
  const double* ys = grid.member_coordinates[1].data();
  const double* zs = grid.member_coordinates[2].data();
  const std::uint32_t* members = grid.members.data();
  std::size_t query_end = 0, other_end = 0;
  for (std::size_t r = 0; r < runs.count; ++r)
    for (std::size_t k = runs.runs[r].first; k < runs.runs[r].last; k += 8) {
      const std::size_t left = runs.runs[r].last - k;
      const __mmask8 lanes = left >= 8 ? __mmask8(0xFF) : static_cast<__mmask8>((1u << left) - 1u);
      const __m256i j = _mm256_maskz_loadu_epi32(lanes, members + k);
      const __m512d dx = _mm512_sub_pd(_mm512_maskz_loadu_pd(lanes, xs + k), px);
      const __m512d dy = _mm512_sub_pd(_mm512_maskz_loadu_pd(lanes, ys + k), py);
      const __m512d dz = _mm512_sub_pd(_mm512_maskz_loadu_pd(lanes, zs + k), pz);
      const __m512d squared =
          _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)), _mm512_mul_pd(dz, dz));
      const __mmask8 near = _mm512_mask_cmp_pd_mask(lanes, squared, squared_radius, _CMP_LT_OQ) &
                            _mm256_cmpneq_epu32_mask(j, self);
      const __mmask8 query = _mm256_cmplt_epu32_mask(j, query_limit);
      const __mmask8 near_query = near & query, near_other = near & static_cast<__mmask8>(~query);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(queries + query_end), _mm256_maskz_compress_epi32(near_query, j));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(others + other_end), _mm256_maskz_compress_epi32(near_other, j));
      query_end += static_cast<std::size_t>(__builtin_popcount(near_query));
      other_end += static_cast<std::size_t>(__builtin_popcount(near_other));
    }
  return {query_end, other_end};
}

/// The same test, 4 candidates at a time, for CPUs without AVX-512: the kept slots are compressed by a byte shuffle
/// from a table indexed by the 4-bit mask.
struct CompressTable {
  std::array<std::array<std::uint8_t, 16>, 16> shuffles{};
  constexpr CompressTable() {
    for (std::size_t mask = 0; mask < 16; ++mask) {
      std::size_t out = 0;
      for (std::size_t lane = 0; lane < 4; ++lane)
        if (mask & (std::size_t{1} << lane)) {
          for (std::size_t byte = 0; byte < 4; ++byte) shuffles[mask][4 * out + byte] = static_cast<std::uint8_t>(4 * lane + byte);
          ++out;
        }
      for (std::size_t byte = 4 * out; byte < 16; ++byte) shuffles[mask][byte] = 0x80;  // zero the rest
    }
  }
};
constexpr CompressTable kCompress4;

__attribute__((target("avx2,popcnt"))) std::pair<std::size_t, std::size_t> gather_neighbours_avx2(
    const CandidateRuns& runs, const FluidBinGrid& grid, double radius, std::size_t i, const Vec3& position,
    std::size_t query_count, std::uint32_t* queries, std::uint32_t* others) {
  const __m256d squared_radius = _mm256_set1_pd(radius * radius);
  const __m256d px = _mm256_set1_pd(position[0]), py = _mm256_set1_pd(position[1]), pz = _mm256_set1_pd(position[2]);
  const __m128i sign = _mm_set1_epi32(static_cast<int>(0x80000000u));
  const __m128i self = _mm_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(i)));
  // Unsigned j < query_count as a signed comparison of both with the sign bit flipped.
  const __m128i query_limit = _mm_xor_si128(_mm_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(query_count))), sign);
  const __m128i lane_index = _mm_setr_epi32(0, 1, 2, 3);
  const double* xs = grid.member_coordinates[0].data();
  const double* ys = grid.member_coordinates[1].data();
  const double* zs = grid.member_coordinates[2].data();
  const std::uint32_t* members = grid.members.data();
  std::size_t query_end = 0, other_end = 0;
  for (std::size_t r = 0; r < runs.count; ++r)
    for (std::size_t k = runs.runs[r].first; k < runs.runs[r].last; k += 4) {
      const std::size_t left = std::min<std::size_t>(runs.runs[r].last - k, 4);
      const __m128i lanes = _mm_cmplt_epi32(lane_index, _mm_set1_epi32(static_cast<int>(left)));
      const __m256i wide_lanes = _mm256_cvtepi32_epi64(lanes);
      const __m128i j = _mm_maskload_epi32(reinterpret_cast<const int*>(members + k), lanes);
      const __m256d dx = _mm256_sub_pd(_mm256_maskload_pd(xs + k, wide_lanes), px);
      const __m256d dy = _mm256_sub_pd(_mm256_maskload_pd(ys + k, wide_lanes), py);
      const __m256d dz = _mm256_sub_pd(_mm256_maskload_pd(zs + k, wide_lanes), pz);
      const __m256d squared =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
      const int within = _mm256_movemask_pd(_mm256_cmp_pd(squared, squared_radius, _CMP_LT_OQ));
      const int is_self = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(j, self)));
      const int query = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmplt_epi32(_mm_xor_si128(j, sign), query_limit)));
      const int near = within & ~is_self & ((1 << left) - 1);
      const int near_query = near & query, near_other = near & ~query;
      _mm_storeu_si128(reinterpret_cast<__m128i*>(queries + query_end),
                       _mm_shuffle_epi8(j, _mm_loadu_si128(reinterpret_cast<const __m128i*>(
                                               kCompress4.shuffles[static_cast<std::size_t>(near_query)].data()))));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(others + other_end),
                       _mm_shuffle_epi8(j, _mm_loadu_si128(reinterpret_cast<const __m128i*>(
                                               kCompress4.shuffles[static_cast<std::size_t>(near_other)].data()))));
      query_end += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(near_query)));
      other_end += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(near_other)));
    }
  return {query_end, other_end};
}
#endif

using GatherNeighbours = std::pair<std::size_t, std::size_t> (*)(const CandidateRuns&, const FluidBinGrid&, double,
                                                                 std::size_t, const Vec3&, std::size_t,
                                                                 std::uint32_t*, std::uint32_t*);

GatherNeighbours pick_gather_neighbours() {
  switch (fluid_search_simd()) {
#ifdef RIFFLE_SEARCH_SIMD
    case FluidSearchSimd::kAvx512: return gather_neighbours_avx512;
    case FluidSearchSimd::kAvx2: return gather_neighbours_avx2;
#endif
    default: return gather_neighbours_portable;
  }
}

/// Sorts a short list that is nearly ascending already (the particles are kept in cell order, see FluidCellSort):
/// insertion sort costs one comparison per entry plus one move per inversion.
void sort_nearly_sorted(std::uint32_t* first, std::uint32_t* last) {
  for (std::uint32_t* next = first + (first == last ? 0 : 1); next < last; ++next) {
    const std::uint32_t value = *next;
    std::uint32_t* hole = next;
    while (hole > first && *(hole - 1) > value) {
      *hole = *(hole - 1);
      --hole;
    }
    *hole = value;
  }
}

}  // namespace

void build_fluid_neighbours(const std::vector<Vec3>& positions, double radius, FluidNeighbours& neighbours,
                            std::size_t query_count, const Vec3& grid_anchor, double cell_radius) {
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw std::invalid_argument("build_fluid_neighbours: the search radius must be positive and finite");
  if (positions.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("build_fluid_neighbours: too many particles for 32-bit slots");
  const std::size_t count = std::min(query_count, positions.size());
  const FluidBinGrid grid = build_grid(positions, radius, count, grid_anchor, cell_radius);

  // One scan per query into per-chunk buffers (each list sorted there), then a prefix sum and a copy: each task
  // writes only its own chunk, and the sorted lists do not depend on the chunking or the thread count. Queries
  // (slots below `count`) and the rest are gathered apart: each part comes out of the scan nearly ascending when
  // the particles are in cell order, and all queries precede the rest.
  const std::size_t chunks = (count + kFluidSearchChunk - 1) / kFluidSearchChunk;
  const GatherNeighbours gather_neighbours = pick_gather_neighbours();
  std::vector<std::vector<std::uint32_t>> chunk_lists(chunks);
  neighbours.offsets.assign(count + 1, 0);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t chunk) {
    std::vector<std::uint32_t>& list = chunk_lists[chunk];
    std::vector<std::uint32_t> others;
    const std::size_t last = std::min(count, (chunk + 1) * kFluidSearchChunk);
    list.resize((last - chunk * kFluidSearchChunk) * 128);
    std::size_t list_end = 0;
    for (std::size_t i = chunk * kFluidSearchChunk; i < last; ++i) {
      const CandidateRuns runs = candidate_runs(positions[i], grid, radius);
      const std::size_t room = runs.candidates + kGatherSlack;
      if (list.size() < list_end + room) list.resize(2 * (list_end + room));
      if (others.size() < room) others.resize(room);
      std::uint32_t* first = list.data() + list_end;
      const auto [query_neighbours, other_neighbours] =
          gather_neighbours(runs, grid, radius, i, positions[i], count, first, others.data());
      std::copy_n(others.begin(), other_neighbours, first + query_neighbours);
      sort_nearly_sorted(first, first + query_neighbours);
      sort_nearly_sorted(first + query_neighbours, first + query_neighbours + other_neighbours);
      list_end += query_neighbours + other_neighbours;
      neighbours.offsets[i + 1] = static_cast<std::uint32_t>(query_neighbours + other_neighbours);
    }
    list.resize(list_end);
  });
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < count; ++i) {
    total += neighbours.offsets[i + 1];
    if (total >= std::numeric_limits<std::uint32_t>::max())
      throw std::length_error("build_fluid_neighbours: too many neighbour entries for 32-bit offsets");
    neighbours.offsets[i + 1] = static_cast<std::uint32_t>(total);
  }
  neighbours.slots.resize(total);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t chunk) {
    std::copy(chunk_lists[chunk].begin(), chunk_lists[chunk].end(),
              neighbours.slots.begin() + neighbours.offsets[chunk * kFluidSearchChunk]);
  });
  neighbours.radius = radius;
  ++neighbours.builds;
}

void FluidNeighbourSearch::exchange_ghosts(const ParticleState& particles, const std::vector<Vec3>& positions,
                                           FluidNeighbours& neighbours) const {
  const Halo& halo = neighbours.halo;
  halo_copy_positions(halo, positions,
                      at_ == Positions::kCurrent ? neighbours.ghosts.position : neighbours.ghosts.predicted_position);
  halo_copy(halo, particles.velocity, neighbours.ghosts.velocity);
  halo_copy(halo, particles.kind, neighbours.ghosts.kind);
}

bool FluidNeighbourSearch::lists_still_valid(const std::vector<Vec3>& positions, std::size_t queries,
                                             const FluidNeighbours& neighbours, double effective_radius,
                                             const Vec3& tank_displacement) {
  // Every pair within r_e now was within r_e + skin at the build if the two largest moves since (in the tank's
  // frame) add up to no more than the skin (systems/physics/geometry/verlet_skin.hpp); over ranks, twice the largest.
  const double built_skin = neighbours.radius - effective_radius;
  if (!(built_skin >= 0.0 && neighbours.built_positions.size() == positions.size() &&
        neighbours.particle_count() == queries))
    return false;
  const LargestMoves moves = largest_moves(positions, neighbours.built_positions,
                                           tank_displacement - neighbours.built_tank_displacement);
  return skin_holds(moves, built_skin, neighbours.ranks.active);
}

void FluidNeighbourSearch::exchange_rank_ghosts(const ParticleState& particles, const std::vector<Vec3>& positions,
                                                FluidNeighbours& neighbours) const {
  FluidGhosts& ghosts = neighbours.ghosts;
  exchange_fluid_ghost_positions(positions, neighbours.ranks,
                                 at_ == Positions::kCurrent ? ghosts.position : ghosts.predicted_position);
  exchange_fluid_ghost_field(particles.velocity, neighbours.ranks, ghosts.velocity);
}

void FluidNeighbourSearch::build_rank_ghosts(const ParticleState& particles, const std::vector<Vec3>& positions,
                                             double radius, FluidNeighbours& neighbours) const {
  const double overflow = fluid_box_overflow(positions, neighbours.ranks);
  FluidGhosts built;
  build_fluid_rank_ghosts(particles, positions, radius + overflow, box_, neighbours.ranks, built);
  FluidGhosts& ghosts = neighbours.ghosts;
  (at_ == Positions::kCurrent ? ghosts.position : ghosts.predicted_position) = std::move(built.position);
  ghosts.velocity = std::move(built.velocity);
  ghosts.kind = std::move(built.kind);
}

void FluidNeighbourSearch::run(SystemContext& context) {
  const ParticleState& particles = context.read<ParticleState>();
  const ParticlePrediction& prediction = context.read<ParticlePrediction>();
  FluidNeighbours& neighbours = context.write<FluidNeighbours>();
  const std::vector<Vec3>& positions = at_ == Positions::kCurrent ? particles.position : prediction.predicted_position;
  const bool over_ranks = neighbours.ranks.active;
  const bool periodic = box_.any() && !over_ranks;  // over ranks the images across the faces are rank ghosts
  const std::size_t queries = fluid_slot_count(particles);
  // Displacements are measured in the tank's frame: pair distances do not change under a common translation, and
  // the walls, which ride with the tank, then never use up the skin (otherwise the tank alone forces a rebuild
  // every few steps).
  const double time = at_ == Positions::kCurrent ? context.time : context.time + context.dt;
  const Vec3 tank_displacement = tank_kinematics(context.model.tank.motion, time).displacement;
  const double built_skin = neighbours.radius - effective_radius_;
  bool valid = lists_still_valid(positions, queries, neighbours, effective_radius_, tank_displacement);
  // Over ranks the ghosts are built together: every rank rebuilds when any must.
  bool keep = valid && !neighbours.reordered;
  if (over_ranks) keep = !ranks::any(!keep);
  if (keep) {
    if (over_ranks) exchange_rank_ghosts(particles, positions, neighbours);
    else if (periodic) exchange_ghosts(particles, positions, neighbours);
    return;
  }
  if (over_ranks) valid = !ranks::any(!valid);  // the same skin on every rank
  context.count_items(positions.size());
  // A rebuild forced only by a reordering (FluidCellSort) says nothing about the flow: it keeps the last skin.
  const bool reordered_only = valid && neighbours.builds > 0;
  const bool lasted_one_step = neighbours.builds > 0 && context.step() <= neighbours.built_step + 1;
  const double skin =
      reordered_only ? std::clamp(built_skin, narrow_skin_, skin_) : lasted_one_step ? narrow_skin_ : skin_;
  // The grid rides with the tank, on the lattice (cells of the wide skin's radius) FluidCellSort orders the
  // particles by.
  const Vec3 grid_anchor = context.model.tank.origin + tank_displacement;
  if (!periodic && !over_ranks) {
    build_fluid_neighbours(positions, effective_radius_ + skin, neighbours, queries, grid_anchor,
                           effective_radius_ + skin_);
  } else {
    // The reals and their ghosts (ascending lists: reals, then ghosts). The positions are not wrapped here, so that
    // when a rebuild happens changes no result (a resumed run rebuilds at its first step): fluid_correct wraps r^k
    // at every step, and r* lies at most a step's travel beyond a face, where image_shifts still gives the one
    // image that comes back into the box.
    if (over_ranks) {
      build_rank_ghosts(particles, positions, effective_radius_ + skin, neighbours);
    } else {
      // r* may lie up to a step's travel past a face (wrapped at the correction): the halo reaches that much further.
      build_halo(positions, particles.id, box_, effective_radius_ + skin + periodic_overshoot(positions, box_),
                 neighbours.halo);
      exchange_ghosts(particles, positions, neighbours);
    }
    const std::vector<Vec3>& ghost_positions =
        at_ == Positions::kCurrent ? neighbours.ghosts.position : neighbours.ghosts.predicted_position;
    std::vector<Vec3> all = positions;
    all.insert(all.end(), ghost_positions.begin(), ghost_positions.end());
    build_fluid_neighbours(all, effective_radius_ + skin, neighbours, queries, grid_anchor, effective_radius_ + skin_);
  }
  neighbours.built_step = context.step();
  neighbours.built_positions = positions;
  neighbours.reordered = false;
  neighbours.built_tank_displacement = tank_displacement;
}

}  // namespace riffle
