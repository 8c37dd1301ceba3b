// The benches' image error (render_noise_bench, cycles_bench): relative RMSE against a reference,
//   sqrt(mean over pixels and channels of (x - r)^2 / (r^2 + 0.01)),
// which weights dark pixels without dividing by zero.
#pragma once

#include <cmath>
#include <stdexcept>

#include "render/image.h"

namespace mf::bench {

inline double relRmse(const render::Image& x, const render::Image& r) {
  if (x.width != r.width || x.height != r.height) throw std::runtime_error("images of different sizes");
  double sum = 0;
  for (size_t i = 0; i < r.rgb.size(); ++i) {
    const double d = double(x.rgb[i]) - r.rgb[i];
    sum += d * d / (double(r.rgb[i]) * r.rgb[i] + 0.01);
  }
  return std::sqrt(sum / double(r.rgb.size()));
}

}  // namespace mf::bench
