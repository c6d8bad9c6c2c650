#pragma once
// Deterministic random numbers: std::mt19937_64 is specified bit-exactly by the
// standard, its distributions are not, so the few we need are written here.
#include <cstdint>
#include <random>
#include <vector>

namespace fray::demo::detail {

class Rng {
public:
    explicit Rng(std::uint64_t seed) : g_(seed) {}
    // Uniform in [0, 1) with 53 random bits.
    double uniform() { return static_cast<double>(g_() >> 11) * (1.0 / 9007199254740992.0); }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    // Uniform integer in [0, n).
    int below(int n) { return n <= 1 ? 0 : static_cast<int>(g_() % static_cast<std::uint64_t>(n)); }
    int between(int lo, int hi) { return lo + below(hi - lo + 1); }  // inclusive
    bool chance(double p) { return uniform() < p; }
    // Multiplicative jitter around 1: uniform in [1 - spread, 1 + spread].
    double jitter(double spread) { return uniform(1.0 - spread, 1.0 + spread); }
    template <class T>
    void shuffle(std::vector<T>& v) {
        for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[static_cast<std::size_t>(below(static_cast<int>(i)))]);
    }
    std::uint64_t next() { return g_(); }

private:
    std::mt19937_64 g_;
};

}  // namespace fray::demo::detail
