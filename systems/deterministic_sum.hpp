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

inline constexpr std::size_t kDeterministicSumBlock = 512;  // enough blocks to balance two threads over ~10^4 terms

/// Sum of term(i) over [0, count), identical for any thread count: fixed blocks summed in order.
template <class Term>
double deterministic_sum(std::size_t count, Term&& term) {
  constexpr std::size_t kBlock = kDeterministicSumBlock;
  const std::size_t blocks = (count + kBlock - 1) / kBlock;
  std::vector<double> partial(blocks, 0.0);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t block) {
    double sum = 0.0;
    const std::size_t end = std::min(count, (block + 1) * kBlock);
    for (std::size_t i = block * kBlock; i < end; ++i) sum += term(i);
    partial[block] = sum;
  });
  double total = 0.0;
  for (double value : partial) total += value;
  return total;
}

/// Several sums in one pass: terms(i) returns std::array<double, N>; each component is summed exactly as
/// deterministic_sum would sum it alone.
template <std::size_t N, class Terms>
std::array<double, N> deterministic_sums(std::size_t count, Terms&& terms) {
  constexpr std::size_t kBlock = kDeterministicSumBlock;
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

}  // namespace riffle
