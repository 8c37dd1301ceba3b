#include "adaptive_sampling.h"

#include <algorithm>
#include <cmath>

namespace mf::render {

namespace {

/// One sample's spread of luminance over sqrt(L^2 + 0.01): a pixel's noise as the bench's rel
/// RMSE weighs it.
double relativeSpread(const LuminanceMoments& m) {
  if (m.n < 2) return 0;
  const double mean = m.sum / m.n;
  return std::sqrt(m.varianceOfMean() * m.n / (mean * mean + 0.01));
}

}  // namespace

void allocateSamples(const std::vector<LuminanceMoments>& moments, const std::vector<uint64_t>& rays, int width, int height,
                     int samples, int cap, std::vector<int>& end) {
  const size_t pixels = moments.size();
  std::vector<double> noise(pixels), weight(pixels), cost(pixels);
  double used = 0, budget = 0;
  for (size_t p = 0; p < pixels; ++p) {
    cost[p] = moments[p].n ? std::max(1.0, double(rays[p]) / moments[p].n) : 1.0;
    noise[p] = relativeSpread(moments[p]) / std::sqrt(cost[p]);
    used += double(rays[p]), budget += samples * cost[p];
  }
  double sum = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double w = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int u = std::clamp(x + dx, 0, width - 1), v = std::clamp(y + dy, 0, height - 1);
          w = std::max(w, noise[size_t(v) * width + u]);
        }
      const size_t p = size_t(y) * width + x;
      weight[p] = w, sum += w * cost[p];
    }
  const double extra = std::max(0.0, budget - used);
  double carry = 0;
  for (size_t p = 0; p < pixels; ++p) {
    const double want = sum > 0 ? extra * weight[p] / sum : 0;
    const double exact = want + carry;
    const int have = int(moments[p].n), whole = int(std::floor(exact));
    // Only the rounding is carried on: what the cap holds back is not spent on the next pixel.
    carry = exact - whole;
    end[p] = have + std::min(whole, std::max(0, cap - have));
  }
}

}  // namespace mf::render
