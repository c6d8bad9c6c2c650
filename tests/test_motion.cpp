#include <gtest/gtest.h>

#include <map>

#include "fray/core/joint_guess.h"
#include "fray/core/kinematics.h"
#include "fray/core/normalize.h"
#include "fray/core/rotation.h"
#include "fray/io/bvh.h"
#include "fray/io/import.h"
#include "test_util.h"

using namespace fray;

namespace {

Motion makeRamp(double fps, int frames) {
    Skeleton sk;
    sk.addJoint("Hips", -1, {0, 0, 0},
                {Channel::Xposition, Channel::Yposition, Channel::Zposition, Channel::Zrotation, Channel::Xrotation, Channel::Yrotation},
                RotationOrder::ZXY);
    sk.addJoint("Spine", 0, {0, 0.5f, 0}, {Channel::Zrotation, Channel::Xrotation, Channel::Yrotation}, RotationOrder::ZXY);
    Motion m(sk, fps, 0);
    for (int f = 0; f < frames; ++f) {
        const float t = static_cast<float>(f / fps);
        const glm::vec3 tr[2] = {{t, 1.0f, 0.0f}, {0, 0.5f, 0}};
        const glm::quat rr[2] = {glm::angleAxis(t, glm::vec3(0, 1, 0)), glm::angleAxis(0.5f * t, glm::vec3(1, 0, 0))};
        m.appendFrame(tr, rr);
    }
    return m;
}

}  // namespace

TEST(Motion, SamplingHitsFramesAndSlerpsBetween) {
    const Motion m = makeRamp(60.0, 61);
    Pose p;
    m.sample(30.0 / 60.0, p);
    EXPECT_NEAR(p.translations[0].x, 0.5f, 1e-6f);
    m.sample(30.5 / 60.0, p);
    EXPECT_NEAR(p.translations[0].x, 30.5f / 60.0f, 1e-6f);
    // Constant angular velocity: slerp halfway equals the analytic rotation.
    const glm::quat expect = glm::angleAxis(30.5f / 60.0f, glm::vec3(0, 1, 0));
    EXPECT_GT(std::abs(glm::dot(p.rotations[0], expect)), 1.0f - 1e-6f);
    // Clamped outside the clip.
    m.sample(-1.0, p);
    EXPECT_EQ(p.translations[0].x, 0.0f);
    m.sample(100.0, p);
    EXPECT_NEAR(p.translations[0].x, 1.0f, 1e-6f);
}

TEST(Motion, Resample120To60KeepsEveryOtherFrame) {
    const Motion m = makeRamp(120.0, 241);
    auto r = resample(m, 60.0);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->frameCount(), 121);
    EXPECT_DOUBLE_EQ(r->fps(), 60.0);
    for (int f = 0; f < r->frameCount(); ++f) {
        EXPECT_NEAR(r->rootTranslation(f).x, m.rootTranslation(2 * f).x, 1e-5f);
        EXPECT_GT(std::abs(glm::dot(r->rotations(f)[1], m.rotations(2 * f)[1])), 1.0f - 1e-6f);
    }
    EXPECT_FALSE(resample(m, 0.0).ok());
    EXPECT_FALSE(resample(m, -5.0).ok());
    EXPECT_FALSE(resample(Motion(), 30.0).ok());
}

TEST(Motion, TrimAndConcatenate) {
    const Motion m = makeRamp(60.0, 100);
    auto t = trim(m, 10, 19);
    ASSERT_TRUE(t.ok());
    EXPECT_EQ(t->frameCount(), 10);
    EXPECT_EQ(t->rootTranslation(0), m.rootTranslation(10));
    EXPECT_FALSE(trim(m, 50, 10).ok());
    EXPECT_FALSE(trim(m, 0, 100).ok());
    EXPECT_FALSE(trim(m, -1, 5).ok());

    auto c = concatenate(*t, *t, false);
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->frameCount(), 20);
    EXPECT_EQ(c->rootTranslation(10), t->rootTranslation(0));
    // Aligned: the second clip starts where the first ended, facing the same way.
    auto a = concatenate(*t, *t, true);
    ASSERT_TRUE(a.ok());
    const glm::vec3 end = a->rootTranslation(9), start = a->rootTranslation(10);
    EXPECT_NEAR(end.x, start.x, 1e-5f);
    EXPECT_NEAR(end.z, start.z, 1e-5f);
    const glm::vec3 f9 = a->rotations(9)[0] * glm::vec3(0, 0, 1), f10 = a->rotations(10)[0] * glm::vec3(0, 0, 1);
    EXPECT_NEAR(std::atan2(f9.x, f9.z), std::atan2(f10.x, f10.z), 1e-5f);

    Motion other = makeRamp(30.0, 10);
    EXPECT_FALSE(concatenate(m, other, false).ok());  // frame rates differ
    other.skeleton().names[1] = "Chest";
    other.setFps(60.0);
    EXPECT_FALSE(concatenate(m, other, false).ok());  // skeletons differ
}

