// The scene: the floor bitmap's tests, the creatures' skeletons, keys and held
// balls, and playback (ScenePoser). The scene file's reader and writer are in
// scene_file.cpp.
#include "fray/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

#include <glm/gtc/quaternion.hpp>
#include <tbb/parallel_for.h>

#include "fray/core/kinematics.h"
#include "scene_bodies.h"

namespace fray::sim {

using detail::BodyKind;
using detail::bodyKind;
using detail::kBodyKinds;

bool FloorBitmap::paintedAt(glm::vec2 floor) const {
    if (empty() || !(metresPerPixel > 0)) return false;
    const double x = (static_cast<double>(floor.x) - static_cast<double>(origin.x)) / metresPerPixel;
    const double y = (static_cast<double>(floor.y) - static_cast<double>(origin.y)) / metresPerPixel;
    if (!(x >= 0 && y >= 0 && x < width && y < height)) return false;
    return painted[static_cast<std::size_t>(static_cast<int>(y)) * static_cast<std::size_t>(width) + static_cast<std::size_t>(static_cast<int>(x))] != 0;
}

bool FloorBitmap::paintedWithin(glm::vec2 q, double r) const {
    if (empty() || !(metresPerPixel > 0) || !(r >= 0)) return false;
    const double px = metresPerPixel, qx = q.x, qz = q.y, ox = origin.x, oz = origin.y;
    const auto lo = [&](double v) { return static_cast<int>(std::clamp(std::floor(v / px), -1.0, 1e9)); };
    const int x0 = std::max(0, lo(qx - r - ox)), x1 = std::min(width - 1, lo(qx + r - ox));
    const int y0 = std::max(0, lo(qz - r - oz)), y1 = std::min(height - 1, lo(qz + r - oz));
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            if (!painted[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)]) continue;
            // The pixel's nearest point to q.
            const double cx = std::clamp(qx, ox + x * px, ox + (x + 1) * px);
            const double cz = std::clamp(qz, oz + y * px, oz + (y + 1) * px);
            if (std::hypot(cx - qx, cz - qz) <= r) return true;
        }
    }
    return false;
}

const Skeleton* creatureSkeleton(std::string_view body) {
    static const auto skeletons = [] {
        std::vector<Skeleton> out;
        for (const auto& kind : kBodyKinds) {
            Skeleton k;
            k.addJoint(std::string(kind.name), -1, glm::vec3(0.0f),
                       {Channel::Xposition, Channel::Yposition, Channel::Zposition, Channel::Zrotation, Channel::Xrotation,
                        Channel::Yrotation},
                       RotationOrder::ZXY);
            k.endSites[0] = glm::vec3(0.0f, 0.0f, kind.length);
            out.push_back(std::move(k));
        }
        return out;
    }();
    const BodyKind* kind = bodyKind(body);
    return kind ? &skeletons[static_cast<std::size_t>(kind - kBodyKinds)] : nullptr;
}

namespace {

// The keys either side of t and the blend between them.
std::tuple<const RootKey*, const RootKey*, double> keysAround(const std::vector<RootKey>& k, double t) {
    if (t <= k.front().time) return {&k.front(), &k.front(), 0.0};
    if (t >= k.back().time) return {&k.back(), &k.back(), 0.0};
    const auto it = std::upper_bound(k.begin(), k.end(), t, [](double x, const RootKey& key) { return x < key.time; });
    const RootKey& b = *it;
    const RootKey& a = *(it - 1);
    const double span = b.time - a.time;
    return {&a, &b, span > 0 ? (t - a.time) / span : 1.0};
}

}  // namespace

RootXf creatureAt(const SceneCharacter& c, double t) {
    if (c.keys.empty()) return {};
    const auto [a, b, u] = keysAround(c.keys, t);
    return lerp(a->at, b->at, u);
}

float creatureHeightAt(const SceneCharacter& c, double t) {
    const BodyKind* kind = bodyKind(c.body);
    const float own = kind ? kind->height : 0.0f;
    if (c.keys.empty()) return own;
    const auto [a, b, u] = keysAround(c.keys, t);
    if (a->height < 0 || b->height < 0) return own;
    return a->height + static_cast<float>(u) * (b->height - a->height);
}

float creaturePitchAt(const SceneCharacter& c, double t) {
    if (c.keys.empty()) return 0.0f;
    const auto [a, b, u] = keysAround(c.keys, t);
    return a->pitch + static_cast<float>(u) * (b->pitch - a->pitch);
}

glm::quat creatureRotation(double heading, float pitch) {
    // Pitch about -X raises +Z towards +Y; then the heading about +Y.
    return glm::angleAxis(static_cast<float>(heading), glm::vec3(0, 1, 0)) * glm::angleAxis(-pitch, glm::vec3(1, 0, 0));
}

