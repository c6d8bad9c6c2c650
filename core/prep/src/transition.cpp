#include "fray/prep/transition.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>

#include "fray/core/ik.h"
#include "fray/core/kinematics.h"

namespace fray::prep {
namespace {

// Rotation vector (axis * angle, shortest way) of q, and back.
glm::vec3 rotationVector(glm::quat q) {
    if (q.w < 0.0f) q = -q;
    const glm::vec3 v(q.x, q.y, q.z);
    const float s = glm::length(v);
    if (s < 1e-7f) return 2.0f * v;
    return v * (2.0f * std::atan2(s, q.w) / s);
}

glm::quat rotationFromVector(const glm::vec3& v) {
    const float angle = glm::length(v);
    if (angle < 1e-7f) return glm::normalize(glm::quat(1.0f, 0.5f * v.x, 0.5f * v.y, 0.5f * v.z));
    return glm::angleAxis(angle, v / angle);
}

float smoothstep01(float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

double wrapAngle(double a) {
    const double twoPi = 2.0 * glm::pi<double>();
    a = std::fmod(a + glm::pi<double>(), twoPi);
    if (a < 0.0) a += twoPi;
    return a - glm::pi<double>();
}

std::optional<std::string> badRange(const Motion& m, ActionRef r, const char* name) {
    if (r.firstFrame < 0 || r.lastFrame < r.firstFrame || r.lastFrame >= m.frameCount())
        return std::string("join: action ") + name + " frames " + std::to_string(r.firstFrame) + ".." +
               std::to_string(r.lastFrame) + " are not a range inside its motion (frames 0.." +
               std::to_string(m.frameCount() - 1) + ")";
    return std::nullopt;
}

bool isAncestor(const Skeleton& s, int ancestor, int joint) {
    for (int j = joint; j >= 0; j = s.parents[static_cast<std::size_t>(j)])
        if (j == ancestor) return true;
    return false;
}

// The roles a join needs, as one comparable tuple.
std::array<int, 9> joinRoles(const StandardJoints& j) {
    return {j.pelvis, j.leftHip, j.rightHip, j.leftKnee, j.rightKnee, j.leftFoot, j.rightFoot, j.leftToe, j.rightToe};
}

// Foot locking: a target is within reach when the hip-ankle distance is at
// most this share of the leg (or of the leg's own extension, when B's pose
// is straighter); beyond it the knee of an almost straight leg snaps.
constexpr float kReach = 0.98f;
constexpr float kMaxDrop = 0.25f;            // share of the leg the pelvis may come down
constexpr double kDropSmoothSeconds = 0.1;   // pelvis drop eases in and out over about this

// How far the hip must come down (straight down) so that target is within r of it.
float requiredDrop(const glm::vec3& hip, const glm::vec3& target, float r) {
    const float dx = target.x - hip.x, dz = target.z - hip.z;
    const float below = hip.y - target.y;
    const float h2 = dx * dx + dz * dz;
    if (h2 >= r * r) return 0.0f;  // out of reach sideways: coming down does not help
    return std::max(0.0f, below - std::sqrt(r * r - h2));
}

// Frame k of motion m; before frame 0, the first step continued backwards
// at constant velocity (for actions that start their motion).
void sourceFrame(const Motion& m, int k, std::span<glm::vec3> t, std::span<glm::quat> r) {
    const auto jc = static_cast<std::size_t>(m.jointCount());
    if (k >= 0 || m.frameCount() < 2) {
        k = std::max(k, 0);
        std::copy_n(m.translations(k).begin(), jc, t.begin());
        std::copy_n(m.rotations(k).begin(), jc, r.begin());
        return;
    }
    const auto t0 = m.translations(0), t1 = m.translations(1);
    const auto r0 = m.rotations(0), r1 = m.rotations(1);
    const auto steps = static_cast<float>(-k);
    for (std::size_t j = 0; j < jc; ++j) {
        t[j] = t0[j] + steps * (t0[j] - t1[j]);
        const glm::vec3 back = rotationVector(r0[j] * glm::inverse(r1[j]));
        r[j] = glm::normalize(rotationFromVector(steps * back) * r0[j]);
    }
}

struct FootLock {
    enum class Mode { Free, Locked, Releasing } mode = Mode::Free;
    glm::vec3 pos{0.0f};     // where the ankle was when the lock began
    glm::quat rot{1, 0, 0, 0};
    glm::vec3 refPos{0.0f};  // B's own (unblended) ankle at that frame
    glm::quat refRot{1, 0, 0, 0};
    int releaseStart = 0;
};

}  // namespace

FootContacts estimateContacts(const Motion& motion, const StandardJoints& joints) {
    FootContacts out;
    const auto frames = static_cast<std::size_t>(std::max(0, motion.frameCount()));
    out.left.assign(frames, 0);
    out.right.assign(frames, 0);
    auto signals = computeSignals(motion, joints);
    if (!signals) return out;
    constexpr float kHeight = 0.05f, kSpeed = 0.4f;
    for (Foot foot : {Foot::Left, Foot::Right}) {
        const auto side = static_cast<std::size_t>(foot);
        for (std::size_t f = 0; f < frames; ++f)
            out.foot(foot)[f] = signals->footHeight[side][f] < kHeight && signals->footSpeed[side][f] < kSpeed;
    }
    return out;
}

SkateStats footSkate(const Motion& motion, const StandardJoints& joints, const FootContacts& contacts,
                     int firstFrame, int lastFrame) {
    SkateStats out;
    firstFrame = std::max(firstFrame, 0);
    lastFrame = std::min({lastFrame, motion.frameCount() - 1, contacts.frameCount() - 1});
    if (lastFrame <= firstFrame || !joints.hasFeet()) return out;
    const std::vector<glm::vec3> world = worldPositions(motion, firstFrame, lastFrame);
    const auto jc = static_cast<std::size_t>(motion.jointCount());
    auto moved = [&](int f, int joint) {
        const auto j = static_cast<std::size_t>(joint);
        const glm::dvec3 d = glm::dvec3(world[static_cast<std::size_t>(f - firstFrame) * jc + j]) -
                             glm::dvec3(world[static_cast<std::size_t>(f - 1 - firstFrame) * jc + j]);
        return std::sqrt(d.x * d.x + d.z * d.z);
    };
    double sum = 0.0;
    for (int f = firstFrame + 1; f <= lastFrame; ++f) {
        for (Foot foot : {Foot::Left, Foot::Right}) {
            const auto& c = contacts.foot(foot);
            if (!c[static_cast<std::size_t>(f)] || !c[static_cast<std::size_t>(f - 1)]) continue;
            const int ankle = foot == Foot::Left ? joints.leftFoot : joints.rightFoot;
            const int toe = foot == Foot::Left ? joints.leftToe : joints.rightToe;
            double m = moved(f, ankle);
            if (toe >= 0) m = std::max(m, moved(f, toe));
            out.maxPerFrame = std::max(out.maxPerFrame, m);
            sum += m;
            ++out.frames;
        }
    }
    if (out.frames > 0) out.meanPerFrame = sum / out.frames;
    return out;
}

Result<JoinedActions> joinActions(const Motion& a, const StandardJoints& ja, ActionRef actionA,
                                  const FootContacts* contactsA, const Motion& b, const StandardJoints& jb,
                                  ActionRef actionB, const FootContacts* contactsB, const TransitionOptions& options) {
    const Skeleton& skel = a.skeleton();
    if (skel.names != b.skeleton().names || skel.parents != b.skeleton().parents)
        return makeError("join: the two motions have different skeletons (joint names or hierarchy)");
    if (std::abs(a.fps() - b.fps()) > 1e-6)
        return makeError("join: frame rates differ (" + std::to_string(a.fps()) + " vs " + std::to_string(b.fps()) +
                         "); resample first");
    if (auto e = badRange(a, actionA, "A")) return makeError(*e);
    if (auto e = badRange(b, actionB, "B")) return makeError(*e);
    if (joinRoles(ja) != joinRoles(jb)) return makeError("join: the standard joints of the two motions differ");
    if (ja.pelvis < 0 || ja.leftHip < 0 || ja.rightHip < 0 || !ja.hasFeet())
        return makeError("join: needs the pelvis, hips and feet (missing: " + ja.missing() + ")");
    const int hips[2] = {ja.leftHip, ja.rightHip};
    const int knees[2] = {ja.leftKnee, ja.rightKnee};
    const int ankles[2] = {ja.leftFoot, ja.rightFoot};
    if (options.footLocking) {
        for (int s = 0; s < 2; ++s) {
            if (knees[s] < 0 || !isAncestor(skel, hips[s], knees[s]) || !isAncestor(skel, knees[s], ankles[s]))
                return makeError("join: foot locking needs hip -> knee -> ankle chains in the skeleton");
        }
    }
    for (auto [c, m, name] : {std::tuple{contactsA, &a, "A"}, std::tuple{contactsB, &b, "B"}}) {
        if (c && (c->left.size() != static_cast<std::size_t>(m->frameCount()) || c->right.size() != c->left.size()))
            return makeError(std::string("join: contacts of ") + name + " do not have one entry per frame (" +
                             std::to_string(m->frameCount()) + ")");
    }
    FootContacts estimatedA, estimatedB;
    if (!contactsA) estimatedA = estimateContacts(a, ja);
    if (!contactsB) estimatedB = estimateContacts(b, jb);
    const FootContacts& ca = contactsA ? *contactsA : estimatedA;
    const FootContacts& cb = contactsB ? *contactsB : estimatedB;

    const int nA = actionA.lastFrame - actionA.firstFrame + 1;
    const int nB = actionB.lastFrame - actionB.firstFrame + 1;
    const int seam = nA;
    const auto jc = static_cast<std::size_t>(skel.jointCount());
    const auto pelvis = static_cast<std::size_t>(ja.pelvis);
    std::vector<glm::vec3> pos(jc);
    std::vector<glm::quat> rot(jc);

    // The two frames before B's first (B's own, or its first step run
    // backwards where B starts its motion). B's previous frame is placed over
    // A's last, and the blend starts from the difference between them.
    std::vector<glm::vec3> prevBT(jc), prev2BT(jc);
    std::vector<glm::quat> prevBR(jc), prev2BR(jc);
    sourceFrame(b, actionB.firstFrame - 1, prevBT, prevBR);
    sourceFrame(b, actionB.firstFrame - 2, prev2BT, prev2BR);

    // 1. Placement: B's previous frame onto A's last (pelvis on the floor, heading).
    worldTransforms(a, actionA.lastFrame, pos, rot);
    const double yawA = headingOf(pos, ja);
    const glm::dvec3 pA(pos[pelvis]);
    forwardKinematics(skel, prevBT, prevBR, pos, rot);
    const double yawB = headingOf(pos, ja);
    const glm::dvec3 pB(pos[pelvis]);
    const glm::dquat turn = glm::angleAxis(wrapAngle(yawA - yawB), glm::dvec3(0, 1, 0));
    glm::dvec3 shift = pA - turn * pB;
    shift.y = 0.0;
    auto place = [&](glm::vec3& rootT, glm::quat& rootR) {
        rootT = glm::vec3(turn * glm::dvec3(rootT) + shift);
        rootR = glm::normalize(glm::quat(turn) * rootR);
    };
    place(prevBT[0], prevBR[0]);
    place(prev2BT[0], prev2BR[0]);

    JoinedActions out;
    out.motion = Motion(skel, a.fps(), nA + nB);
    out.seam = seam;
    out.contacts.left.resize(static_cast<std::size_t>(nA + nB));
    out.contacts.right.resize(static_cast<std::size_t>(nA + nB));
    for (int i = 0; i < nA + nB; ++i) {
        const bool fromA = i < nA;
        const Motion& src = fromA ? a : b;
        const int f = fromA ? actionA.firstFrame + i : actionB.firstFrame + i - nA;
        auto t = out.motion.translations(i);
        auto r = out.motion.rotations(i);
        std::copy_n(src.translations(f).begin(), jc, t.begin());
        std::copy_n(src.rotations(f).begin(), jc, r.begin());
        if (!fromA) place(t[0], r[0]);
        const FootContacts& c = fromA ? ca : cb;
        out.contacts.left[static_cast<std::size_t>(i)] = c.left[static_cast<std::size_t>(f)];
        out.contacts.right[static_cast<std::size_t>(i)] = c.right[static_cast<std::size_t>(f)];
    }

    // B's own feet, placed but not blended: the path a locked foot follows.
    std::array<std::vector<glm::vec3>, 2> natPos;
    std::array<std::vector<glm::quat>, 2> natRot;
    for (std::size_t s = 0; s < 2; ++s) {
        natPos[s].resize(static_cast<std::size_t>(nB));
        natRot[s].resize(static_cast<std::size_t>(nB));
    }
    for (int i = 0; i < nB; ++i) {
        worldTransforms(out.motion, seam + i, pos, rot);
        for (std::size_t s = 0; s < 2; ++s) {
            natPos[s][static_cast<std::size_t>(i)] = pos[static_cast<std::size_t>(ankles[s])];
            natRot[s][static_cast<std::size_t>(i)] = rot[static_cast<std::size_t>(ankles[s])];
        }
    }

    // 2. Blend (inertialisation): the offset x0 = A's last pose - B's previous
    // pose and its rate v0 = A's velocity into its last frame - B's velocity
    // into its previous frame (the same instant once placed) decay to zero
    // along a cubic with zero value and slope at the end. The seam keeps A's
    // position and velocity (plus B's own acceleration); B plays unchanged
    // after the window, and consecutive actions come back as they were.
    std::vector<glm::vec3> seamPos(jc), pelvisTmp(jc);
    std::vector<glm::quat> seamRot(jc), rotTmp(jc);
    worldTransforms(out.motion, seam - 1, seamPos, seamRot);
    auto pelvisOf = [&](std::span<const glm::vec3> t, std::span<const glm::quat> r) {
        forwardKinematics(skel, t, r, pelvisTmp, rotTmp);
        return pelvisTmp[pelvis];
    };
    // A's frame before its last; A counts as still when it starts its motion with one frame.
    const int prevAFrame = std::max(0, actionA.lastFrame - 1);
    const auto lastAT = out.motion.translations(seam - 1);
    const auto lastAR = out.motion.rotations(seam - 1);
    const auto prevAT = a.translations(prevAFrame);
    const auto prevAR = a.rotations(prevAFrame);
    const glm::vec3 pelvisLastA = seamPos[pelvis];
    const glm::vec3 pelvisPrevA = pelvisOf(prevAT, prevAR);
    const glm::vec3 pelvisPrevB = pelvisOf(prevBT, prevBR);
    const glm::vec3 pelvisPrev2B = pelvisOf(prev2BT, prev2BR);
    const glm::vec3 rootX0 = pelvisLastA - pelvisPrevB;
    const glm::vec3 rootV0 = (pelvisLastA - pelvisPrevA) - (pelvisPrevB - pelvisPrev2B);
    std::vector<glm::vec3> rotX0(jc), rotV0(jc), tX0(jc, glm::vec3(0.0f)), tV0(jc, glm::vec3(0.0f));
    for (std::size_t j = 0; j < jc; ++j) {
        rotX0[j] = rotationVector(lastAR[j] * glm::inverse(prevBR[j]));
        rotV0[j] = rotationVector(lastAR[j] * glm::inverse(prevAR[j])) -
                   rotationVector(prevBR[j] * glm::inverse(prev2BR[j]));
        // Root and pelvis positions are blended in world space (rootX0 / rootV0).
        if (j != 0 && j != pelvis) {
            tX0[j] = lastAT[j] - prevBT[j];
            tV0[j] = (lastAT[j] - prevAT[j]) - (prevBT[j] - prev2BT[j]);
        }
    }
    const int blend = std::clamp(static_cast<int>(std::lround(options.blendSeconds * a.fps())), 1, nB);
    out.blendFrames = blend;
    for (int i = 0; i < blend; ++i) {
        // Hermite basis on s in (0, 1): value x0 and slope v0 (per frame) at
        // s = 0, zero value and slope at s = 1; the window is blend+1 frames long.
        const float s = static_cast<float>(i + 1) / static_cast<float>(blend + 1);
        const float h00 = (2.0f * s - 3.0f) * s * s + 1.0f;
        const float h10 = ((s - 2.0f) * s + 1.0f) * s * static_cast<float>(blend + 1);
        auto t = out.motion.translations(seam + i);
        auto r = out.motion.rotations(seam + i);
        for (std::size_t j = 0; j < jc; ++j) {
            r[j] = glm::normalize(rotationFromVector(h00 * rotX0[j] + h10 * rotV0[j]) * r[j]);
            t[j] += h00 * tX0[j] + h10 * tV0[j];
        }
        t[0] += h00 * rootX0 + h10 * rootV0;
    }
    out.lastAdjusted = seam + blend - 1;

    // 3. Foot locking, in two passes. The first plans, per frame and foot,
    // where the ankle must be (pos, world rotation) and how far the pelvis
    // must come down for every target to be within reach: a locked foot can
    // end up further from the hip than B's leg reaches, and a nearly
    // straight leg makes the knee snap. The second lowers the pelvis by a
    // smoothed drop and solves the legs; while the pelvis is lowered, every
    // foot is held where it was, so the drop never moves a foot.
    if (options.footLocking) {
        const int frames = nA + nB;
        const int release = std::max(1, static_cast<int>(std::lround(options.releaseSeconds * a.fps())));
        const int smoothing = std::max(1, static_cast<int>(std::lround(kDropSmoothSeconds * a.fps())));
        struct Plan {
            bool held = false;  // locked or releasing
            glm::vec3 pos{0.0f};
            glm::quat rot{1, 0, 0, 0};
        };
        std::vector<std::array<Plan, 2>> plan;
        std::vector<float> drop;
        std::array<FootLock, 2> locks;
        int planned = seam;  // one past the last planned frame
        for (int f = seam; f < frames; ++f) {
            const int i = f - seam;
            if (i >= blend && locks[0].mode == FootLock::Mode::Free && locks[1].mode == FootLock::Mode::Free) break;
            worldTransforms(out.motion, f, pos, rot);
            std::array<Plan, 2>& fp = plan.emplace_back();
            float need = 0.0f;
            for (std::size_t s = 0; s < 2; ++s) {
                FootLock& L = locks[s];
                const auto ankle = static_cast<std::size_t>(ankles[s]);
                const auto& c = out.contacts.foot(static_cast<Foot>(s));
                const bool contact = c[static_cast<std::size_t>(f)] != 0;
                const auto ii = static_cast<std::size_t>(i);
                auto startLock = [&](const glm::vec3& p, const glm::quat& q) {
                    L.mode = FootLock::Mode::Locked;
                    L.pos = p;
                    L.rot = q;
                    L.refPos = natPos[s][ii];
                    L.refRot = natRot[s][ii];
                };
                fp[s].pos = pos[ankle];
                fp[s].rot = rot[ankle];
                if (L.mode == FootLock::Mode::Free) {
                    if (!contact || i >= blend) continue;
                    // Planted across the seam: hold it where A left it (toe included).
                    if (f == seam && c[static_cast<std::size_t>(seam - 1)])
                        startLock(seamPos[ankle], seamRot[ankle]);
                    else
                        startLock(pos[ankle], rot[ankle]);
                } else if (L.mode == FootLock::Mode::Locked && !contact) {
                    L.mode = FootLock::Mode::Releasing;
                    L.releaseStart = f;
                }
                // Follow B's own foot from where the lock began: B's foot is
                // planted, so the held foot is too, rolling as B's does.
                glm::vec3 tp = L.pos + (natPos[s][ii] - L.refPos);
                glm::quat tq = glm::normalize(natRot[s][ii] * glm::inverse(L.refRot) * L.rot);
                if (L.mode == FootLock::Mode::Releasing) {
                    const int k = f - L.releaseStart;
                    if (k >= release) {
                        L.mode = FootLock::Mode::Free;
                        continue;
                    }
                    const float beta = smoothstep01(static_cast<float>(k + 1) / static_cast<float>(release + 1));
                    tp = glm::mix(tp, pos[ankle], beta);
                    tq = glm::slerp(tq, rot[ankle], beta);
                    if (contact) startLock(tp, tq);  // down again before the release ended: hold it here
                }
                fp[s] = Plan{true, tp, tq};
                const auto hip = static_cast<std::size_t>(hips[s]);
                const auto knee = static_cast<std::size_t>(knees[s]);
                const float reach = glm::length(pos[knee] - pos[hip]) + glm::length(pos[ankle] - pos[knee]);
                const float r = std::max(kReach * reach, glm::length(pos[ankle] - pos[hip]));
                need = std::max(need, std::min(kMaxDrop * reach, requiredDrop(pos[hip], tp, r)));
            }
            drop.push_back(need);
            planned = f + 1;
        }
        // Smooth the drop so that it never falls below what a frame needs:
        // widen every need over 2 * smoothing frames, then average twice over
        // +-smoothing frames (a triangle kernel of the same total width).
        const int extra = planned > seam ? 2 * smoothing : 0;
        const int span = std::min(frames, planned + extra) - seam;
        std::vector<float> widened(static_cast<std::size_t>(span), 0.0f);
        for (int i = 0; i < static_cast<int>(drop.size()); ++i) {
            if (drop[static_cast<std::size_t>(i)] <= 0.0f) continue;
            for (int k = std::max(0, i - 2 * smoothing); k <= std::min(span - 1, i + 2 * smoothing); ++k)
                widened[static_cast<std::size_t>(k)] =
                    std::max(widened[static_cast<std::size_t>(k)], drop[static_cast<std::size_t>(i)]);
        }
        auto boxFilter = [&](const std::vector<float>& in) {
            std::vector<float> o(in.size(), 0.0f);
            for (int i = 0; i < span; ++i) {
                double sum = 0.0;
                for (int k = i - smoothing; k <= i + smoothing; ++k)
                    if (k >= 0 && k < span) sum += static_cast<double>(in[static_cast<std::size_t>(k)]);
                o[static_cast<std::size_t>(i)] = static_cast<float>(sum / (2 * smoothing + 1));
            }
            return o;
        };
        const std::vector<float> smooth = boxFilter(boxFilter(widened));

        for (int i = 0; i < span; ++i) {
            const int f = seam + i;
            const float d = smooth[static_cast<std::size_t>(i)];
            const bool planned_ = i < static_cast<int>(plan.size());
            if (d <= 0.0f && (!planned_ || (!plan[static_cast<std::size_t>(i)][0].held &&
                                             !plan[static_cast<std::size_t>(i)][1].held)))
                continue;
            // Feet not planned here (after the locks) stay where they are before the drop.
            std::array<Plan, 2> fp;
            if (planned_) {
                fp = plan[static_cast<std::size_t>(i)];
            } else {
                worldTransforms(out.motion, f, pos, rot);
                for (std::size_t s = 0; s < 2; ++s)
                    fp[s] =
                        Plan{false, pos[static_cast<std::size_t>(ankles[s])], rot[static_cast<std::size_t>(ankles[s])]};
            }
            out.motion.translations(f)[0].y -= d;
            worldTransforms(out.motion, f, pos, rot);
            for (std::size_t s = 0; s < 2; ++s) {
                if (!fp[s].held && d <= 0.0f) continue;
                const bool reached = applyTwoBoneIk(skel, out.motion.rotations(f), pos, rot, hips[s], knees[s],
                                                    ankles[s], fp[s].pos, &fp[s].rot);
                if (fp[s].held) out.ikReached &= reached;
            }
            out.lastAdjusted = std::max(out.lastAdjusted, f);
        }
    }
    return out;
}

}  // namespace fray::prep
