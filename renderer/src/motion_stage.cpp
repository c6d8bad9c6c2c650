#include "fray/render/motion_stage.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "fray/core/joint_guess.h"
#include "fray/core/kinematics.h"

namespace fray::render {

void MotionStage::clear() {
    actors_.clear();
    posed_.clear();
    instances_.clear();
}

int MotionStage::add(StageActor actor) {
    actors_.push_back(std::move(actor));
    posed_.emplace_back();
    instances_.emplace_back();
    return static_cast<int>(actors_.size()) - 1;
}

namespace {
int lastOf(const StageActor& a) {
    const int last = a.motion->frameCount() - 1;
    return a.lastFrame < 0 ? last : std::clamp(a.lastFrame, 0, last);
}
}  // namespace

void MotionStage::poseActor(std::size_t i, double localTime, bool exactFrame, int frame) {
    const StageActor& a = actors_[i];
    Posed& p = posed_[i];
    CharacterInstance& inst = instances_[i];
    if (!a.motion || a.motion->frameCount() == 0) {
        inst = CharacterInstance{};
        return;
    }
    const Motion& m = *a.motion;
    const Skeleton& sk = m.skeleton();
    const auto jc = static_cast<std::size_t>(sk.jointCount());
    p.positions.resize(jc);
    p.rotations.resize(jc);
    const int first = std::clamp(a.firstFrame, 0, m.frameCount() - 1);
    const int last = std::max(first, lastOf(a));
    if (exactFrame) {
        p.frame = std::clamp(first + frame, first, last);
        forwardKinematics(sk, m.translations(p.frame), m.rotations(p.frame), p.positions, p.rotations);
    } else {
        const double t0 = first / m.fps();
        const double t = std::clamp(t0 + localTime, t0, last / m.fps());
        p.frame = std::clamp(static_cast<int>(std::lround(t * m.fps())), first, last);
        m.sample(t, p.local);
        forwardKinematics(sk, p.local.translations, p.local.rotations, p.positions, p.rotations);
    }
    if (a.offset != glm::vec3(0.0f))
        for (glm::vec3& q : p.positions) q += a.offset;
    inst.skeleton = &sk;
    inst.jointPositions = p.positions;
    inst.jointRotations = p.rotations;
    inst.tint = a.tint;
    inst.selected = a.selected;
    inst.label = actionOf(static_cast<int>(i));
    if (inst.label.empty()) inst.label = a.name;
}

void MotionStage::pose(double t, bool loop) {
    for (std::size_t i = 0; i < actors_.size(); ++i) {
        double local = t;
        const StageActor& a = actors_[i];
        if (loop && a.motion && a.motion->frameCount() > 1) {
            const int first = std::clamp(a.firstFrame, 0, a.motion->frameCount() - 1);
            const double len = (std::max(first, lastOf(a)) - first) / a.motion->fps();
            if (len > 0.0) local = std::fmod(std::max(t, 0.0), len);
        }
        poseActor(i, local, false, 0);
    }
}

void MotionStage::poseFrame(int offset) {
    for (std::size_t i = 0; i < actors_.size(); ++i) poseActor(i, 0.0, true, offset);
}

int MotionStage::frameOf(int actor) const { return posed_[static_cast<std::size_t>(actor)].frame; }

std::string_view MotionStage::actionOf(int actor) const {
    const auto i = static_cast<std::size_t>(actor);
    const int f = posed_[i].frame;
    for (const ActionSpan& s : actors_[i].actions)
        if (f >= s.firstFrame && f <= s.lastFrame) return s.name;
    return {};
}

double MotionStage::duration() const {
    double d = 0.0;
    for (const StageActor& a : actors_) {
        if (!a.motion || a.motion->frameCount() == 0) continue;
        const int first = std::clamp(a.firstFrame, 0, a.motion->frameCount() - 1);
        d = std::max(d, (std::max(first, lastOf(a)) - first) / a.motion->fps());
    }
    return d;
}

int MotionStage::longestFrameCount() const {
    int n = 0;
    for (const StageActor& a : actors_) {
        if (!a.motion || a.motion->frameCount() == 0) continue;
        const int first = std::clamp(a.firstFrame, 0, a.motion->frameCount() - 1);
        n = std::max(n, std::max(first, lastOf(a)) - first + 1);
    }
    return n;
}

Bounds MotionStage::bounds() const { return characterBounds(instances_); }

std::vector<glm::vec3> floorTrail(const Motion& motion, int first, int last, int step, glm::vec3 offset) {
    std::vector<glm::vec3> out;
    if (motion.frameCount() == 0) return out;
    first = std::clamp(first, 0, motion.frameCount() - 1);
    last = std::clamp(last, first, motion.frameCount() - 1);
    step = std::max(1, step);
    const StandardJoints sj = guessStandardJoints(motion.skeleton());
    const auto pelvis = static_cast<std::size_t>(sj.pelvis >= 0 ? sj.pelvis : 0);
    std::vector<glm::vec3> pos(static_cast<std::size_t>(motion.jointCount()));
    std::vector<glm::quat> rot(pos.size());
    for (int f = first;; f = std::min(f + step, last)) {
        worldTransforms(motion, f, pos, rot);
        out.emplace_back(pos[pelvis].x + offset.x, 0.0f, pos[pelvis].z + offset.z);
        if (f == last) break;
    }
    return out;
}

glm::vec3 teamColor(int index) {
    static constexpr std::array<glm::vec3, 8> kColors{{
        {0.80f, 0.30f, 0.25f},  // red
        {0.25f, 0.45f, 0.80f},  // blue
        {0.30f, 0.65f, 0.35f},  // green
        {0.85f, 0.60f, 0.20f},  // amber
        {0.55f, 0.35f, 0.70f},  // purple
        {0.25f, 0.65f, 0.70f},  // teal
        {0.80f, 0.45f, 0.60f},  // pink
        {0.60f, 0.60f, 0.55f},  // stone
    }};
    return kColors[static_cast<std::size_t>(index) % kColors.size()];
}

glm::vec3 sideColor(int side, int member) {
    static constexpr std::array<std::array<glm::vec3, 3>, 4> kSides{{
        {{{0.80f, 0.30f, 0.25f}, {0.88f, 0.50f, 0.30f}, {0.66f, 0.22f, 0.32f}}},  // reds
        {{{0.25f, 0.45f, 0.80f}, {0.30f, 0.62f, 0.85f}, {0.32f, 0.32f, 0.72f}}},  // blues
        {{{0.30f, 0.65f, 0.35f}, {0.50f, 0.72f, 0.30f}, {0.22f, 0.52f, 0.42f}}},  // greens
        {{{0.85f, 0.60f, 0.20f}, {0.90f, 0.72f, 0.35f}, {0.72f, 0.50f, 0.18f}}},  // ambers
    }};
    const int shade = ((member % 3) + 3) % 3;
    if (side >= 0 && side < static_cast<int>(kSides.size())) return kSides[static_cast<std::size_t>(side)][static_cast<std::size_t>(shade)];
    return teamColor(std::max(side, 0) * 3 + shade);
}

}  // namespace fray::render
