// Small parallel helpers of the step loop whose answers do not depend on the thread count.
#pragma once

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <limits>
#include <vector>

#include "vec3.h"

namespace mf {

constexpr size_t kGrain = 1024;

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Smallest i < n with pred(i), or -1: the same answer on any thread count.
template <class F>
int64_t firstIndexWhere(size_t n, F&& pred) {
  const int64_t none = std::numeric_limits<int64_t>::max();
  const int64_t first = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, kGrain), none,
      [&](const tbb::blocked_range<size_t>& r, int64_t best) {
        for (size_t i = r.begin(); i != r.end() && int64_t(i) < best; ++i)
          if (pred(i)) return int64_t(i);
        return best;
      },
      [](int64_t a, int64_t b) { return std::min(a, b); });
  return first == none ? -1 : first;
}

template <class F>
Real parallelMax(size_t n, F&& value) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, kGrain), Real(0),
      [&](const tbb::blocked_range<size_t>& r, Real m) {
        for (size_t i = r.begin(); i != r.end(); ++i) m = std::max(m, value(i));
        return m;
      },
      [](Real a, Real b) { return std::max(a, b); });
}

/// Sum of f(i) for i < n in blocks of kGrain, added in block order: the same bits on any thread
/// count (a parallel_reduce would add in the order the threads happen to finish).
template <class F>
Real blockSum(size_t n, F&& f) {
  std::vector<Real> partial((n + kGrain - 1) / kGrain, 0);
  tbb::parallel_for(size_t(0), partial.size(), [&](size_t b) {
    Real s = 0;
    for (size_t i = b * kGrain, e = std::min(n, (b + 1) * kGrain); i < e; ++i) s += f(i);
    partial[b] = s;
  });
  Real total = 0;
  for (Real s : partial) total += s;
  return total;
}

}  // namespace mf
