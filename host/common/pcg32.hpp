#pragma once
// PCG32 (O'Neill 2014): small state, independent streams. Renderers and samplers seed one stream per pixel or per
// sample index, so results do not depend on how work is split across threads.
#include <cstdint>

namespace clr {

class Pcg32 {
 public:
  Pcg32(std::uint64_t index, std::uint64_t stream) {
    inc_ = (stream << 1u) | 1u;
    next_uint();
    state_ += index;
    next_uint();
  }
  // The stream of sample `sample` of pixel `pixel`: each sample its own, so that the first n samples of an image are
  // the same whichever passes or sessions drew them (a resumed reference equals one rendered in one go). The key is
  // hashed (splitmix64's finaliser) because neighbouring keys would start at correlated states of one sequence.
  static Pcg32 for_sample(std::uint64_t pixel, std::uint64_t sample, std::uint64_t seed) {
    std::uint64_t key = (pixel << 26) ^ sample;  // distinct for pixel < 2^38, sample < 2^26
    key = (key ^ (key >> 30)) * 0xbf58476d1ce4e5b9ull;
    key = (key ^ (key >> 27)) * 0x94d049bb133111ebull;
    return Pcg32(key ^ (key >> 31), seed);
  }
  std::uint32_t next_uint() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const auto xorshifted = std::uint32_t(((old >> 18u) ^ old) >> 27u);
    const auto rot = std::uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  // Uniform in [0, 1): the top 24 bits, so the result is exact in float and never rounds up to 1.
  float next_float() { return float(next_uint() >> 8) * 0x1p-24f; }
  double next_double() { return double((std::uint64_t(next_uint()) << 21) ^ next_uint()) * 0x1p-53; }

 private:
  std::uint64_t state_ = 0x853c49e6748fea9bull;
  std::uint64_t inc_ = 0;
};

}  // namespace clr
