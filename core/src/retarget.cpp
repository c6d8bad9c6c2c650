// Retargeting between skeletons (see fray/core/retarget.h for the method).
#include "fray/core/retarget.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "fray/core/ik.h"
#include "fray/core/kinematics.h"

namespace fray {
namespace {

using SJ = StandardJoints;

struct Role {
    const char* name;
    int SJ::*member;
};

// Order matters: a joint two roles share (CMU's thorax is both spine and
// chest) goes to the first.
constexpr std::array<Role, 19> kRoles = {{{"pelvis", &SJ::pelvis},
                                          {"chest", &SJ::chest},
                                          {"spine", &SJ::spine},
                                          {"neck", &SJ::neck},
                                          {"head", &SJ::head},
                                          {"leftHip", &SJ::leftHip},
                                          {"leftKnee", &SJ::leftKnee},
                                          {"leftFoot", &SJ::leftFoot},
                                          {"leftToe", &SJ::leftToe},
                                          {"rightHip", &SJ::rightHip},
                                          {"rightKnee", &SJ::rightKnee},
                                          {"rightFoot", &SJ::rightFoot},
                                          {"rightToe", &SJ::rightToe},
                                          {"leftShoulder", &SJ::leftShoulder},
                                          {"leftElbow", &SJ::leftElbow},
                                          {"leftHand", &SJ::leftHand},
                                          {"rightShoulder", &SJ::rightShoulder},
                                          {"rightElbow", &SJ::rightElbow},
                                          {"rightHand", &SJ::rightHand}}};

enum R : int {
    Pelvis,
    Chest,
    Spine,
    Neck,
    Head,
    LHip,
    LKnee,
    LFoot,
    LToe,
    RHip,
    RKnee,
    RFoot,
    RToe,
    LShoulder,
    LElbow,
    LHand,
    RShoulder,
    RElbow,
    RHand,
    RoleCount
};
static_assert(RoleCount == kRoles.size());

using RoleJoints = std::array<int, RoleCount>;

RoleJoints rolesOf(const StandardJoints& sj) {
    RoleJoints out{};
    for (std::size_t r = 0; r < kRoles.size(); ++r) out[r] = sj.*(kRoles[r].member);
    return out;
}

// A rotation whose Y axis is `primary` and whose X axis is `secondary` made
// perpendicular to it (columns X, Y, Z = X x Y).
glm::dquat frameFrom(const glm::dvec3& primary, const glm::dvec3& secondary) {
    const double lp = glm::length(primary);
    const glm::dvec3 y = lp > 1e-12 ? primary / lp : glm::dvec3(0, 1, 0);
    glm::dvec3 x = secondary - y * glm::dot(secondary, y);
    if (glm::length(x) < 1e-9 * std::max(1.0, glm::length(secondary))) {
        x = glm::cross(y, glm::dvec3(0, 0, 1));
        if (glm::length(x) < 1e-6) x = glm::cross(y, glm::dvec3(1, 0, 0));
    }
    x = glm::normalize(x);
    const glm::dvec3 z = glm::cross(x, y);
    return glm::normalize(glm::quat_cast(glm::dmat3(x, y, z)));
}

// Anatomical frames of the mapped roles from world positions (roles not
// mapped, -1 in `rj`, are not used, so both skeletons build them alike).
class FrameBuilder {
public:
    explicit FrameBuilder(const RoleJoints& rj) : rj_(rj) {}

