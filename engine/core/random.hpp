// Deterministic random streams (DESIGN convention 9): one seed per experiment, one independent stream per
// trial, so results never depend on the number of threads. The generator is xoshiro256** (Blackman & Vigna,
// 2018) seeded through splitmix64; the normal deviates come from the Marsaglia polar method, implemented here
// so the numbers are identical across standard libraries (std::normal_distribution is
// implementation-defined).
#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

namespace keel::core {

// splitmix64 step: advances `state` and returns a well-mixed 64-bit value.
inline std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) {
    std::uint64_t sm = seed;
    for (auto& w : s_) w = splitmix64(sm);
  }

  // Independent stream `index` of experiment seed `seed` (trial i uses stream(seed, i)). The pair is hashed
  // through two splitmix rounds so neighbouring indices give unrelated states.
  static Rng stream(std::uint64_t seed, std::uint64_t index) {
    std::uint64_t a = seed;
    std::uint64_t h = splitmix64(a);
    std::uint64_t b = h ^ (index * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull);
    return Rng(splitmix64(b));
  }

  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  // Uniform on [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

  // Uniform on [a, b).
  double uniform(double a, double b) { return a + (b - a) * uniform(); }

  // Standard normal deviate (Marsaglia polar method; the second deviate of each pair is cached).
  double normal() {
    if (has_cached_) {
      has_cached_ = false;
      return cached_;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform() - 1.0;
      v = 2.0 * uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * std::log(s) / s);
    cached_ = v * f;
    has_cached_ = true;
    return u * f;
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  double cached_ = 0.0;
  bool has_cached_ = false;
};

// The random streams of one run (DESIGN convention 9): the experiment's seed and a base index. Stream i of a
// Streams is Rng::stream(seed, base + i), so a study draws trial i from `streams.stream(i)` whatever the
// thread or shard that runs it. `offset(k)` is the same family shifted by k (a sweep point that reuses its
// neighbours' layout, or common random numbers with base 0); `child(name)` is an independent family named
// for what it draws ("world1d", "candidates"): its seed hashes the parent's seed, base and name, so two
// children of different names, or of different parents, share no stream.
class Streams {
 public:
  Streams() = default;
  explicit Streams(std::uint64_t seed, std::uint64_t base = 0) : seed_(seed), base_(base) {}

  [[nodiscard]] Rng stream(std::uint64_t index) const { return Rng::stream(seed_, base_ + index); }
  [[nodiscard]] Streams offset(std::uint64_t k) const { return Streams(seed_, base_ + k); }
  [[nodiscard]] Streams child(std::string_view name) const {
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a of the name, then mixed with seed and base
    for (unsigned char c : name) {
      h ^= c;
      h *= 0x100000001b3ull;
    }
    std::uint64_t state = seed_ ^ (h * 0x9E3779B97F4A7C15ull);
    const std::uint64_t a = splitmix64(state);
    state = a ^ (base_ * 0xD1B54A32D192ED03ull);
    return Streams(splitmix64(state), 0);
  }
  // The (seed, index) pair of stream i, for generators that take them (sim::generate_world1d(o, seed, i)).
  [[nodiscard]] std::uint64_t seed() const { return seed_; }
  [[nodiscard]] std::uint64_t index(std::uint64_t i) const { return base_ + i; }
  [[nodiscard]] std::uint64_t base() const { return base_; }

 private:
  std::uint64_t seed_ = 0, base_ = 0;
};

}  // namespace keel::core
