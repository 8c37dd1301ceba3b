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
  Sampler(uint64_t seed, uint32_t index, bool random = false)
      : random_(random), seed_(seed), index_(index), reversedIndex_(reverse(index)) {}

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
    const uint32_t i = reverse(laineKarras(reversedIndex_, s));  // the sample's place in the pair's shuffled order
    // nestedUniformScramble(sobol0(i), .) = reverse(laineKarras(i, .)): the two reversals cancel.
    u = toUnit(reverse(laineKarras(i, hash(s ^ 0xA511E9B3u))));
    v = toUnit(reverse(laineKarras(reversedSobol1(i), hash(s ^ 0x63D83595u))));
  }
  /// One value in [0, 1): the first coordinate of the pair (a scrambled van der Corput point).
  double get1D(uint32_t pair) const {
    if (random_) {
      double u, v;
      get2D(pair, u, v);
      return u;
    }
    const uint32_t s = uint32_t(mix(seed_ ^ (uint64_t(pair) << 32)));
    return toUnit(reverse(laineKarras(reverse(laineKarras(reversedIndex_, s)), hash(s ^ 0xA511E9B3u))));
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
  /// Bit reversal by bytes: the tables of Tables() (1 KiB each) stay in the L1 cache.
  static uint32_t reverse(uint32_t x) {
    const uint32_t* r = tables().reverseByte;
    return (r[x & 0xFF] << 24) | (r[(x >> 8) & 0xFF] << 16) | (r[(x >> 16) & 0xFF] << 8) | r[x >> 24];
  }
  static uint32_t laineKarras(uint32_t x, uint32_t seed) {  // Burley's improved constants
    x ^= x * 0x3D20ADEAu;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526C56u;
    x ^= x * 0x53A22864u;
    return x;
  }
  /// Sobol's second dimension, bit-reversed: the XOR of reverse(v_k) over the set bits k of i
  /// (v_k = v_{k-1} ^ (v_{k-1} >> 1), v_0 = 2^31), a byte of i at a time.
  static uint32_t reversedSobol1(uint32_t i) {
    const uint32_t(*t)[256] = tables().sobol1;
    return t[0][i & 0xFF] ^ t[1][(i >> 8) & 0xFF] ^ t[2][(i >> 16) & 0xFF] ^ t[3][i >> 24];
  }
  struct Tables {
    uint32_t reverseByte[256];
    uint32_t sobol1[4][256];
    Tables() {
      for (uint32_t b = 0; b < 256; ++b) {
        uint32_t r = 0;
        for (int k = 0; k < 8; ++k) r |= ((b >> k) & 1u) << (7 - k);
        reverseByte[b] = r;
      }
      uint32_t column[32];  // reverse(v_k)
      for (uint32_t k = 0, v = 1u << 31; k < 32; ++k, v ^= v >> 1) {
        uint32_t r = 0;
        for (int bit = 0; bit < 32; ++bit) r |= ((v >> bit) & 1u) << (31 - bit);
        column[k] = r;
      }
      for (int byte = 0; byte < 4; ++byte)
        for (uint32_t b = 0; b < 256; ++b) {
          uint32_t x = 0;
          for (int k = 0; k < 8; ++k)
            if (b >> k & 1u) x ^= column[8 * byte + k];
          sobol1[byte][b] = x;
        }
    }
  };
  static const Tables& tables() {
    static const Tables t;
    return t;
  }
  static double toUnit(uint32_t x) { return (x >> 8) * (1.0 / 16777216.0); }  // [0, 1), 24 bits

  bool random_;
  uint64_t seed_;
  uint32_t index_, reversedIndex_;
  uint32_t bounce_ = 0, next_ = kCameraPairs;
};

}  // namespace mf::render