RootKey ballKey(double time, const glm::vec3& hand, const glm::vec3& elbow) {
    glm::vec3 d = hand - elbow;
    const float len = glm::length(d);
    d = len > 1e-4f && std::isfinite(len) ? d / len : glm::vec3(0, 0, 1);
    const float flat = std::sqrt(d.x * d.x + d.z * d.z);
    const double heading = flat > 1e-4f ? static_cast<double>(std::atan2(d.x, d.z)) : 0.0;
    const float pitch = std::atan2(d.y, flat);
    const glm::vec3 back = hand - d * (kBallTuck + 0.5f * kBallLength);
    RootKey k;
    k.time = time;
    k.at = {{back.x, back.z}, wrapAngle(heading)};
    k.height = std::max(0.0f, back.y);
    k.pitch = pitch;
    return k;
}

glm::vec3 ballGrip(const RootXf& at, float height, float pitch) {
    return glm::vec3(at.pos.x, height, at.pos.y) + creatureRotation(at.heading, pitch) * glm::vec3(0, 0, 0.5f * kBallLength + kBallTuck);
}

glm::vec3 ballGripAt(const SceneCharacter& ball, double t) {
    return ballGrip(creatureAt(ball, t), creatureHeightAt(ball, t), creaturePitchAt(ball, t));
}

std::int64_t heldKeyCount(double from, double to) {
    return static_cast<std::int64_t>(std::ceil((to - from) * kSampleRate - 1e-9)) + 1;
}

std::vector<RootKey> heldBallKeys(const Scene& scene, const ActionLibrary& lib, int ball) {
    const auto& b = scene.characters[static_cast<std::size_t>(ball)];
    const int carrier = b.holder;
    if (!b.held() || carrier >= static_cast<int>(scene.characters.size()) || scene.isCreature(carrier)) return {};
    const auto& track = scene.characters[static_cast<std::size_t>(carrier)].track;
    if (track.empty()) return {};
    const auto& joints = lib.motion(lib.actions()[static_cast<std::size_t>(track.front().action)].motion).joints;
    const int handJoint = b.hand == 0 ? joints.leftHand : joints.rightHand;
    const int elbowJoint = b.hand == 0 ? joints.leftElbow : joints.rightElbow;
    if (handJoint < 0 || elbowJoint < 0) return {};  // a skeleton without arms holds no ball
    const ScenePoser poser(scene, lib);
    std::vector<glm::vec3> world;
    std::vector<RootKey> keys;
    const double from = b.heldFrom, to = b.heldTo;
    const std::int64_t n = heldKeyCount(from, to);
    keys.reserve(static_cast<std::size_t>(n));
    for (std::int64_t k = 0; k < n; ++k) {
        const double t = std::min(to, from + static_cast<double>(k) / kSampleRate);
        poser.worldPositions(carrier, t, world);
        keys.push_back(ballKey(t, world[static_cast<std::size_t>(handJoint)], world[static_cast<std::size_t>(elbowJoint)]));
    }
    return keys;
}

void placeHeldBalls(Scene& scene, const ActionLibrary& lib) {
    std::vector<int> balls;
    for (std::size_t i = 0; i < scene.characters.size(); ++i) {
        if (scene.characters[i].held()) balls.push_back(static_cast<int>(i));
    }
    // Each ball's keys are its own; the poses read only the holders' tracks.
    tbb::parallel_for(std::size_t{0}, balls.size(), [&](std::size_t i) {
        const int b = balls[i];
        std::vector<RootKey> held = heldBallKeys(scene, lib, b);
        auto& ball = scene.characters[static_cast<std::size_t>(b)];
        std::vector<RootKey> keys;
        keys.reserve(ball.keys.size() + held.size());
        for (const auto& k : ball.keys) {
            if (k.time < ball.heldFrom) keys.push_back(k);
        }
        keys.insert(keys.end(), held.begin(), held.end());
        for (const auto& k : ball.keys) {
            if (k.time > ball.heldTo) keys.push_back(k);
        }
        ball.keys = std::move(keys);
    });
}

int Scene::instanceAt(int c, double t) const { return instanceIndexAt(characters[static_cast<std::size_t>(c)].track, t); }

int instanceIndexAt(std::span<const ActionInstance> track, double t) {
    if (track.empty()) return -1;
    const auto it = std::upper_bound(track.begin(), track.end(), t,
                                     [](double x, const ActionInstance& inst) { return x < inst.start; });
    if (it == track.begin()) return 0;
    return static_cast<int>(it - track.begin()) - 1;
}

// ---- playback ---------------------------------------------------------------

ScenePoser::ScenePoser(const Scene& scene, const ActionLibrary& lib, double blendSeconds)
    : scene_(scene), lib_(lib), blend_(blendSeconds) {}

