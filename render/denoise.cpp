#include "denoise.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <cmath>
#include <stdexcept>

namespace mf::render {

namespace {

// Below this albedo a channel is not divided out: its light would be amplified noise.
constexpr float kAlbedoFloor = 0.02f;
// The B3 spline's taps (1, 4, 6, 4, 1) / 16, as Dammertz et al. use them.
constexpr float kKernel[3] = {3.0f / 8, 1.0f / 4, 1.0f / 16};

float luminance(const float* c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

/// x^power, by squaring where the power is a whole number (SVGF's 128: seven multiplications).
float powerOf(float x, float power) {
  if (power == std::floor(power) && power >= 0 && power <= 1024) {
    float r = 1;
    for (unsigned e = unsigned(power); e; e >>= 1, x *= x)
      if (e & 1) r *= x;
    return r;
  }
  return std::pow(x, power);
}

/// The depth's screen-space change per pixel along one axis: the smaller of the two one-sided
/// differences, so that a pixel next to a silhouette does not take the jump for its slope.
float depthSlope(float zl, float z, float zr) {
  float best = std::numeric_limits<float>::infinity();
  if (std::isfinite(zl)) best = std::min(best, std::abs(z - zl));
  if (std::isfinite(zr)) best = std::min(best, std::abs(zr - z));
  return std::isfinite(best) ? best : 0.0f;
}

/// The variance blurred by a 3x3 binomial kernel (SVGF: a steadier estimate of the
/// luminance's standard deviation than the pixel's own few samples give).
std::vector<float> blurVariance(const std::vector<float>& var, int w, int h) {
  std::vector<float> out(var.size());
  const float k[3] = {0.25f, 0.5f, 0.25f};
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < w; ++x) {
        float sum = 0, wsum = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = x + dx, qy = y + dy;
            if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
            const float kw = k[dx + 1] * k[dy + 1];
            sum += kw * var[size_t(qy) * w + qx];
            wsum += kw;
          }
        out[size_t(y) * w + x] = sum / wsum;
      }
  });
  return out;
}

/// The guides' part of a tap's weight (Dammertz et al.; SVGF's normal and depth terms): 0
/// across sky and surface or differing depth, normal or albedo, 1 where they match.
struct Guides {
  int w = 0, h = 0;
  const std::vector<float>* albedo;  // the guide: the AOV, then its smoothed version
  const std::vector<float>& normal;
  const std::vector<float>& depth;
  std::vector<float> slopeX, slopeY;
  std::vector<uint8_t> sky;  // the pixel's samples all met the sky (normal 0)
  float normalPower, sigmaDepth, albedoScale;

  Guides(const Aovs& a, const DenoiseSettings& s)
      : w(a.width), h(a.height), albedo(&a.albedo), normal(a.normal), depth(a.depth), slopeX(a.pixels()), slopeY(a.pixels()),
        sky(a.pixels()), normalPower(s.normalPower), sigmaDepth(s.sigmaDepth),
        albedoScale(1 / (s.sigmaAlbedo * s.sigmaAlbedo)) {
    const float inf = std::numeric_limits<float>::infinity();
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t p = size_t(y) * w + x;
        slopeX[p] = depthSlope(x > 0 ? depth[p - 1] : inf, depth[p], x + 1 < w ? depth[p + 1] : inf);
        slopeY[p] = depthSlope(y > 0 ? depth[p - w] : inf, depth[p], y + 1 < h ? depth[p + w] : inf);
        sky[p] = normal[3 * p] == 0 && normal[3 * p + 1] == 0 && normal[3 * p + 2] == 0;
      }
  }

  /// The weight of q (offset ox, oy pixels from p) in p's sum, and the exponent of its
  /// exponential factors in `exponent` (the caller adds its own before taking exp); < 0: none.
  float weight(size_t p, size_t q, int ox, int oy, float& exponent) const {
    if (sky[p] != sky[q]) return -1;
    const float zp = depth[p], zq = depth[q];
    if (std::isfinite(zp) != std::isfinite(zq)) return -1;
    exponent = 0;
    if (std::isfinite(zp)) {  // SVGF: the difference against what the depth's slope predicts
      const float predicted = sigmaDepth * (slopeX[p] * std::abs(ox) + slopeY[p] * std::abs(oy));
      exponent += std::abs(zp - zq) / (predicted + 1e-3f * zp + 1e-6f);
    }
    const float* ap = &(*albedo)[3 * p];
    const float* aq = &(*albedo)[3 * q];
    const float da[3] = {ap[0] - aq[0], ap[1] - aq[1], ap[2] - aq[2]};
    exponent += (da[0] * da[0] + da[1] * da[1] + da[2] * da[2]) * albedoScale;
    if (sky[p]) return 1;
    const float* np = &normal[3 * p];
    const float* nq = &normal[3 * q];
    return powerOf(std::max(0.0f, np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2]), normalPower);
  }
};

