#pragma once
// Keyframed scalar curves. Between two keys the curve is a Hermite spline
// through the keys' values and slopes: quintic with zero acceleration at the
// keys by default (C1 everywhere, C2 where slopes are zero), or cubic. A key
// with slope 0 is an "ease" key; keys with matched slopes chain motions
// without stopping (locomotion).
#include <cstdint>
#include <vector>

namespace fray::demo::detail {

enum class Interp : std::uint8_t { Quintic, Cubic };

struct Key {
    double t = 0;
    double value = 0;
    double slope = 0;                // units per second
    Interp in = Interp::Quintic;     // shape of the segment ending at this key
};

class Curve {
public:
    explicit Curve(double initial = 0.0) : initial_(initial) {}

    // Inserts (or replaces, at the same time) a key; keys stay sorted.
    void key(double t, double value, double slope = 0.0, Interp in = Interp::Quintic);
    // Pins the current value at t with a flat key, unless a key is already there.
    void hold(double t);
    // Holds at t0 and eases to `value` at t1 (flat at both ends).
    void ease(double t0, double t1, double value, Interp in = Interp::Quintic);

    double value(double t) const;
    double slope(double t) const;
    double lastValue() const { return keys_.empty() ? initial_ : keys_.back().value; }
    double lastTime() const { return keys_.empty() ? 0.0 : keys_.back().t; }
    bool empty() const { return keys_.empty(); }

private:
    std::size_t segment(double t) const;  // index of the key ending the segment holding t
    std::vector<Key> keys_;
    double initial_;
};

// Easing helpers on [0, 1].
double smoothstep(double u);    // cubic, zero slope at the ends
double smootherstep(double u);  // quintic, zero slope and acceleration at the ends
double pulse(double u);         // 64 u^3 (1-u)^3 on [0,1], 0 outside: a C2 pulse peaking at 1
// C2 smooth minimum / maximum with blending width k.
double smin(double a, double b, double k);
double smax(double a, double b, double k);
double clamp01(double x);

}  // namespace fray::demo::detail
