// The demo skeleton: structure, channel layout, standard-joint guessing,
// proportions, and a BVH round trip of a generated take.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "fray/core/joint_guess.h"
#include "fray/core/kinematics.h"
#include "fray/core/normalize.h"
#include "fray/demo/demo_actor.h"
#include "fray/io/bvh.h"

using namespace fray;
using namespace fray::demo;

namespace {

std::vector<glm::vec3> restPose(const Skeleton& sk, float rootHeight) {
    std::vector<glm::vec3> t(sk.offsets.begin(), sk.offsets.end());
    t[0] = glm::vec3(0, rootHeight, 0);
    std::vector<glm::quat> r(t.size(), glm::quat(1, 0, 0, 0));
    std::vector<glm::vec3> p(t.size());
    std::vector<glm::quat> q(t.size());
    forwardKinematics(sk, t, r, p, q);
    return p;
}

}  // namespace

TEST(DemoSkeleton, StructureAndChannelLayout) {
    const Skeleton sk = makeDemoSkeleton();
    EXPECT_FALSE(sk.validate().has_value());
    EXPECT_GE(sk.jointCount(), 22);
    EXPECT_LE(sk.jointCount(), 28);
    const std::vector<Channel> root = {Channel::Xposition, Channel::Yposition, Channel::Zposition,
                                       Channel::Zrotation, Channel::Xrotation, Channel::Yrotation};
    EXPECT_EQ(sk.channels[0], root);
    EXPECT_EQ(sk.parents[0], -1);
    for (int j = 1; j < sk.jointCount(); ++j) {
        const auto ju = static_cast<std::size_t>(j);
        EXPECT_EQ(sk.channels[ju], (std::vector<Channel>{Channel::Zrotation, Channel::Xrotation, Channel::Yrotation}))
            << sk.names[ju];
        EXPECT_EQ(sk.rotationOrders[ju], RotationOrder::ZXY);
        // Every leaf ends in an End Site, and only leaves do.
        EXPECT_EQ(sk.children(j).empty(), sk.endSites[ju].has_value()) << sk.names[ju];
    }
}

TEST(DemoSkeleton, GuessStandardJointsFindsEveryRole) {
    const Skeleton sk = makeDemoSkeleton();
    const StandardJoints s = guessStandardJoints(sk);
    ASSERT_TRUE(s.complete()) << s.missing();
    auto name = [&](int j) { return j >= 0 ? sk.names[static_cast<std::size_t>(j)] : std::string("?"); };
    EXPECT_EQ(name(s.pelvis), "Hips");
    EXPECT_EQ(name(s.spine), "Spine");
    EXPECT_EQ(name(s.chest), "Spine2");
    EXPECT_EQ(name(s.neck), "Neck");
    EXPECT_EQ(name(s.head), "Head");
    EXPECT_EQ(name(s.leftShoulder), "LeftArm");
    EXPECT_EQ(name(s.rightShoulder), "RightArm");
    EXPECT_EQ(name(s.leftElbow), "LeftForeArm");
    EXPECT_EQ(name(s.rightElbow), "RightForeArm");
    EXPECT_EQ(name(s.leftHand), "LeftHand");
    EXPECT_EQ(name(s.rightHand), "RightHand");
    EXPECT_EQ(name(s.leftHip), "LeftUpLeg");
    EXPECT_EQ(name(s.rightHip), "RightUpLeg");
    EXPECT_EQ(name(s.leftKnee), "LeftLeg");
    EXPECT_EQ(name(s.rightKnee), "RightLeg");
    EXPECT_EQ(name(s.leftFoot), "LeftFoot");
    EXPECT_EQ(name(s.rightFoot), "RightFoot");
    EXPECT_EQ(name(s.leftToe), "LeftToe");
    EXPECT_EQ(name(s.rightToe), "RightToe");
}

TEST(DemoSkeleton, AdultProportionsInMetresYUp) {
    const Skeleton sk = makeDemoSkeleton();
    const auto p = restPose(sk, 1.01f);
    auto at = [&](const char* n) { return p[static_cast<std::size_t>(sk.find(n))]; };
    const glm::vec3 headTop = at("Head") + *sk.endSites[static_cast<std::size_t>(sk.find("Head"))];
    EXPECT_NEAR(headTop.y, 1.78, 0.05);                           // stature
    EXPECT_NEAR(at("LeftToe").y, 0.025, 0.01);                     // feet on the floor
    EXPECT_NEAR(at("LeftFoot").y, 0.08, 0.01);                     // ankle height
    EXPECT_NEAR(at("LeftArm").y, 1.45, 0.04);                      // shoulder height
    EXPECT_NEAR(at("LeftArm").x - at("RightArm").x, 0.36, 0.04);   // shoulder width
    EXPECT_NEAR(glm::length(at("LeftHand") - at("LeftArm")), 0.55, 0.03);       // arm
    EXPECT_NEAR(glm::length(at("LeftFoot") - at("LeftUpLeg")), 0.86, 0.03);     // leg
    EXPECT_GT(at("LeftArm").x, 0.0f);  // facing +Z, left is +X
    EXPECT_GT(at("LeftToe").z, at("LeftFoot").z);
}

TEST(DemoSkeleton, TakeSurvivesBvhRoundTripAndNormalisesAsMetresYUp) {
    TakeSpec spec{"t", TakeKind::ShadowBoxing, Style::Energetic, 20.0};
    const Take take = generateTake(spec, 3);
    const std::string text = writeBvhToString(take.motion);
    auto back = readBvhFromMemory(text, "demo.bvh");
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->frameCount(), take.motion.frameCount());
    double worst = 0;
    const int n = take.motion.frameCount();
    const auto a = worldPositions(take.motion, 0, n - 1);
    const auto b = worldPositions(*back, 0, n - 1);
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, static_cast<double>(glm::length(a[i] - b[i])));
    EXPECT_LT(worst, 1e-4);
    // What `fray-cli info` does on import: units and up axis are detected from the motion.
    EXPECT_EQ(guessUpAxis(*back), UpAxis::Y);
    EXPECT_EQ(guessUnits(*back).name, std::string("m"));
}
