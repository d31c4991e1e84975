#pragma once
// Parallel sums whose result does not depend on the thread count: the terms are summed in fixed blocks, and the
// blocks' partial sums in order. Every reduction of the fluid and of the pressure solve goes through it, so that runs
// on one and two threads, and resumed runs, give byte-identical states.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace riffle {

/// Sums of terms(i) over [0, count), terms(i) returning std::array<double, N>, identical for any thread count: each
/// component is summed in fixed blocks of the terms, and the blocks' partial sums in order.
template <std::size_t N, class Terms>
std::array<double, N> deterministic_sums(std::size_t count, Terms&& terms) {
  constexpr std::size_t kBlock = 512;  // enough blocks to balance two threads over ~10^4 terms
  const std::size_t blocks = (count + kBlock - 1) / kBlock;
  std::vector<std::array<double, N>> partial(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t block) {
    std::array<double, N> sum{};
    const std::size_t end = std::min(count, (block + 1) * kBlock);
    for (std::size_t i = block * kBlock; i < end; ++i) {
      const std::array<double, N> term = terms(i);
      for (std::size_t n = 0; n < N; ++n) sum[n] += term[n];
    }
    partial[block] = sum;
  });
  std::array<double, N> total{};
  for (const auto& value : partial)
    for (std::size_t n = 0; n < N; ++n) total[n] += value[n];
  return total;
}

/// Sum of term(i) over [0, count), identical for any thread count: fixed blocks summed in order.
template <class Term>
double deterministic_sum(std::size_t count, Term&& term) {
  return deterministic_sums<1>(count, [&](std::size_t i) { return std::array<double, 1>{term(i)}; })[0];
}

}  // namespace riffle
