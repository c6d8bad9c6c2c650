#include "fray/core/motion.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

namespace fray {

Motion::Motion(Skeleton skeleton, double fps, int frameCount)
    : skeleton_(std::move(skeleton)), fps_(fps), frameCount_(frameCount) {
    const std::size_t n = static_cast<std::size_t>(frameCount) * static_cast<std::size_t>(skeleton_.jointCount());
    translations_.resize(n);
    rotations_.assign(n, glm::quat(1, 0, 0, 0));
    for (int f = 0; f < frameCount; ++f)
        for (int j = 0; j < skeleton_.jointCount(); ++j)
            translations_[index(f, j)] = skeleton_.offsets[static_cast<std::size_t>(j)];
}

std::span<glm::vec3> Motion::translations(int frame) {
    return {translations_.data() + index(frame, 0), static_cast<std::size_t>(jointCount())};
}
std::span<const glm::vec3> Motion::translations(int frame) const {
    return {translations_.data() + index(frame, 0), static_cast<std::size_t>(jointCount())};
}
std::span<glm::quat> Motion::rotations(int frame) {
    return {rotations_.data() + index(frame, 0), static_cast<std::size_t>(jointCount())};
}
std::span<const glm::quat> Motion::rotations(int frame) const {
    return {rotations_.data() + index(frame, 0), static_cast<std::size_t>(jointCount())};
}

void Motion::appendFrame(std::span<const glm::vec3> translations, std::span<const glm::quat> rotations) {
    translations_.insert(translations_.end(), translations.begin(), translations.end());
    rotations_.insert(rotations_.end(), rotations.begin(), rotations.end());
    ++frameCount_;
}

void Motion::reserveFrames(std::size_t frames) {
    const std::size_t n = frames * static_cast<std::size_t>(jointCount());
    translations_.reserve(n);
    rotations_.reserve(n);
}

void Motion::sample(double t, Pose& out) const {
    const auto jc = static_cast<std::size_t>(jointCount());
    out.translations.resize(jc);
    out.rotations.resize(jc);
    if (frameCount_ == 0) return;
    const double x = std::clamp(t * fps_, 0.0, static_cast<double>(frameCount_ - 1));
    const int f0 = static_cast<int>(std::floor(x));
    const int f1 = std::min(f0 + 1, frameCount_ - 1);
    const float a = static_cast<float>(x - f0);
    const glm::vec3* t0 = translations_.data() + index(f0, 0);
    const glm::vec3* t1 = translations_.data() + index(f1, 0);
    const glm::quat* r0 = rotations_.data() + index(f0, 0);
    const glm::quat* r1 = rotations_.data() + index(f1, 0);
    for (std::size_t j = 0; j < jc; ++j) {
        out.translations[j] = glm::mix(t0[j], t1[j], a);
        out.rotations[j] = a == 0.0f ? r0[j] : glm::slerp(r0[j], r1[j], a);
    }
}

Result<Motion> resample(const Motion& motion, double targetFps) {
    if (!(targetFps > 0.0) || !std::isfinite(targetFps))
        return makeError("resample: target frame rate must be positive, got " + std::to_string(targetFps));
    if (motion.frameCount() == 0) return makeError("resample: motion has no frames");
    const double duration = motion.duration();
    const int frames = static_cast<int>(std::floor(duration * targetFps + 1e-6)) + 1;
    Motion out(motion.skeleton(), targetFps, 0);
    out.source() = motion.source();
    out.reserveFrames(static_cast<std::size_t>(frames));
    Pose pose;
    for (int f = 0; f < frames; ++f) {
        motion.sample(f / targetFps, pose);
        out.appendFrame(pose.translations, pose.rotations);
    }
    return out;
}

Result<Motion> trim(const Motion& motion, int first, int last) {
    if (first < 0 || last >= motion.frameCount() || first > last)
        return makeError("trim: frame range " + std::to_string(first) + ".." + std::to_string(last) +
                         " is outside 0.." + std::to_string(motion.frameCount() - 1));
    Motion out(motion.skeleton(), motion.fps(), 0);
    out.source() = motion.source();
    out.reserveFrames(static_cast<std::size_t>(last - first + 1));
    for (int f = first; f <= last; ++f) out.appendFrame(motion.translations(f), motion.rotations(f));
    return out;
}

namespace {
// Heading (rotation about +Y) of a root orientation: the angle of its forward
// (+Z) axis projected on the floor.
float headingOf(const glm::quat& q) {
    const glm::vec3 fwd = q * glm::vec3(0, 0, 1);
    return std::atan2(fwd.x, fwd.z);
}
}  // namespace

Result<Motion> concatenate(const Motion& a, const Motion& b, bool alignRoot) {
    const Skeleton& sa = a.skeleton();
    const Skeleton& sb = b.skeleton();
    if (sa.names != sb.names || sa.parents != sb.parents)
        return makeError("concatenate: skeletons differ (joint names or hierarchy)");
    if (std::abs(a.fps() - b.fps()) > 1e-6)
        return makeError("concatenate: frame rates differ (" + std::to_string(a.fps()) + " vs " +
                         std::to_string(b.fps()) + "); resample first");
    Motion out = a;
    if (b.frameCount() == 0) return out;
    glm::quat turn(1, 0, 0, 0);
    glm::vec3 shift(0);
    if (alignRoot && a.frameCount() > 0) {
        const float dh = headingOf(a.rotations(a.frameCount() - 1)[0]) - headingOf(b.rotations(0)[0]);
        turn = glm::angleAxis(dh, glm::vec3(0, 1, 0));
        const glm::vec3 endA = a.rootTranslation(a.frameCount() - 1);
        const glm::vec3 startB = turn * b.rootTranslation(0);
        shift = glm::vec3(endA.x - startB.x, 0.0f, endA.z - startB.z);
    }
    out.reserveFrames(static_cast<std::size_t>(a.frameCount() + b.frameCount()));
    std::vector<glm::vec3> t;
    std::vector<glm::quat> r;
    for (int f = 0; f < b.frameCount(); ++f) {
        auto bt = b.translations(f);
        auto br = b.rotations(f);
        t.assign(bt.begin(), bt.end());
        r.assign(br.begin(), br.end());
        t[0] = turn * t[0] + shift;
        r[0] = turn * r[0];
        out.appendFrame(t, r);
    }
    return out;
}

}  // namespace fray
