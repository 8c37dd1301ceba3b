// The benches' image error (render_noise_bench, cycles_bench): relative RMSE against a reference,
//   sqrt(mean over pixels and channels of (x - r)^2 / (r^2 + 0.01)),
// which weights dark pixels without dividing by zero.
#pragma once

#include <cmath>
#include <stdexcept>
#include <vector>

#include "render/image.h"

namespace mf::bench {

/// One channel's term: (x - r)^2 / (r^2 + 0.01).
inline double relSquaredError(float x, float r) {
  const double d = double(x) - r;
  return d * d / (double(r) * r + 0.01);
}

inline double relRmse(const render::Image& x, const render::Image& r) {
  if (x.width != r.width || x.height != r.height) throw std::runtime_error("images of different sizes");
  double sum = 0;
  for (size_t i = 0; i < r.rgb.size(); ++i) sum += relSquaredError(x.rgb[i], r.rgb[i]);
  return std::sqrt(sum / double(r.rgb.size()));
}

/// The terms summed per pixel over its channels: where the error is.
inline std::vector<double> relSquaredErrorPerPixel(const render::Image& x, const render::Image& r) {
  if (x.width != r.width || x.height != r.height) throw std::runtime_error("images of different sizes");
  std::vector<double> e(r.rgb.size() / 3, 0.0);
  for (size_t i = 0; i < r.rgb.size(); ++i) e[i / 3] += relSquaredError(x.rgb[i], r.rgb[i]);
  return e;
}

}  // namespace mf::bench