/// The albedo guide: the AOV smoothed by two passes of the same guided kernel (steps 1 and 2).
/// At 8 spp the AOV of a texture finer than a pixel (the far checkers, what glass shows) is itself
/// noisy, and a noisy guide would stop the light's filter everywhere; an albedo step well above
/// sigma_albedo stops this kernel, so resolved texture edges stay. The light is multiplied again
/// by the pixel's own albedo, not this one: smoothing blurs texture steps below sigma_albedo.
std::vector<float> smoothAlbedo(const Guides& g) {
  std::vector<float> cur = *g.albedo, next(cur.size());
  for (int step = 1; step <= 2; step *= 2) {
    tbb::parallel_for(tbb::blocked_range<int>(0, g.h), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < g.w; ++x) {
          const size_t p = size_t(y) * g.w + x;
          float sumW = 0, sum[3] = {0, 0, 0};
          for (int dy = -2; dy <= 2; ++dy) {
            const int qy = y + dy * step;
            if (qy < 0 || qy >= g.h) continue;
            for (int dx = -2; dx <= 2; ++dx) {
              const int qx = x + dx * step;
              if (qx < 0 || qx >= g.w) continue;
              const size_t q = size_t(qy) * g.w + qx;
              float wq = kKernel[std::abs(dx)] * kKernel[std::abs(dy)], exponent = 0;
              if (q != p) {
                const float f = g.weight(p, q, dx * step, dy * step, exponent);
                if (f <= 0 || exponent > 30) continue;
                wq *= f * std::exp(-exponent);
              }
              for (int c = 0; c < 3; ++c) sum[c] += wq * cur[3 * q + c];
              sumW += wq;
            }
          }
          for (int c = 0; c < 3; ++c) next[3 * p + c] = sum[c] / sumW;
        }
    });
    cur.swap(next);
  }
  return cur;
}

}  // namespace

