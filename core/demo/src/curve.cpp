#include "curve.h"

#include <algorithm>
#include <cmath>

namespace fray::demo::detail {

void Curve::key(double t, double value, double slope, Interp in) {
    auto it = std::lower_bound(keys_.begin(), keys_.end(), t, [](const Key& k, double x) { return k.t < x; });
    if (it != keys_.end() && std::abs(it->t - t) < 1e-9) {
        *it = Key{it->t, value, slope, in};
        return;
    }
    keys_.insert(it, Key{t, value, slope, in});
}

void Curve::hold(double t) {
    const auto it = std::lower_bound(keys_.begin(), keys_.end(), t - 1e-9, [](const Key& k, double x) { return k.t < x; });
    if (it != keys_.end() && std::abs(it->t - t) < 1e-9) return;
    key(t, value(t), slope(t));
}

void Curve::ease(double t0, double t1, double v, Interp in) {
    hold(t0);
    key(t1, v, 0.0, in);
}

std::size_t Curve::segment(double t) const {
    const auto it = std::upper_bound(keys_.begin(), keys_.end(), t, [](double x, const Key& k) { return x < k.t; });
    return static_cast<std::size_t>(it - keys_.begin());
}

double Curve::value(double t) const {
    if (keys_.empty()) return initial_;
    const std::size_t i = segment(t);
    if (i == 0) return keys_.front().value;
    if (i == keys_.size()) return keys_.back().value;
    const Key& a = keys_[i - 1];
    const Key& b = keys_[i];
    const double h = b.t - a.t;
    const double u = (t - a.t) / h;
    const double m0 = a.slope * h, m1 = b.slope * h;
    const double u2 = u * u, u3 = u2 * u;
    if (b.in == Interp::Cubic) {
        return (2 * u3 - 3 * u2 + 1) * a.value + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * b.value +
               (u3 - u2) * m1;
    }
    const double u4 = u3 * u, u5 = u4 * u;
    return (1 - 10 * u3 + 15 * u4 - 6 * u5) * a.value + (u - 6 * u3 + 8 * u4 - 3 * u5) * m0 +
           (10 * u3 - 15 * u4 + 6 * u5) * b.value + (-4 * u3 + 7 * u4 - 3 * u5) * m1;
}

double Curve::slope(double t) const {
    if (keys_.empty()) return 0.0;
    const std::size_t i = segment(t);
    if (i == 0 || i == keys_.size()) return 0.0;
    const Key& a = keys_[i - 1];
    const Key& b = keys_[i];
    const double h = b.t - a.t;
    const double u = (t - a.t) / h;
    const double m0 = a.slope * h, m1 = b.slope * h;
    const double u2 = u * u, u3 = u2 * u, u4 = u3 * u;
    double d = 0;
    if (b.in == Interp::Cubic) {
        d = (6 * u2 - 6 * u) * a.value + (3 * u2 - 4 * u + 1) * m0 + (-6 * u2 + 6 * u) * b.value + (3 * u2 - 2 * u) * m1;
    } else {
        d = (-30 * u2 + 60 * u3 - 30 * u4) * a.value + (1 - 18 * u2 + 32 * u3 - 15 * u4) * m0 +
            (30 * u2 - 60 * u3 + 30 * u4) * b.value + (-12 * u2 + 28 * u3 - 15 * u4) * m1;
    }
    return d / h;
}

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }
double smoothstep(double u) {
    u = clamp01(u);
    return u * u * (3 - 2 * u);
}
double smootherstep(double u) {
    u = clamp01(u);
    return u * u * u * (u * (6 * u - 15) + 10);
}
double pulse(double u) {
    if (u <= 0 || u >= 1) return 0.0;
    const double v = u * (1 - u);
    return 64 * v * v * v;
}
double smin(double a, double b, double k) {
    // Cubic polynomial smooth minimum: C2, so a limit that engages does not
    // jerk what it limits.
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - h * h * h * k / 6.0;
}
double smax(double a, double b, double k) { return -smin(-a, -b, k); }

}  // namespace fray::demo::detail