TEST(Motion, ForwardKinematicsRangeMatchesSingleFrames) {
    const Motion m = makeRamp(60.0, 20);
    const auto all = worldPositions(m, 5, 14);
    std::vector<glm::vec3> one(2);
    for (int f = 5; f <= 14; ++f) {
        worldPositions(m, f, one);
        for (std::size_t j = 0; j < 2; ++j) EXPECT_EQ(all[static_cast<std::size_t>(f - 5) * 2 + j], one[j]);
    }
}

// Unit and up-axis detection against the figures in ../shared/mocap/README.md.
TEST(Normalize, DetectsUnitsAndUpAxisOfEverySharedFile) {
    const std::map<std::string, std::pair<std::string, UpAxis>> expected = {
        {"bandai", {"cm", UpAxis::Y}},  {"cmu135_karate", {"inch", UpAxis::Z}}, {"cmu14", {"cmu", UpAxis::Y}},
        {"fair_animateddrawings", {"inch", UpAxis::Z}}, {"lafan1", {"cm", UpAxis::Y}}};
    const auto files = fray::test::sharedBvhFiles();
    ASSERT_FALSE(files.empty());
    for (const auto& f : files) {
        const std::string folder = f.parent_path().filename().string();
        auto it = expected.find(folder);
        ASSERT_NE(it, expected.end()) << "unknown folder " << folder;
        auto m = loadMotion(f);
        ASSERT_TRUE(m.ok()) << m.error().message;
        EXPECT_EQ(m->source().unitName, it->second.first) << f;
        EXPECT_EQ(m->source().sourceUp, it->second.second) << f;
        // Normalised: the head is above the pelvis, standing height plausible.
        const StandardJoints sj = guessStandardJoints(m->skeleton());
        std::vector<glm::vec3> p(static_cast<std::size_t>(m->jointCount()));
        float best = 0;
        for (int fr = 0; fr < m->frameCount(); fr += std::max(1, m->frameCount() / 20)) {
            worldPositions(*m, fr, p);
            best = std::max(best, p[static_cast<std::size_t>(sj.head)].y -
                                      std::min(p[static_cast<std::size_t>(sj.leftFoot)].y, p[static_cast<std::size_t>(sj.rightFoot)].y));
        }
        EXPECT_GT(best, 1.0f) << f;  // motorcycle.bvh is a crouched calibration pose
        EXPECT_LT(best, 1.9f) << f;
    }
}

TEST(Normalize, UnitAndAxisNames) {
    EXPECT_EQ(fray::unitScaleByName("cm"), 0.01);
    EXPECT_EQ(fray::unitScaleByName("in"), 0.0254);
    EXPECT_EQ(fray::unitScaleByName("cmu"), 0.056444);
    EXPECT_FALSE(fray::unitScaleByName("").has_value());
    EXPECT_FALSE(fray::unitScaleByName("feet").has_value());
    EXPECT_EQ(fray::upAxisByName("Z"), fray::UpAxis::Z);
    EXPECT_FALSE(fray::upAxisByName("x").has_value());
    const auto o = fray::normalizeOptionsFor("mm", "");
    EXPECT_EQ(o.unitScale, 0.001);
    EXPECT_FALSE(o.upAxis.has_value());
}

TEST(Normalize, ExplicitOptionsOverrideDetection) {
    auto raw = readBvh(fray::test::sharedMocap() / "lafan1/walk4_subject1.bvh");
    ASSERT_TRUE(raw.ok());
    Motion m = *raw;
    NormalizeOptions o;
    o.unitScale = 0.5;
    o.upAxis = UpAxis::Y;
    normalize(m, o);
    EXPECT_NEAR(m.rootTranslation(0).y, raw->rootTranslation(0).y * 0.5f, 1e-4f);
    EXPECT_TRUE(m.source().normalized);
    const glm::vec3 before = m.rootTranslation(0);
    normalize(m, o);  // idempotent
    EXPECT_EQ(m.rootTranslation(0), before);
}

