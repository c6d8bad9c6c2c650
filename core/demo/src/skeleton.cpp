#include <array>

#include "fray/demo/demo_actor.h"
#include "rig.h"

namespace fray::demo {
namespace detail {
namespace {

struct JointDef {
    const char* name;
    int parent;
    glm::dvec3 offset;
    bool endSite;
    glm::dvec3 endOffset;
};

using D = RigDims;
const std::array<JointDef, kJointCount> kJoints = {{
    {"Hips", -1, {0, 0, 0}, false, {}},
    {"Spine", kHips, {0, D::pelvisToSpine, 0}, false, {}},
    {"Spine1", kSpine, {0, D::spine1, 0}, false, {}},
    {"Spine2", kSpine1, {0, D::spine2, 0}, false, {}},
    {"Neck", kSpine2, {0, D::neck, 0}, false, {}},
    {"Head", kNeck, {0, D::head, 0.02}, true, {0, 0.17, 0}},
    {"LeftShoulder", kSpine2, {D::clavicleX, D::clavicleY, 0}, false, {}},
    {"LeftArm", kLClavicle, {D::clavicle, 0, 0}, false, {}},
    {"LeftForeArm", kLArm, {D::upperArm, 0, 0}, false, {}},
    {"LeftHand", kLForeArm, {D::foreArm, 0, 0}, false, {}},
    {"LeftHandIndex1", kLHand, {D::hand, 0, 0}, true, {0.03, 0, 0}},
    {"RightShoulder", kSpine2, {-D::clavicleX, D::clavicleY, 0}, false, {}},
    {"RightArm", kRClavicle, {-D::clavicle, 0, 0}, false, {}},
    {"RightForeArm", kRArm, {-D::upperArm, 0, 0}, false, {}},
    {"RightHand", kRForeArm, {-D::foreArm, 0, 0}, false, {}},
    {"RightHandIndex1", kRHand, {-D::hand, 0, 0}, true, {-0.03, 0, 0}},
    {"LeftUpLeg", kHips, {D::hipX, D::hipY, 0}, false, {}},
    {"LeftLeg", kLUpLeg, {0, -D::thigh, 0}, false, {}},
    {"LeftFoot", kLLeg, {0, -D::shin, 0}, false, {}},
    {"LeftToe", kLFoot, {0, D::toeY, D::toeZ}, true, {0, 0, 0.06}},
    {"RightUpLeg", kHips, {-D::hipX, D::hipY, 0}, false, {}},
    {"RightLeg", kRUpLeg, {0, -D::thigh, 0}, false, {}},
    {"RightFoot", kRLeg, {0, -D::shin, 0}, false, {}},
    {"RightToe", kRFoot, {0, D::toeY, D::toeZ}, true, {0, 0, 0.06}},
}};

}  // namespace

glm::dvec3 restOffset(int joint) { return kJoints[static_cast<std::size_t>(joint)].offset; }
int parentOf(int joint) { return kJoints[static_cast<std::size_t>(joint)].parent; }

}  // namespace detail

Skeleton makeDemoSkeleton() {
    using namespace detail;
    Skeleton sk;
    const std::vector<Channel> root = {Channel::Xposition, Channel::Yposition, Channel::Zposition,
                                       Channel::Zrotation, Channel::Xrotation, Channel::Yrotation};
    const std::vector<Channel> rot = {Channel::Zrotation, Channel::Xrotation, Channel::Yrotation};
    for (const JointDef& j : kJoints) {
        const int index = sk.addJoint(j.name, j.parent, glm::vec3(j.offset), j.parent < 0 ? root : rot,
                                      RotationOrder::ZXY);
        if (j.endSite) sk.endSites[static_cast<std::size_t>(index)] = glm::vec3(j.endOffset);
    }
    return sk;
}

}  // namespace fray::demo
