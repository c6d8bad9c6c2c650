#include "retarget_export.h"

#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "fray/core/joint_guess.h"
#include "fray/core/kinematics.h"

namespace fray::exporter {

std::optional<RootMotion> parseRootMotion(std::string_view name) {
    if (name == "none") return RootMotion::None;
    if (name == "floor") return RootMotion::Floor;
    if (name == "in-place") return RootMotion::InPlace;
    return std::nullopt;
}

Status retargetCharacters(SampledScene& scene, const RetargetTarget& rig, std::vector<std::string>& notes) {
    int done = 0;
    std::string firstRefusal;
    for (CharacterTake& c : scene.characters) {
        // A creature without feet (a rat, a bag) keeps its own skeleton.
        if (auto st = checkRetargetable(c.motion.skeleton(), "character '" + c.name + "'"); !st) {
            notes.push_back(st.error().message + "; it keeps its own skeleton");
            if (firstRefusal.empty()) firstRefusal = st.error().message;
            continue;
        }
        Motion source = c.motion;
        source.source().path = "character '" + c.name + "'";
        RetargetReport report;
        auto out = retarget(source, rig, {}, &report);
        if (!out) return out.error();
        // Keep quaternions in one hemisphere from frame to frame (importers interpolate component-wise).
        for (int f = 1; f < out->frameCount(); ++f) {
            auto q = out->rotations(f);
            const auto prev = out->rotations(f - 1);
            for (std::size_t j = 0; j < q.size(); ++j)
                if (glm::dot(q[j], prev[j]) < 0.0f) q[j] = -q[j];
        }
        c.motion = std::move(*out);
        notes.push_back(report.text());
        ++done;
    }
    if (done == 0) return makeError("--rig " + rig.name + ": no character of the scene can be retargeted: " + firstRefusal);
    return {};
}

void addRootBone(Motion& motion, RootMotion mode) {
    if (mode == RootMotion::None || motion.jointCount() == 0) return;
    const Skeleton& old = motion.skeleton();
    std::string name(kRootBoneName);
    if (old.find(name) >= 0) name = "fray_root";
    for (int k = 2; old.find(name) >= 0; ++k) name = "fray_root" + std::to_string(k);
    Skeleton sk;
    sk.addJoint(name, -1, glm::vec3(0), {Channel::Xposition, Channel::Yposition, Channel::Zposition, Channel::Zrotation,
                                         Channel::Xrotation, Channel::Yrotation},
                RotationOrder::ZXY);
    for (int j = 0; j < old.jointCount(); ++j) {
        const auto u = static_cast<std::size_t>(j);
        std::vector<Channel> channels = old.channels[u];
        if (j == 0 && !old.hasPositionChannels(0))
            channels.insert(channels.begin(), {Channel::Xposition, Channel::Yposition, Channel::Zposition});
        sk.addJoint(old.names[u], old.parents[u] < 0 ? 0 : old.parents[u] + 1, j == 0 ? glm::vec3(0) : old.offsets[u],
                    std::move(channels), old.rotationOrders[u]);
        sk.endSites.back() = old.endSites[u];
    }
    const StandardJoints sj = guessStandardJoints(old);
    const bool hips = sj.leftHip >= 0 && sj.rightHip >= 0 && sj.leftHip != sj.rightHip;
    Motion out(sk, motion.fps(), motion.frameCount());
    out.source() = motion.source();
    const auto jc = static_cast<std::size_t>(old.jointCount());
    std::vector<glm::vec3> pos(jc);
    std::vector<glm::quat> rot(jc);
    glm::quat prevRoot(1, 0, 0, 0);
    for (int f = 0; f < motion.frameCount(); ++f) {
        worldTransforms(motion, f, pos, rot);
        // Heading: perpendicular to the hip line on the floor (or the root's own forward).
        glm::vec3 forward = hips ? glm::cross(pos[static_cast<std::size_t>(sj.leftHip)] - pos[static_cast<std::size_t>(sj.rightHip)],
                                              glm::vec3(0, 1, 0))
                                 : rot[0] * glm::vec3(0, 0, 1);
        forward.y = 0.0f;
        const float yaw = glm::length(forward) > 1e-6f ? std::atan2(forward.x, forward.z) : 0.0f;
        glm::quat heading = glm::angleAxis(yaw, glm::vec3(0, 1, 0));
        if (glm::dot(heading, prevRoot) < 0.0f) heading = -heading;
        prevRoot = heading;
        const glm::vec3 floor(pos[0].x, 0.0f, pos[0].z);
        auto T = out.translations(f);
        auto R = out.rotations(f);
        const auto src = motion.translations(f);
        const auto srq = motion.rotations(f);
        T[0] = mode == RootMotion::Floor ? floor : glm::vec3(0);
        R[0] = mode == RootMotion::Floor ? heading : glm::quat(1, 0, 0, 0);
        // The old root relative to the trajectory (the same in both modes).
        T[1] = glm::inverse(heading) * (pos[0] - floor);
        R[1] = glm::normalize(glm::inverse(heading) * srq[0]);
        if (f > 0 && glm::dot(R[1], out.rotations(f - 1)[1]) < 0.0f) R[1] = -R[1];
        for (std::size_t j = 1; j < jc; ++j) {
            T[j + 1] = src[j];
            R[j + 1] = srq[j];
        }
    }
    motion = std::move(out);
}

}  // namespace fray::exporter