    // Frames of every mapped role; `has[r]` says which were built.
    void build(const std::vector<glm::vec3>& pos, std::array<glm::dquat, RoleCount>& out) const {
        auto P = [&](int r) { return glm::dvec3(pos[static_cast<std::size_t>(rj_[static_cast<std::size_t>(r)])]); };
        auto on = [&](int r) { return rj_[static_cast<std::size_t>(r)] >= 0; };
        const int up = firstOf({Chest, Spine, Neck, Head});
        const glm::dvec3 left = P(LHip) - P(RHip);
        const glm::dvec3 upVec = up >= 0 ? P(up) - P(Pelvis) : glm::dvec3(0, 1, 0);
        const glm::dquat body = frameFrom(upVec, left);
        const glm::dvec3 forward = body * glm::dvec3(0, 0, 1);
        const glm::dvec3 bodyUp = body * glm::dvec3(0, 1, 0);
        out[Pelvis] = body;
        const glm::dvec3 shoulderLeft = on(LShoulder) && on(RShoulder) ? P(LShoulder) - P(RShoulder) : left;
        // Torso: the next mapped joint up gives the bone.
        const std::array<int, 4> torso = {Spine, Chest, Neck, Head};
        glm::dquat chestFrame = body;
        for (std::size_t i = 0; i < torso.size(); ++i) {
            const int r = torso[i];
            if (!on(r)) continue;
            int next = -1;
            for (std::size_t k = i + 1; k < torso.size() && next < 0; ++k)
                if (on(torso[k])) next = torso[k];
            const glm::dvec3 side = r == Spine ? glm::normalize(left) + safeNormalize(shoulderLeft) : shoulderLeft;
            if (next >= 0) {
                out[static_cast<std::size_t>(r)] = frameFrom(P(next) - P(r), side);
            } else {
                // The top of the chain (the head): the bone that reaches it.
                int below = -1;
                for (std::size_t k = i; k-- > 0 && below < 0;)
                    if (on(torso[k])) below = torso[k];
                out[static_cast<std::size_t>(r)] = below >= 0 ? frameFrom(P(r) - P(below), side) : body;
            }
            if (r == Chest || (r == Spine && !on(Chest))) chestFrame = out[static_cast<std::size_t>(r)];
        }
        const glm::dvec3 chestForward = chestFrame * glm::dvec3(0, 0, 1);
        const glm::dvec3 chestUp = chestFrame * glm::dvec3(0, 1, 0);
        limb(pos, out, LHip, LKnee, LFoot, LToe, forward, bodyUp, left, true);
        limb(pos, out, RHip, RKnee, RFoot, RToe, forward, bodyUp, left, true);
        limb(pos, out, LShoulder, LElbow, LHand, -1, chestForward, chestUp, shoulderLeft, false);
        limb(pos, out, RShoulder, RElbow, RHand, -1, chestForward, chestUp, shoulderLeft, false);
    }

private:
    static glm::dvec3 safeNormalize(const glm::dvec3& v) {
        const double l = glm::length(v);
        return l > 1e-12 ? v / l : glm::dvec3(0.0);
    }

    int firstOf(std::initializer_list<int> roles) const {
        for (int r : roles)
            if (rj_[static_cast<std::size_t>(r)] >= 0) return r;
        return -1;
    }

    // Upper bone, lower bone, end (ankle / wrist) and, for legs, the toe. The
    // second axis is the limb's bending axis; near-straight limbs fall back on
    // a body axis that agrees with it for a normal bend (so the twist stays
    // continuous).
    void limb(const std::vector<glm::vec3>& pos, std::array<glm::dquat, RoleCount>& out, int upper, int mid, int end,
              int toe, const glm::dvec3& forward, const glm::dvec3& up, const glm::dvec3& left, bool leg) const {
        auto on = [&](int r) { return r >= 0 && rj_[static_cast<std::size_t>(r)] >= 0; };
        auto P = [&](int r) { return glm::dvec3(pos[static_cast<std::size_t>(rj_[static_cast<std::size_t>(r)])]); };
        if (!on(upper) || !on(mid)) return;
        const glm::dvec3 a = P(mid) - P(upper);
        const glm::dvec3 b = on(end) ? P(end) - P(mid) : a;
        const double la = glm::length(a), lb = glm::length(b);
        const glm::dvec3 ua = safeNormalize(a);
        glm::dvec3 hinge = glm::cross(a, b);
        if (leg) hinge += 0.25 * la * lb * glm::cross(forward, ua) + 0.05 * la * lb * safeNormalize(left);
        else hinge += 0.25 * la * lb * glm::cross(ua, forward) - 0.05 * la * lb * safeNormalize(up);
        out[static_cast<std::size_t>(upper)] = frameFrom(a, hinge);
        out[static_cast<std::size_t>(mid)] = on(end) ? frameFrom(b, hinge) : out[static_cast<std::size_t>(upper)];
        if (!on(end)) return;
        out[static_cast<std::size_t>(end)] = on(toe) ? frameFrom(P(toe) - P(end), hinge) : out[static_cast<std::size_t>(mid)];
        if (on(toe)) out[static_cast<std::size_t>(toe)] = out[static_cast<std::size_t>(end)];
    }