TEST(JointGuess, FindsStandardJointsInEverySharedSkeleton) {
    for (const auto& f : fray::test::sharedBvhFiles()) {
        auto m = readBvh(f);
        ASSERT_TRUE(m.ok());
        const StandardJoints sj = guessStandardJoints(m->skeleton());
        EXPECT_TRUE(sj.complete()) << f << " missing " << sj.missing();
        EXPECT_GE(sj.leftToe, 0) << f;
        EXPECT_GE(sj.rightToe, 0) << f;
        EXPECT_GE(sj.spine, 0) << f;
        EXPECT_GE(sj.leftKnee, 0) << f;
        EXPECT_GE(sj.rightElbow, 0) << f;
        EXPECT_NE(sj.leftHand, sj.rightHand);
    }
}

TEST(JointGuess, NamingConventions) {
    auto build = [](std::vector<std::pair<std::string, int>> joints) {
        Skeleton sk;
        for (auto& [n, p] : joints) sk.addJoint(n, p, {0, 1, 0}, {}, RotationOrder::ZXY);
        return sk;
    };
    // Mixamo-like.
    Skeleton mix = build({{"mixamorig:Hips", -1}, {"mixamorig:Spine", 0}, {"mixamorig:Neck", 1}, {"mixamorig:Head", 2},
                          {"mixamorig:LeftShoulder", 1}, {"mixamorig:LeftArm", 4}, {"mixamorig:LeftForeArm", 5},
                          {"mixamorig:LeftHand", 6}, {"mixamorig:RightShoulder", 1}, {"mixamorig:RightArm", 8},
                          {"mixamorig:RightForeArm", 9}, {"mixamorig:RightHand", 10}, {"mixamorig:LeftUpLeg", 0},
                          {"mixamorig:LeftLeg", 12}, {"mixamorig:LeftFoot", 13}, {"mixamorig:LeftToeBase", 14},
                          {"mixamorig:RightUpLeg", 0}, {"mixamorig:RightLeg", 16}, {"mixamorig:RightFoot", 17},
                          {"mixamorig:RightToeBase", 18}});
    StandardJoints s = guessStandardJoints(mix);
    EXPECT_TRUE(s.complete());
    EXPECT_EQ(s.leftShoulder, 5);   // LeftArm is the upper arm; LeftShoulder the clavicle
    EXPECT_EQ(s.leftKnee, 13);      // LeftLeg is the shin
    EXPECT_EQ(s.leftHip, 12);
    EXPECT_EQ(s.rightToe, 19);
    // 3ds Max Biped.
    Skeleton bip = build({{"Bip01 Pelvis", -1}, {"Bip01 Spine", 0}, {"Bip01 Head", 1}, {"Bip01 L Thigh", 0}, {"Bip01 L Calf", 3},
                          {"Bip01 L Foot", 4}, {"Bip01 L Toe0", 5}, {"Bip01 R Thigh", 0}, {"Bip01 R Calf", 7},
                          {"Bip01 R Foot", 8}, {"Bip01 R Toe0", 9}, {"Bip01 L UpperArm", 1}, {"Bip01 L Forearm", 11},
                          {"Bip01 L Hand", 12}, {"Bip01 R UpperArm", 1}, {"Bip01 R Forearm", 14}, {"Bip01 R Hand", 15}});
    s = guessStandardJoints(bip);
    EXPECT_TRUE(s.complete()) << s.missing();
    EXPECT_EQ(s.leftFoot, 5);
    EXPECT_EQ(s.rightHand, 16);
    EXPECT_EQ(s.leftKnee, 4);
    // Unnamed joints: nothing is invented; the missing roles are listed.
    Skeleton anon = build({{"a", -1}, {"b", 0}, {"c", 1}});
    s = guessStandardJoints(anon);
    EXPECT_FALSE(s.complete());
    EXPECT_NE(s.missing().find("leftFoot"), std::string::npos);
}

TEST(JointGuess, FindsStandardJointsInUnityNamedFbx) {
    auto m = loadMotion(fray::test::sharedMocap() / "cmu_fbx/135_02.fbx");
    ASSERT_TRUE(m.ok()) << m.error().message;
    const StandardJoints sj = guessStandardJoints(m->skeleton());
    EXPECT_TRUE(sj.complete()) << sj.missing();
    EXPECT_EQ(m->skeleton().names[static_cast<std::size_t>(sj.pelvis)], "Neo_Hips");
}