Image denoise(const Image& noisy, const Aovs& aovs, const DenoiseSettings& s) {
  const int w = noisy.width, h = noisy.height;
  if (aovs.width != w || aovs.height != h || aovs.albedo.size() != size_t(w) * h * 3 || aovs.variance.size() != size_t(w) * h)
    throw std::invalid_argument("denoise: the AOVs are not the image's size");
  if (aovs.albedoVariance.size() != size_t(w) * h) throw std::invalid_argument("denoise: the AOVs have no albedo variance");
  const size_t n = size_t(w) * h;
  const std::vector<float>& albedo = aovs.albedo;

  // Demodulate: light = colour / albedo per channel; the variance scaled by the same factor.
  std::vector<float> light(n * 3), var(n);
  for (size_t p = 0; p < n; ++p) {
    for (int c = 0; c < 3; ++c) {
      const float a = albedo[3 * p + c];
      light[3 * p + c] = a > kAlbedoFloor ? noisy.rgb[3 * p + c] / a : noisy.rgb[3 * p + c];
    }
    const float lc = luminance(&noisy.rgb[3 * p]), ll = luminance(&light[3 * p]);
    const float scale = lc > 1e-12f ? ll / lc : 1 / std::max(luminance(&albedo[3 * p]), kAlbedoFloor);
    var[p] = aovs.variance[p] * scale * scale;
  }
  Guides guides(aovs, s);
  const std::vector<float> smooth = smoothAlbedo(guides);
  guides.albedo = &smooth;
  std::vector<float> nextLight(n * 3), nextVar(n);
  for (int it = 0; it < s.iterations; ++it) {
    const int step = 1 << it;
    const std::vector<float> sd = blurVariance(var, w, h);
    std::vector<float> lum(n);
    for (size_t p = 0; p < n; ++p) lum[p] = luminance(&light[3 * p]);
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < w; ++x) {
          const size_t p = size_t(y) * w + x;
          const float lp = lum[p];
          const float lumScale = 1 / (s.sigmaLuminance * std::sqrt(std::max(sd[p], 0.0f)) + 1e-6f);
          float sumW = 0, sumV = 0, sum[3] = {0, 0, 0};
          for (int dy = -2; dy <= 2; ++dy) {
            const int qy = y + dy * step;
            if (qy < 0 || qy >= h) continue;
            for (int dx = -2; dx <= 2; ++dx) {
              const int qx = x + dx * step;
              if (qx < 0 || qx >= w) continue;
              const size_t q = size_t(qy) * w + qx;
              float wq = kKernel[std::abs(dx)] * kKernel[std::abs(dy)], exponent = 0;
              if (q != p) {
                const float f = guides.weight(p, q, dx * step, dy * step, exponent);
                if (f <= 0) continue;
                exponent += std::abs(lp - lum[q]) * lumScale;
                if (exponent > 30) continue;  // a weight below 1e-13: none
                wq *= f * std::exp(-exponent);
              }
              for (int c = 0; c < 3; ++c) sum[c] += wq * light[3 * q + c];
              sumW += wq;
              sumV += wq * wq * var[q];
            }
          }
          // sumW >= the centre tap's 9/64 > 0.
          for (int c = 0; c < 3; ++c) nextLight[3 * p + c] = sum[c] / sumW;
          nextVar[p] = sumV / (sumW * sumW);  // the variance of the weighted mean (SVGF eq. 3)
        }
    });
    light.swap(nextLight);
    var.swap(nextVar);
  }

  // Remodulate with the pixel's own albedo, the mean of its samples' as the colour is, where the
  // samples agree on it: a texture they resolved comes back as it was (the smoothed guide blurs
  // steps below sigma_albedo; on the noise bench's glass that was half of the denoised error).
  // Where they scatter (a glass wall's samples reflect or refract), the difference d from the
  // smoothed albedo is mostly that scatter: the variance of the pixel's mean, se^2, weighs the
  // two as a Wiener filter does, the pixel's own by |d|^2 / (|d|^2 + se^2). The sky (noise-free)
  // as it was.
  Image out(w, h);
  for (size_t p = 0; p < n; ++p) {
    const float* a = &albedo[3 * p];
    const float* sm = &smooth[3 * p];
    const float d2 = (a[0] - sm[0]) * (a[0] - sm[0]) + (a[1] - sm[1]) * (a[1] - sm[1]) + (a[2] - sm[2]) * (a[2] - sm[2]);
    const float se2 = aovs.albedoVariance[p];
    const float keep = d2 + se2 > 0 ? d2 / (d2 + se2) : 1.0f;
    for (int c = 0; c < 3; ++c) {
      const float remodulate = sm[c] + keep * (a[c] - sm[c]);
      out.rgb[3 * p + c] = guides.sky[p] ? noisy.rgb[3 * p + c] : a[c] > kAlbedoFloor ? light[3 * p + c] * remodulate : light[3 * p + c];
    }
  }
  return out;
}

}  // namespace mf::render