    RoleJoints rj_;
};

double legLength(const std::vector<glm::vec3>& pos, const StandardJoints& sj) {
    auto at = [&](int j) { return pos[static_cast<std::size_t>(j)]; };
    const double l = glm::length(at(sj.leftKnee) - at(sj.leftHip)) + glm::length(at(sj.leftFoot) - at(sj.leftKnee));
    const double r = glm::length(at(sj.rightKnee) - at(sj.rightHip)) + glm::length(at(sj.rightFoot) - at(sj.rightKnee));
    return 0.5 * (l + r);
}

std::string listJoints(const Skeleton& sk) {
    std::string out;
    const int n = sk.jointCount();
    for (int j = 0; j < n && j < 24; ++j) out += (j ? ", " : "") + sk.names[static_cast<std::size_t>(j)];
    if (n > 24) out += " and " + std::to_string(n - 24) + " more";
    return out;
}

// Runs shorter than minRun frames removed, gaps shorter than minRun filled.
void cleanRuns(std::vector<std::uint8_t>& c, int minRun) {
    const int n = static_cast<int>(c.size());
    for (int pass = 0; pass < 2; ++pass) {
        const std::uint8_t value = pass == 0 ? 0 : 1;  // first fill gaps, then drop slivers
        int i = 0;
        while (i < n) {
            if (c[static_cast<std::size_t>(i)] != value) {
                ++i;
                continue;
            }
            int k = i;
            while (k < n && c[static_cast<std::size_t>(k)] == value) ++k;
            const bool inner = pass == 1 || (i > 0 && k < n);
            if (k - i < minRun && inner)
                for (int f = i; f < k; ++f) c[static_cast<std::size_t>(f)] = static_cast<std::uint8_t>(1 - value);
            i = k;
        }
    }
}

}  // namespace

RetargetTarget retargetTargetFromMotion(const Motion& motion, int frame, std::string name) {
    RetargetTarget t;
    t.skeleton = motion.skeleton();
    t.name = std::move(name);
    if (motion.frameCount() == 0) return retargetTargetFromRest(motion.skeleton(), t.name);
    frame = std::clamp(frame, 0, motion.frameCount() - 1);
    const auto tr = motion.translations(frame);
    const auto ro = motion.rotations(frame);
    t.translations.assign(tr.begin(), tr.end());
    t.rotations.assign(ro.begin(), ro.end());
    return t;
}

RetargetTarget retargetTargetFromRest(const Skeleton& skeleton, std::string name) {
    RetargetTarget t;
    t.skeleton = skeleton;
    t.name = std::move(name);
    t.translations = skeleton.offsets;
    t.rotations.assign(skeleton.offsets.size(), glm::quat(1, 0, 0, 0));
    return t;
}

FootContactTrack detectFootContacts(const Motion& motion, const StandardJoints& sj) {
    FootContactTrack out;
    const int n = motion.frameCount();
    if (!sj.hasFeet() || n == 0 || sj.leftKnee < 0 || sj.rightKnee < 0 || sj.leftHip < 0 || sj.rightHip < 0) return out;
    const auto jc = static_cast<std::size_t>(motion.jointCount());
    const std::vector<glm::vec3> pos = worldPositions(motion, 0, n - 1);
    std::vector<glm::vec3> first(pos.begin(), pos.begin() + static_cast<std::ptrdiff_t>(jc));
    const double scale = std::max(0.2, legLength(first, sj) / 0.85);
    const double fps = motion.fps() > 0 ? motion.fps() : 30.0;
    const int minRun = std::max(1, static_cast<int>(std::lround(0.06 * fps)));
    for (int side = 0; side < 2; ++side) {
        const auto foot = static_cast<std::size_t>(side ? sj.rightFoot : sj.leftFoot);
        std::vector<float> heights(static_cast<std::size_t>(n));
        for (int f = 0; f < n; ++f) heights[static_cast<std::size_t>(f)] = pos[static_cast<std::size_t>(f) * jc + foot].y;
        std::vector<float> sorted = heights;
        const auto k = sorted.size() / 20;
        std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
        const double floor = static_cast<double>(sorted[k]);
        std::vector<std::uint8_t> c(static_cast<std::size_t>(n), 0);
        for (int f = 0; f < n; ++f) {
            const int a = std::max(0, f - 1), b = std::min(n - 1, f + 1);
            glm::vec3 d = pos[static_cast<std::size_t>(b) * jc + foot] - pos[static_cast<std::size_t>(a) * jc + foot];
            d.y = 0.0f;
            const double speed = b > a ? static_cast<double>(glm::length(d)) * fps / (b - a) : 0.0;
            c[static_cast<std::size_t>(f)] = static_cast<double>(heights[static_cast<std::size_t>(f)]) - floor < 0.05 * scale && speed < 0.35 * scale;
        }
        cleanRuns(c, minRun);
        (side ? out.right : out.left) = std::move(c);
    }
    return out;
}

FootSkate measureFootSkate(const Motion& motion, const StandardJoints& sj, const FootContactTrack& contacts) {
    FootSkate s;
    const int n = motion.frameCount();
    if (!sj.hasFeet() || n < 2) return s;
    const auto jc = static_cast<std::size_t>(motion.jointCount());
    const std::vector<glm::vec3> pos = worldPositions(motion, 0, n - 1);
    double sum = 0.0;
    for (int side = 0; side < 2; ++side) {
        const auto& c = side ? contacts.right : contacts.left;
        const auto foot = static_cast<std::size_t>(side ? sj.rightFoot : sj.leftFoot);
        for (int f = 1; f < n && static_cast<std::size_t>(f) < c.size(); ++f) {
            if (!c[static_cast<std::size_t>(f)] || !c[static_cast<std::size_t>(f - 1)]) continue;
            glm::vec3 d = pos[static_cast<std::size_t>(f) * jc + foot] - pos[static_cast<std::size_t>(f - 1) * jc + foot];
            d.y = 0.0f;
            const double m = static_cast<double>(glm::length(d));
            sum += m;
            s.max = std::max(s.max, m);
            ++s.frames;
        }
    }
    s.mean = s.frames ? sum / s.frames : 0.0;
    return s;
}

bool sameSkeleton(const Skeleton& a, const Skeleton& b) { return a.names == b.names && a.parents == b.parents; }

Status checkRetargetable(const Skeleton& sk, const std::string& what) {
    if (sk.jointCount() == 0) return makeError(what + ": the skeleton has no joints");
    const StandardJoints sj = guessStandardJoints(sk);
    std::vector<std::string> missing;
    auto need = [&](int j, const char* role) {
        if (j < 0 || j == sj.pelvis) missing.push_back(role);
    };
    need(sj.leftFoot, "leftFoot");
    need(sj.rightFoot, "rightFoot");
    need(sj.leftKnee, "leftKnee");
    need(sj.rightKnee, "rightKnee");
    need(sj.leftHip, "leftHip");
    need(sj.rightHip, "rightHip");
    const bool feetMissing = sj.leftFoot < 0 || sj.rightFoot < 0;
    if (sj.chest < 0 && sj.spine < 0 && sj.neck < 0 && sj.head < 0) missing.push_back("spine/chest/neck/head");
    // Legs must be chains of distinct joints.
    const std::array<int, 6> legs = {sj.leftHip, sj.leftKnee, sj.leftFoot, sj.rightHip, sj.rightKnee, sj.rightFoot};
    for (std::size_t i = 0; i < legs.size() && missing.empty(); ++i)
        for (std::size_t k = i + 1; k < legs.size(); ++k)
            if (legs[i] == legs[k]) {
                missing.push_back("distinct leg joints (" + sk.names[static_cast<std::size_t>(legs[i])] + " plays two parts)");
                break;
            }
    if (missing.empty()) return {};
    std::string list;
    for (std::size_t i = 0; i < missing.size(); ++i) list += (i ? ", " : "") + missing[i];
    return makeError(what + ": cannot retarget: " + (feetMissing ? "no feet found" : "joints not found") + " (" + list +
                     "); its joints are " + listJoints(sk) +
                     " (joint names are matched as in docs/DATA_PREP.md, e.g. LeftFoot, l_ankle, lfoot, Foot_L)");
}

std::string RetargetReport::text() const {
    std::string out = "retargeted " + source + " onto " + target + ":\n";
    char buf[96];
    std::snprintf(buf, sizeof buf, "  scale %.3f (leg length ratio)\n", scale);
    out += buf;
    out += "  mapped " + std::to_string(mapped.size()) + ":";
    for (const auto& m : mapped) out += " " + m.role + " " + m.source + "->" + m.target + ";";
    out += "\n";
    auto list = [&](const char* what, const std::vector<std::string>& names) {
        out += std::string("  ") + what + " " + std::to_string(names.size()) + (names.empty() ? "" : ":");
        for (const auto& n : names) out += " " + n;
        out += "\n";
    };
    list("dropped (source joints that drive nothing)", droppedSource);
    list("held in the reference pose (target joints no source joint drives)", heldTarget);
    std::snprintf(buf, sizeof buf, "  feet held by IK on %d foot-frames (%d out of reach)", plantedFrames, unreachedFrames);
    out += buf;
    return out;
}

Result<Motion> retarget(const Motion& source, const RetargetTarget& target, const RetargetOptions& options,
                        RetargetReport* report) {
    const std::string srcName = source.source().path.empty() ? std::string("the source motion") : source.source().path;
    if (auto st = checkRetargetable(source.skeleton(), srcName); !st) return st.error();
    if (auto st = checkRetargetable(target.skeleton, target.name.empty() ? std::string("the target") : target.name); !st)
        return st.error();
    const Skeleton& tsk = target.skeleton;
    const int tj = tsk.jointCount();
    if (target.translations.size() != static_cast<std::size_t>(tj) || target.rotations.size() != static_cast<std::size_t>(tj))
        return makeError(target.name + ": the reference pose has " + std::to_string(target.rotations.size()) +
                         " joints but the skeleton " + std::to_string(tj));
    const int frames = source.frameCount();
    if (frames == 0) return makeError(srcName + ": no frames to retarget");

    // Mapping: roles both skeletons have, each joint used once per side.
    const StandardJoints ssj = guessStandardJoints(source.skeleton());
    const StandardJoints tsj = guessStandardJoints(tsk);
    const RoleJoints sAll = rolesOf(ssj), tAll = rolesOf(tsj);
    RoleJoints sr{}, tr{};
    sr.fill(-1);
    tr.fill(-1);
    std::vector<char> sUsed(static_cast<std::size_t>(source.jointCount()), 0), tUsed(static_cast<std::size_t>(tj), 0);
    RetargetReport rep;
    rep.source = srcName;
    rep.target = target.name;
    for (std::size_t r = 0; r < kRoles.size(); ++r) {
        const int s = sAll[r], t = tAll[r];
        if (s < 0 || t < 0 || sUsed[static_cast<std::size_t>(s)] || tUsed[static_cast<std::size_t>(t)]) continue;
        sr[r] = s;
        tr[r] = t;
        sUsed[static_cast<std::size_t>(s)] = tUsed[static_cast<std::size_t>(t)] = 1;
        rep.mapped.push_back({kRoles[r].name, source.skeleton().names[static_cast<std::size_t>(s)], tsk.names[static_cast<std::size_t>(t)]});
    }
    for (int j = 0; j < source.jointCount(); ++j)
        if (!sUsed[static_cast<std::size_t>(j)]) rep.droppedSource.push_back(source.skeleton().names[static_cast<std::size_t>(j)]);
    for (int j = 0; j < tj; ++j)
        if (!tUsed[static_cast<std::size_t>(j)]) rep.heldTarget.push_back(tsk.names[static_cast<std::size_t>(j)]);

    // Target reference pose: world transforms, anatomical frames, offsets.
    const auto tjs = static_cast<std::size_t>(tj);
    std::vector<glm::vec3> refPos(tjs), pos(tjs);
    std::vector<glm::quat> refRot(tjs), rot(tjs);
    forwardKinematics(tsk, target.translations, target.rotations, refPos, refRot);
    const FrameBuilder tFrames(tr), sFrames(sr);
    std::array<glm::dquat, RoleCount> tA{}, sA{};
    tFrames.build(refPos, tA);
    std::array<glm::dquat, RoleCount> offset{};
    for (std::size_t r = 0; r < kRoles.size(); ++r)
        if (tr[r] >= 0) offset[r] = glm::inverse(tA[r]) * glm::dquat(refRot[static_cast<std::size_t>(tr[r])]);
    std::vector<int> roleOfTarget(tjs, -1);
    for (std::size_t r = 0; r < kRoles.size(); ++r)
        if (tr[r] >= 0) roleOfTarget[static_cast<std::size_t>(tr[r])] = static_cast<int>(r);

    // Scale from the leg lengths.
    const auto sjc = static_cast<std::size_t>(source.jointCount());
    std::vector<glm::vec3> sPos(sjc);
    std::vector<glm::quat> sRot(sjc);
    worldTransforms(source, 0, sPos, sRot);
    const double sLeg = legLength(sPos, ssj), tLeg = legLength(refPos, tsj);
    if (!(sLeg > 1e-6) || !(tLeg > 1e-6))
        return makeError((sLeg > 1e-6 ? target.name : srcName) + ": cannot retarget: the legs have no length");
    const double scale = tLeg / sLeg;
    rep.scale = scale;

    Motion out(tsk, source.fps(), frames);
    out.source() = source.source();
    out.source().warnings.push_back("retargeted onto " + target.name);
    const int pelvis = tsj.pelvis;
    // The pelvis joint sits at different heights above the hip joints from
    // one source to another: the hip joints' midpoint is what is scaled.
    auto hipMid = [](const std::vector<glm::vec3>& p, const StandardJoints& sj) {
        return 0.5 * (glm::dvec3(p[static_cast<std::size_t>(sj.leftHip)]) + glm::dvec3(p[static_cast<std::size_t>(sj.rightHip)]));
    };
    const glm::dvec3 hipMidInPelvis = glm::inverse(glm::dquat(refRot[static_cast<std::size_t>(pelvis)])) *
                                      (hipMid(refPos, tsj) - glm::dvec3(refPos[static_cast<std::size_t>(pelvis)]));
    for (int f = 0; f < frames; ++f) {
        worldTransforms(source, f, sPos, sRot);
        sFrames.build(sPos, sA);
        const glm::dquat pelvisWorld = sA[Pelvis] * offset[Pelvis];
        const glm::dvec3 want = scale * hipMid(sPos, ssj) - pelvisWorld * hipMidInPelvis;
        auto T = out.translations(f);
        auto Q = out.rotations(f);
        for (int j = 0; j < tj; ++j) {
            const auto u = static_cast<std::size_t>(j);
            const int p = tsk.parents[u];
            const glm::dquat parentRot = p >= 0 ? glm::dquat(rot[static_cast<std::size_t>(p)]) : glm::dquat(1, 0, 0, 0);
            const glm::dvec3 parentPos = p >= 0 ? glm::dvec3(pos[static_cast<std::size_t>(p)]) : glm::dvec3(0.0);
            glm::dvec3 t = target.translations[u];
            glm::dquat q = target.rotations[u];
            if (roleOfTarget[u] >= 0) {
                const auto r = static_cast<std::size_t>(roleOfTarget[u]);
                q = glm::normalize(glm::inverse(parentRot) * (sA[r] * offset[r]));
            }
            if (j == pelvis) t = glm::inverse(parentRot) * (want - parentPos);
            T[u] = glm::vec3(t);
            Q[u] = glm::quat(q);
            pos[u] = glm::vec3(parentPos + parentRot * t);
            rot[u] = glm::quat(glm::normalize(parentRot * q));
        }
    }

    // Feet held through the source's contacts.
    if (options.plantFeet) {
        FootContactTrack detected;
        const FootContactTrack* contacts = options.contacts;
        if (!contacts || contacts->left.size() != static_cast<std::size_t>(frames) ||
            contacts->right.size() != static_cast<std::size_t>(frames)) {
            detected = detectFootContacts(source, ssj);
            contacts = &detected;
        }
        const double fps = source.fps() > 0 ? source.fps() : 30.0;
        const int ease = std::max(1, static_cast<int>(std::lround(0.1 * fps)));
        // Per foot and frame: the IK target and its weight (0 = leave as is).
        struct Plan {
            std::vector<glm::vec3> target;
            std::vector<float> weight;
        };
        std::array<Plan, 2> plans;
        const std::array<int, 2> ankles = {tsj.leftFoot, tsj.rightFoot};
        for (int side = 0; side < 2; ++side) {
            const auto& c = side ? contacts->right : contacts->left;
            Plan& plan = plans[static_cast<std::size_t>(side)];
            plan.target.assign(static_cast<std::size_t>(frames), glm::vec3(0));
            plan.weight.assign(static_cast<std::size_t>(frames), 0.0f);
            if (c.size() != static_cast<std::size_t>(frames)) continue;
            const auto ankle = static_cast<std::size_t>(ankles[static_cast<std::size_t>(side)]);
            int f = 0;
            while (f < frames) {
                if (!c[static_cast<std::size_t>(f)]) {
                    ++f;
                    continue;
                }
                int e = f;
                while (e < frames && c[static_cast<std::size_t>(e)]) ++e;
                // The lock: where the retargeted ankle is on average in the contact.
                glm::dvec3 sum(0.0);
                for (int k = f; k < e; ++k) {
                    worldPositions(out, k, pos);
                    sum += glm::dvec3(pos[ankle]);
                }
                const glm::vec3 lock(sum / static_cast<double>(e - f));
                for (int k = std::max(0, f - ease); k < std::min(frames, e + ease); ++k) {
                    const int d = k < f ? f - k : (k >= e ? k - e + 1 : 0);
                    const float w = d == 0 ? 1.0f : 1.0f - static_cast<float>(d) / static_cast<float>(ease + 1);
                    const float smooth = w * w * (3.0f - 2.0f * w);
                    if (smooth > plan.weight[static_cast<std::size_t>(k)]) {
                        plan.weight[static_cast<std::size_t>(k)] = smooth;
                        plan.target[static_cast<std::size_t>(k)] = lock;
                    }
                }
                f = e;
            }
        }
        const std::array<int, 2> hips = {tsj.leftHip, tsj.rightHip}, knees = {tsj.leftKnee, tsj.rightKnee};
        for (int f = 0; f < frames; ++f) {
            if (plans[0].weight[static_cast<std::size_t>(f)] <= 0.0f && plans[1].weight[static_cast<std::size_t>(f)] <= 0.0f)
                continue;
            worldTransforms(out, f, pos, rot);
            auto Q = out.rotations(f);
            for (std::size_t side = 0; side < 2; ++side) {
                const float w = plans[side].weight[static_cast<std::size_t>(f)];
                if (w <= 0.0f) continue;
                const auto ankle = static_cast<std::size_t>(ankles[side]);
                const glm::vec3 goal = glm::mix(pos[ankle], plans[side].target[static_cast<std::size_t>(f)], w);
                const glm::quat footWorld = rot[ankle];
                const bool reached =
                    applyTwoBoneIk(tsk, Q, pos, rot, hips[side], knees[side], ankles[side], goal, &footWorld);
                if (w >= 1.0f) {
                    ++rep.plantedFrames;
                    if (!reached) ++rep.unreachedFrames;
                }
            }
        }
    }
    if (report) *report = std::move(rep);
    return out;
}

}  // namespace fray
