#pragma once
// Parallel sums whose result does not depend on the thread count: the terms are summed in fixed blocks, and the
// blocks' partial sums in order. Every reduction of the fluid and of the pressure solve goes through it, so that runs
// on one and two threads, and resumed runs, give byte-identical states.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace riffle {

/// Sum of term(i) over [0, count), identical for any thread count: fixed blocks summed in order.
template <class Term>
double deterministic_sum(std::size_t count, Term&& term) {
  constexpr std::size_t kBlock = 512;  // enough blocks to balance two threads over ~10^4 terms
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

}  // namespace riffle
