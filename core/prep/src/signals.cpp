#include "fray/prep/signals.h"

#include <algorithm>
#include <cmath>

#include "fray/core/kinematics.h"

namespace fray::prep {
namespace {

// Value at fraction q (0..1) of the sorted data (nearest rank).
float percentile(std::vector<float> values, double q) {
    if (values.empty()) return 0.0f;
    const auto k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
    return values[k];
}

}  // namespace

Support supportAt(const FootContacts& contacts, int frame) {
    const auto f = static_cast<std::size_t>(frame);
    const bool l = f < contacts.left.size() && contacts.left[f] != 0;
    const bool r = f < contacts.right.size() && contacts.right[f] != 0;
    return l && r ? Support::Double : l ? Support::Left : r ? Support::Right : Support::None;
}

Result<MotionSignals> computeSignals(const Motion& motion, const StandardJoints& joints) {
    if (!joints.hasFeet()) {
        return makeError("cannot find the feet in the skeleton (missing: " + joints.missing() + ")");
    }
    const int frames = motion.frameCount();
    if (frames < 3) return makeError("motion has " + std::to_string(frames) + " frames; at least 3 are needed");
    const int jointCount = motion.jointCount();
    const std::vector<glm::vec3> world = worldPositions(motion, 0, frames - 1);
    auto at = [&](int frame, int joint) -> const glm::vec3& {
        return world[static_cast<std::size_t>(frame) * static_cast<std::size_t>(jointCount) +
                     static_cast<std::size_t>(joint)];
    };

    MotionSignals s;
    s.fps = motion.fps();
    s.frameCount = frames;

    // Acceleration over a fixed 1/60 s step (k frames), whatever the capture rate.
    const int k = std::max(1, static_cast<int>(std::lround(motion.fps() / 60.0)));
    const double h = k / motion.fps();
    const double inv = 1.0 / (h * h);
    s.acceleration.assign(static_cast<std::size_t>(frames), 0.0f);
    for (int f = 0; f < frames; ++f) {
        const int a = std::max(0, f - k);
        const int b = std::min(frames - 1, f + k);
        if (b - f != f - a) continue;  // filled from neighbours below
        double sum = 0.0;
        for (int j = 0; j < jointCount; ++j) {
            const glm::dvec3 acc = (glm::dvec3(at(b, j)) - 2.0 * glm::dvec3(at(f, j)) + glm::dvec3(at(a, j))) * inv;
            sum += glm::dot(acc, acc);
        }
        s.acceleration[static_cast<std::size_t>(f)] = static_cast<float>(sum);
    }
    // The first and last k frames have no centred difference: hold the nearest value.
    for (int f = 0; f < std::min(k, frames); ++f) {
        s.acceleration[static_cast<std::size_t>(f)] = s.acceleration[static_cast<std::size_t>(std::min(k, frames - 1))];
        const int g = frames - 1 - f;
        s.acceleration[static_cast<std::size_t>(g)] =
            s.acceleration[static_cast<std::size_t>(std::max(0, frames - 1 - k))];
    }

    const int ankles[2] = {joints.leftFoot, joints.rightFoot};
    const int toes[2] = {joints.leftToe, joints.rightToe};
    auto heights = [&](int joint) {
        std::vector<float> y(static_cast<std::size_t>(frames));
        for (int f = 0; f < frames; ++f) y[static_cast<std::size_t>(f)] = at(f, joint).y;
        return y;
    };
    auto speed = [&](int joint, int f) {
        const int a = std::max(0, f - 1);
        const int b = std::min(frames - 1, f + 1);
        return static_cast<float>(glm::length(glm::dvec3(at(b, joint)) - glm::dvec3(at(a, joint))) * motion.fps() /
                                  (b - a));
    };
    for (int side = 0; side < 2; ++side) {
        const std::vector<float> ankleY = heights(ankles[side]);
        s.ankleFloor[static_cast<std::size_t>(side)] = percentile(ankleY, 0.02);
        std::vector<float> toeY;
        if (toes[side] >= 0) {
            toeY = heights(toes[side]);
            s.toeFloor[static_cast<std::size_t>(side)] = percentile(toeY, 0.02);
        }
        auto& sp = s.footSpeed[static_cast<std::size_t>(side)];
        auto& ht = s.footHeight[static_cast<std::size_t>(side)];
        sp.resize(static_cast<std::size_t>(frames));
        ht.resize(static_cast<std::size_t>(frames));
        for (int f = 0; f < frames; ++f) {
            const auto i = static_cast<std::size_t>(f);
            float v = speed(ankles[side], f);
            float y = ankleY[i] - s.ankleFloor[static_cast<std::size_t>(side)];
            if (toes[side] >= 0) {
                v = std::min(v, speed(toes[side], f));
                y = std::min(y, toeY[i] - s.toeFloor[static_cast<std::size_t>(side)]);
            }
            sp[i] = v;
            ht[i] = y;
        }
    }
    if (joints.pelvis >= 0 && joints.head >= 0 && joints.hasHands()) {
        s.posture.resize(static_cast<std::size_t>(frames));
        for (int f = 0; f < frames; ++f) {
            const glm::vec3& pelvis = at(f, joints.pelvis);
            const glm::vec3& head = at(f, joints.head);
            s.posture[static_cast<std::size_t>(f)] = {pelvis.y, head.y,
                                                      glm::length(glm::vec2(head.x - pelvis.x, head.z - pelvis.z)),
                                                      at(f, joints.leftHand).y - pelvis.y,
                                                      at(f, joints.rightHand).y - pelvis.y};
        }
    }
    // Body height.
    {
        const double floorY = std::min(s.ankleFloor[0], s.ankleFloor[1]);
        if (joints.head >= 0) {
            s.bodyHeight = double(percentile(heights(joints.head), 0.9)) - floorY;
        } else if (joints.pelvis >= 0) {
            s.bodyHeight = 1.9 * (double(percentile(heights(joints.pelvis), 0.9)) - floorY);
        }
        if (!(s.bodyHeight > 1e-6) || !std::isfinite(s.bodyHeight)) s.bodyHeight = 1.7;
    }
    if (joints.pelvis >= 0 && joints.hasHands()) {
        s.effectorSpeed.resize(static_cast<std::size_t>(frames));
        const double scale = motion.fps() / s.bodyHeight;
        for (int f = 0; f < frames; ++f) {
            const int a = std::max(0, f - 1), b = std::min(frames - 1, f + 1);
            const double perFrame = scale / double(b - a);
            double v = 0.0;
            for (const int hand : {joints.leftHand, joints.rightHand}) {
                const glm::dvec3 d = (glm::dvec3(at(b, hand)) - glm::dvec3(at(b, joints.pelvis))) -
                                     (glm::dvec3(at(a, hand)) - glm::dvec3(at(a, joints.pelvis)));
                v = std::max(v, glm::length(d) * perFrame);
            }
            for (const int foot : ankles) {
                v = std::max(v, glm::length(glm::dvec3(at(b, foot)) - glm::dvec3(at(a, foot))) * perFrame);
            }
            s.effectorSpeed[static_cast<std::size_t>(f)] = static_cast<float>(v);
        }
    }
    return s;
}

}  // namespace fray::prep
