// The path tracer's sample generator: Owen-scrambled Sobol points, padded by dimension pairs
// (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)). Each pixel sample k is the
// k-th point of a (0,2)-sequence in every pair of dimensions; a pair's points are Owen-scrambled
// (nested uniform scrambling, Laine-Karras hash) and their order shuffled by a seed of its own,
// so that pairs are independent of each other and of other pixels, while within a pair any
// prefix of 2^m samples is stratified in every elementary interval.
//
// A path takes dimension pairs in the order it draws them (next1D, next2D), as pbrt's samplers
// do. Everything is a pure function of (pixel seed, sample index, dimension): the same bits on
// any thread count.
#pragma once

#include <cstdint>

namespace mf::render {

class Sampler {
 public:
  static constexpr uint32_t kCameraPairs = 1;  // pair 0: the pixel position
  static constexpr uint32_t kTimePair = 0xFFFF;  // the shutter time (motion blur), apart from the path's pairs

  /// `seed`: the pixel's (see pixelSeed); `index`: the sample within the pixel. `random`:
  /// independent hashed values instead (for comparison: render.sobol = false).
  Sampler(uint64_t seed, uint32_t index, bool random = false) : random_(random), seed_(seed), index_(index) {}

  static uint64_t pixelSeed(uint64_t x, uint64_t y, uint64_t frame) {
    return mix(mix(mix(0x5851F42D4C957F2Dull ^ frame) ^ y) ^ x);
  }

  void startBounce(int bounce) { bounce_ = uint32_t(bounce); }
  int bounce() const { return int(bounce_); }  // the path's bounce (for the roulette)

  /// A point of the pixel's sequence in [0, 1)^2, for dimension pair `pair`.
  void get2D(uint32_t pair, double& u, double& v) const {
    if (random_) {
      const uint64_t h = mix(mix(seed_ ^ (uint64_t(pair) << 32)) ^ index_);
      u = toUnit(uint32_t(h)), v = toUnit(uint32_t(h >> 32));
      return;
    }
    const uint32_t s = uint32_t(mix(seed_ ^ (uint64_t(pair) << 32)));
    const uint32_t i = nestedUniformScramble(index_, s);
    u = toUnit(nestedUniformScramble(sobol0(i), hash(s ^ 0xA511E9B3u)));
    v = toUnit(nestedUniformScramble(sobol1(i), hash(s ^ 0x63D83595u)));
  }
  /// One value in [0, 1): the first coordinate of the pair (a scrambled van der Corput point).
  double get1D(uint32_t pair) const {
    if (random_) {
      double u, v;
      get2D(pair, u, v);
      return u;
    }
    const uint32_t s = uint32_t(mix(seed_ ^ (uint64_t(pair) << 32)));
    return toUnit(nestedUniformScramble(sobol0(nestedUniformScramble(index_, s)), hash(s ^ 0xA511E9B3u)));
  }
  /// The path's next dimensions.
  void next2D(double& u, double& v) { get2D(next_++, u, v); }
  double next1D() { return get1D(next_++); }

 private:
  static uint64_t mix(uint64_t x) {  // splitmix64's finaliser
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
  }
  static uint32_t hash(uint32_t x) {  // a 32-bit integer hash (Wellons' lowbias32)
    x ^= x >> 16, x *= 0x7FEB352Du, x ^= x >> 15, x *= 0x846CA68Bu, x ^= x >> 16;
    return x;
  }
  static uint32_t reverse(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
  }
  static uint32_t laineKarras(uint32_t x, uint32_t seed) {  // Burley's improved constants
    x ^= x * 0x3D20ADEAu;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526C56u;
    x ^= x * 0x53A22864u;
    return x;
  }
  /// Owen scrambling: every bit flipped by a hash of the bits above it.
  static uint32_t nestedUniformScramble(uint32_t x, uint32_t seed) { return reverse(laineKarras(reverse(x), seed)); }
  static uint32_t sobol0(uint32_t i) { return reverse(i); }  // van der Corput
  static uint32_t sobol1(uint32_t i) {  // Sobol's second dimension: v_k = v_{k-1} ^ (v_{k-1} >> 1)
    uint32_t r = 0;
    for (uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1)
      if (i & 1) r ^= v;
    return r;
  }
  static double toUnit(uint32_t x) { return (x >> 8) * (1.0 / 16777216.0); }  // [0, 1), 24 bits

  bool random_;
  uint64_t seed_;
  uint32_t index_;
  uint32_t bounce_ = 0, next_ = kCameraPairs;
};

}  // namespace mf::render