const Skeleton& ScenePoser::skeleton(int character) const {
    if (scene_.isCreature(character)) return *creatureSkeleton(scene_.characters[static_cast<std::size_t>(character)].body);
    const auto& track = scene_.characters[static_cast<std::size_t>(character)].track;
    const int motion = track.empty() ? 0 : lib_.actions()[static_cast<std::size_t>(track.front().action)].motion;
    return lib_.motion(motion).motion.skeleton();
}

void ScenePoser::rawPose(int character, int instance, double t, Pose& out) const {
    const auto& inst = scene_.characters[static_cast<std::size_t>(character)].track[static_cast<std::size_t>(instance)];
    // A looped instance plays the repetition under way at t.
    rawPoseAt(character, instance, inst.offset + (t - inst.repeatStart(inst.repeatAt(t))), out);
}

void ScenePoser::rawPoseAt(int character, int instance, double clipTime, Pose& out) const {
    const auto& inst = scene_.characters[static_cast<std::size_t>(character)].track[static_cast<std::size_t>(instance)];
    const auto& a = lib_.actions()[static_cast<std::size_t>(inst.action)];
    const auto& lm = lib_.motion(a.motion);
    const double fps = lm.motion.fps();
    const double tau = std::clamp(clipTime, 0.0, a.duration);
    const double frame = std::min(a.firstFrame + tau * fps, static_cast<double>(a.lastFrame));
    lm.motion.sample(frame / fps, out);
    // The clip's first-frame placement in its motion, moved to inst.root.
    const RootXf m = inst.root * a.source.inverse();
    out.translations[0] = m.apply(out.translations[0]);
    out.rotations[0] = glm::angleAxis(static_cast<float>(m.heading), glm::vec3(0, 1, 0)) * out.rotations[0];
}

void ScenePoser::pose(int character, double t, Pose& out) const {
    if (scene_.isCreature(character)) {
        const auto& c = scene_.characters[static_cast<std::size_t>(character)];
        const RootXf at = creatureAt(c, t);
        out.translations.assign(1, glm::vec3(at.pos.x, creatureHeightAt(c, t), at.pos.y));
        out.rotations.assign(1, creatureRotation(at.heading, creaturePitchAt(c, t)));
        return;
    }
    const int i = scene_.instanceAt(character, t);
    if (i < 0) return;
    rawPose(character, i, t, out);
    const auto& track = scene_.characters[static_cast<std::size_t>(character)].track;
    const auto& inst = track[static_cast<std::size_t>(i)];
    // A looped instance's repetitions meet at seams of their own: the clip's
    // end (where the previous repetition leaves off) blends into its start.
    const int k = inst.repeatAt(t);
    const double seamTime = inst.repeatStart(k);
    const double x = (t - seamTime) / blend_;
    if ((i == 0 && k == 0) || blend_ <= 0 || x >= 1.0 || x < 0.0) return;
    // Offsets from the previous action's pose at the seam, fading out.
    Pose prev, seam;
    if (k > 0) {
        rawPoseAt(character, i, inst.offset + (seamTime - inst.repeatStart(k - 1)), prev);
    } else {
        rawPose(character, i - 1, inst.start, prev);
    }
    rawPoseAt(character, i, inst.offset, seam);
    const float w = static_cast<float>(1.0 - x * x * (3.0 - 2.0 * x));
    for (std::size_t j = 0; j < out.rotations.size(); ++j) {
        const glm::quat off = prev.rotations[j] * glm::inverse(seam.rotations[j]);
        out.rotations[j] = glm::normalize(glm::slerp(glm::quat(1, 0, 0, 0), off, w) * out.rotations[j]);
        out.translations[j] += w * (prev.translations[j] - seam.translations[j]);
    }
}

void ScenePoser::worldPositions(int character, double t, std::vector<glm::vec3>& out) const {
    Pose p;
    pose(character, t, p);
    const auto& sk = skeleton(character);
    out.resize(p.translations.size());
    std::vector<glm::quat> rot(p.translations.size());
    forwardKinematics(sk, p.translations, p.rotations, out, rot);
}

std::array<bool, 2> ScenePoser::contacts(int character, double t) const {
    if (scene_.isCreature(character)) return {false, false};
    const int i = scene_.instanceAt(character, t);
    if (i < 0) return {false, false};
    const auto& inst = scene_.characters[static_cast<std::size_t>(character)].track[static_cast<std::size_t>(i)];
    const auto& a = lib_.actions()[static_cast<std::size_t>(inst.action)];
    const auto& c = lib_.motion(a.motion).contacts;
    const int f = lib_.frameAt(inst.action, inst.offset + (t - inst.repeatStart(inst.repeatAt(t))));
    if (f < 0 || f >= c.frameCount()) return {false, false};
    return {c.left[static_cast<std::size_t>(f)] != 0, c.right[static_cast<std::size_t>(f)] != 0};
}

}  // namespace fray::sim
