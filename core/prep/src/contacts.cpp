// Heuristic contacts, training samples and agreement (SPEC 1.3). The SVM
// lives in contact_svm.cpp.
#include "fray/prep/contacts.h"

#include <algorithm>
#include <cmath>

namespace fray::prep {
namespace {

// Median filter of a 0/1 sequence = majority vote in a centred window. At
// the ends the window is cut short; a tie there keeps the frame's own value.
std::vector<std::uint8_t> majorityFilter(const std::vector<std::uint8_t>& raw, int window) {
    const int n = static_cast<int>(raw.size());
    const int half = window / 2;
    if (half <= 0 || n == 0) return raw;
    std::vector<int> prefix(static_cast<std::size_t>(n) + 1, 0);
    for (std::size_t f = 0; f < raw.size(); ++f) prefix[f + 1] = prefix[f] + (raw[f] ? 1 : 0);
    std::vector<std::uint8_t> out(raw.size());
    for (int f = 0; f < n; ++f) {
        const int a = std::max(0, f - half);
        const int b = std::min(n - 1, f + half);
        const int ones = prefix[static_cast<std::size_t>(b) + 1] - prefix[static_cast<std::size_t>(a)];
        const int count = b - a + 1;
        const auto i = static_cast<std::size_t>(f);
        out[i] = 2 * ones > count ? 1 : 2 * ones < count ? 0 : raw[i];
    }
    return out;
}

}  // namespace

FootContacts heuristicContacts(const MotionSignals& signals, const HeuristicParams& params) {
    // The window is given at 60 fps; a 120 fps capture needs twice the frames
    // for the same time span. Odd, so the window is centred.
    int window = 1;
    if (params.medianWindow > 1 && signals.fps > 0.0) {
        window = std::max(1, static_cast<int>(std::lround(params.medianWindow * signals.fps / 60.0)));
        if (window % 2 == 0) ++window;
    }
    FootContacts out;
    for (const Foot foot : {Foot::Left, Foot::Right}) {
        const auto side = static_cast<std::size_t>(foot);
        const auto& speed = signals.footSpeed[side];
        const auto& height = signals.footHeight[side];
        const std::size_t n = std::min(speed.size(), height.size());
        std::vector<std::uint8_t> raw(n);
        // NaN compares false: an undefined feature reads as "not supporting".
        for (std::size_t f = 0; f < n; ++f) raw[f] = height[f] <= params.maxHeight && speed[f] <= params.maxSpeed;
        out.foot(foot) = majorityFilter(raw, window);
    }
    return out;
}

std::vector<TrainingSample> collectSamples(const MotionSignals& signals, const FrameLabels& labels) {
    std::vector<TrainingSample> out;
    for (const Foot foot : {Foot::Left, Foot::Right}) {
        const auto side = static_cast<std::size_t>(foot);
        const auto& lab = foot == Foot::Left ? labels.left : labels.right;
        const std::size_t n = std::min({lab.size(), signals.footSpeed[side].size(), signals.footHeight[side].size()});
        for (std::size_t f = 0; f < n; ++f) {
            if (lab[f] < 0) continue;
            out.push_back({signals.footSpeed[side][f], signals.footHeight[side][f], lab[f] > 0});
        }
    }
    return out;
}

std::vector<ContactLabel> labelsFromContacts(const FootContacts& contacts, int firstFrame, int lastFrame) {
    std::vector<ContactLabel> out;
    const int last = std::min(lastFrame, std::min(contacts.frameCount(), static_cast<int>(contacts.right.size())) - 1);
    for (int f = std::max(0, firstFrame); f <= last; ++f) {
        const bool l = contacts.left[static_cast<std::size_t>(f)] != 0;
        const bool r = contacts.right[static_cast<std::size_t>(f)] != 0;
        if (!out.empty() && out.back().lastFrame == f - 1 && out.back().left == l && out.back().right == r) {
            out.back().lastFrame = f;
        } else {
            out.push_back({f, f, l, r});
        }
    }
    return out;
}

double contactAgreement(const FootContacts& a, const FootContacts& b) {
    std::size_t total = 0;
    std::size_t equal = 0;
    for (const Foot foot : {Foot::Left, Foot::Right}) {
        const auto& x = a.foot(foot);
        const auto& y = b.foot(foot);
        const std::size_t common = std::min(x.size(), y.size());
        total += std::max(x.size(), y.size());
        for (std::size_t f = 0; f < common; ++f) equal += (x[f] != 0) == (y[f] != 0) ? 1 : 0;
    }
    return total == 0 ? 1.0 : static_cast<double>(equal) / static_cast<double>(total);
}

}  // namespace fray::prep
