// export --rig and --root-motion (docs/EXPORT.md): the duel retargeted onto a
// Mixamo-style rig written here (other names, hierarchy, proportions, rest
// pose and units) and onto the CMU base skeleton (FBX, no mesh); feet held;
// the root bone carries the trajectory; bad rigs and takes as clear errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <set>

#include "export_fixture.h"
#include "gltf_writer.h"  // core/export/src
#include "rig.h"          // core/export/src
#include "fray/core/body_mesh.h"
#include "fray/core/kinematics.h"
#include "fray/core/retarget.h"
#include "fray/io/bvh.h"
#include "fray/io/import.h"
#include "fray/io/rig_import.h"
#include "test_util.h"

namespace fray::test {
namespace {

// A Mixamo-named rig in centimetres, T-pose, long legs (hips at 1.05 m) and
// short arms: nothing like the demo actor's skeleton but the anatomy.
constexpr const char* kMixamoRig = R"(HIERARCHY
ROOT mixamorig:Hips
{
  OFFSET 0 105 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT mixamorig:Spine
  {
    OFFSET 0 12 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT mixamorig:Spine1
    {
      OFFSET 0 14 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT mixamorig:Spine2
      {
        OFFSET 0 14 0
        CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT mixamorig:Neck
        {
          OFFSET 0 16 0
          CHANNELS 3 Zrotation Xrotation Yrotation
          JOINT mixamorig:Head
          {
            OFFSET 0 10 2
            CHANNELS 3 Zrotation Xrotation Yrotation
            End Site
            {
              OFFSET 0 18 0
            }
          }
        }
        JOINT mixamorig:LeftShoulder
        {
          OFFSET 6 12 0
          CHANNELS 3 Zrotation Xrotation Yrotation
          JOINT mixamorig:LeftArm
          {
            OFFSET 12 0 0
            CHANNELS 3 Zrotation Xrotation Yrotation
            JOINT mixamorig:LeftForeArm
            {
              OFFSET 24 0 0
              CHANNELS 3 Zrotation Xrotation Yrotation
              JOINT mixamorig:LeftHand
              {
                OFFSET 22 0 0
                CHANNELS 3 Zrotation Xrotation Yrotation
                End Site
                {
                  OFFSET 8 0 0
                }
              }
            }
          }
        }
        JOINT mixamorig:RightShoulder
        {
          OFFSET -6 12 0
          CHANNELS 3 Zrotation Xrotation Yrotation
          JOINT mixamorig:RightArm
          {
            OFFSET -12 0 0
            CHANNELS 3 Zrotation Xrotation Yrotation
            JOINT mixamorig:RightForeArm
            {
              OFFSET -24 0 0
              CHANNELS 3 Zrotation Xrotation Yrotation
              JOINT mixamorig:RightHand
              {
                OFFSET -22 0 0
                CHANNELS 3 Zrotation Xrotation Yrotation
                End Site
                {
                  OFFSET -8 0 0
                }
              }
            }
          }
        }
      }
    }
  }
  JOINT mixamorig:LeftUpLeg
  {
    OFFSET 10 -6 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT mixamorig:LeftLeg
    {
      OFFSET 0 -48 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT mixamorig:LeftFoot
      {
        OFFSET 0 -45 0
        CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT mixamorig:LeftToeBase
        {
          OFFSET 0 -5 14
          CHANNELS 3 Zrotation Xrotation Yrotation
          End Site
          {
            OFFSET 0 0 6
          }
        }
      }
    }
  }
  JOINT mixamorig:RightUpLeg
  {
    OFFSET -10 -6 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT mixamorig:RightLeg
    {
      OFFSET 0 -48 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT mixamorig:RightFoot
      {
        OFFSET 0 -45 0
        CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT mixamorig:RightToeBase
        {
          OFFSET 0 -5 14
          CHANNELS 3 Zrotation Xrotation Yrotation
          End Site
          {
            OFFSET 0 0 6
          }
        }
      }
    }
  }
}
MOTION
Frames: 1
Frame Time: 0.0333333
0 105 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0
)";

fs::path writeText(const TempFolder& dir, const std::string& name, const std::string& text) {
    const fs::path p = dir / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
}

exporter::ExportOptions rigOptions(exporter::Format format, const TempFolder& dir, const fs::path& rig,
                                   exporter::RootMotion root = exporter::RootMotion::None) {
    auto o = optionsFor(format, dir.path() / "out");
    auto loaded = loadRigSkeleton(rig);
    EXPECT_TRUE(loaded) << (loaded ? "" : loaded.error().message);
    if (loaded) o.rig = loaded->target;
    o.rootMotion = root;
    return o;
}

std::vector<Motion> readCharacters(const fs::path& dir) {
    std::vector<Motion> out;
    for (const char* c : {"duel_a.bvh", "duel_b.bvh"}) {
        auto m = loadMotion(dir / c);
        EXPECT_TRUE(m) << (m ? "" : m.error().message);
        if (m) out.push_back(std::move(*m));
    }
    return out;
}

TEST(RigExport, MixamoRigTakesTheDuelWithFeetPlanted) {
    TempFolder dir;
    const fs::path rig = writeText(dir, "mixamo.bvh", kMixamoRig);
    auto report = exporter::exportScene(exportDuel(), exportLibrary(), rigOptions(exporter::Format::Bvh, dir, rig));
    ASSERT_TRUE(report) << report.error().message;
    ASSERT_GE(report->notes.size(), 2u);  // one per character, and the hits the IK moved
    EXPECT_NE(report->notes[0].find("leftFoot"), std::string::npos) << report->notes[0];
    auto rigMotion = loadMotion(rig);
    ASSERT_TRUE(rigMotion);
    for (const Motion& m : readCharacters(dir.path() / "out")) {
        // The rig's skeleton: its names, hierarchy and proportions (cm read back as m).
        ASSERT_TRUE(sameSkeleton(m.skeleton(), rigMotion->skeleton()));
        for (int j = 1; j < m.jointCount(); ++j)
            EXPECT_NEAR(glm::length(m.skeleton().offsets[static_cast<std::size_t>(j)] -
                                    rigMotion->skeleton().offsets[static_cast<std::size_t>(j)]),
                        0.0f, 1e-4f);
        const StandardJoints sj = guessStandardJoints(m.skeleton());
        const FootContactTrack contacts = detectFootContacts(m, sj);
        const FootSkate skate = measureFootSkate(m, sj, contacts);
        std::printf("Mixamo rig: foot skate %.3f cm per contact frame (max %.2f cm) over %d frames\n", skate.mean * 100,
                    skate.max * 100, skate.frames);
        EXPECT_GT(skate.frames, 30);
        EXPECT_LT(skate.mean, 0.005);
        // Feet on the floor in contact: the lowest ankle in contact is where the rig's rest puts it.
        double lowest = 1e9;
        std::vector<glm::vec3> pos(static_cast<std::size_t>(m.jointCount()));
        for (int f = 0; f < m.frameCount(); ++f) {
            if (!contacts.left[static_cast<std::size_t>(f)]) continue;
            worldPositions(m, f, pos);
            lowest = std::min(lowest, static_cast<double>(pos[static_cast<std::size_t>(sj.leftFoot)].y));
        }
        EXPECT_GT(lowest, 0.0);
        EXPECT_LT(lowest, 0.2);
    }
}

// Closest distance between segments p0-p1 and q0-q1.
double segmentDistance(glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 q0, glm::dvec3 q1) {
    const glm::dvec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
    double s = 0.0, t = 0.0;
    if (a < 1e-12 && e < 1e-12) return glm::length(r);
    if (a < 1e-12) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = glm::dot(d1, r);
        if (e < 1e-12) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = glm::dot(d1, d2), den = a * e - b * b;
            s = den > 1e-12 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0.0) t = 0.0, s = std::clamp(-c / a, 0.0, 1.0);
            else if (t > 1.0) t = 1.0, s = std::clamp((b - c) / a, 0.0, 1.0);
        }
    }
    return glm::length((p0 + s * d1) - (q0 + t * d2));
}

// Per hit of the scene: how far the attacker's striking bone (forearm,
// shin, foot...) is from the surface of the defender's body (its capsules,
// fray::bodyCapsules) in the exported characters at the hit's frame; 0 when
// it touches or goes in.
std::vector<double> hitGaps(const sim::Scene& scene, const std::vector<Motion>& characters, double fps) {
    std::vector<double> out;
    for (const sim::HitEvent& h : scene.hits) {
        const Motion& a = characters[static_cast<std::size_t>(h.attacker)];
        const Motion& d = characters[static_cast<std::size_t>(h.defender)];
        const int f = std::min(a.frameCount() - 1, static_cast<int>(std::lround(h.time * fps)));
        const StandardJoints sj = guessStandardJoints(a.skeleton());
        std::pair<int, int> bone{-1, -1};
        switch (h.effector) {
            case sim::kLeftUpperArm: bone = {sj.leftShoulder, sj.leftElbow}; break;
            case sim::kLeftForearm: bone = {sj.leftElbow, sj.leftHand}; break;
            case sim::kRightUpperArm: bone = {sj.rightShoulder, sj.rightElbow}; break;
            case sim::kRightForearm: bone = {sj.rightElbow, sj.rightHand}; break;
            case sim::kLeftThigh: bone = {sj.leftHip, sj.leftKnee}; break;
            case sim::kLeftShin: bone = {sj.leftKnee, sj.leftFoot}; break;
            case sim::kLeftFoot: bone = {sj.leftFoot, sj.leftToe >= 0 ? sj.leftToe : sj.leftFoot}; break;
            case sim::kRightThigh: bone = {sj.rightHip, sj.rightKnee}; break;
            case sim::kRightShin: bone = {sj.rightKnee, sj.rightFoot}; break;
            case sim::kRightFoot: bone = {sj.rightFoot, sj.rightToe >= 0 ? sj.rightToe : sj.rightFoot}; break;
            default: bone = {sj.head, sj.head};
        }
        std::vector<glm::vec3> ap(static_cast<std::size_t>(a.jointCount())), dp(static_cast<std::size_t>(d.jointCount()));
        std::vector<glm::quat> ar(ap.size()), dr(dp.size());
        worldTransforms(a, f, ap, ar);
        worldTransforms(d, f, dp, dr);
        const glm::dvec3 p0(ap[static_cast<std::size_t>(bone.first)]), p1(ap[static_cast<std::size_t>(bone.second)]);
        double gap = 1e9;
        for (const BodyCapsule& c : bodyCapsules(d.skeleton())) {
            const glm::dvec3 q0(dp[c.joint] + dr[c.joint] * c.a), q1(dp[c.joint] + dr[c.joint] * c.b);
            gap = std::min(gap, std::max(0.0, segmentDistance(p0, p1, q0, q1) - static_cast<double>(c.radius)));
        }
        out.push_back(gap);
    }
    return out;
}

// A longer duel than the fixture's, for more hits.
const sim::Scene& longDuel() {
    static const sim::Scene scene = [] {
        auto s = runSpec(duelSpec(2, 2, 11, 20.0));
        if (!s) throw std::runtime_error(s.error().message);
        return std::move(*s);
    }();
    return scene;
}

TEST(RigExport, HitsStillLandOnTheVictimsBody) {
    for (const sim::Scene* scene : {&exportDuel(), &longDuel()}) {
        TempFolder plain, rigged;
        const fs::path rig = writeText(rigged, "mixamo.bvh", kMixamoRig);
        ASSERT_TRUE(exporter::exportScene(*scene, exportLibrary(), optionsFor(exporter::Format::Bvh, plain.path() / "out")));
        ASSERT_TRUE(exporter::exportScene(*scene, exportLibrary(), rigOptions(exporter::Format::Bvh, rigged, rig)));
        const auto before = hitGaps(*scene, readCharacters(plain.path() / "out"), 30.0);
        const auto after = hitGaps(*scene, readCharacters(rigged.path() / "out"), 30.0);
        ASSERT_FALSE(after.empty()) << "the duel has hits";
        for (std::size_t i = 0; i < after.size(); ++i) {
            std::printf("hit %zu at %.2f s (%s): striking bone to the victim's body %.1f cm (capture skeleton %.1f cm)\n", i,
                        scene->hits[i].time, sim::segmentName(scene->hits[i].effector), after[i] * 100, before[i] * 100);
            EXPECT_LE(after[i], 0.03);
        }
    }
}

TEST(RigExport, RootMotionPutsTheTrajectoryOnARootBoneOnTheFloor) {
    TempFolder dir;
    const fs::path rig = writeText(dir, "mixamo.bvh", kMixamoRig);
    TempFolder other;
    ASSERT_TRUE(exporter::exportScene(exportDuel(), exportLibrary(),
                                      rigOptions(exporter::Format::Bvh, dir, rig, exporter::RootMotion::Floor)));
    ASSERT_TRUE(exporter::exportScene(exportDuel(), exportLibrary(),
                                      rigOptions(exporter::Format::Bvh, other, rig, exporter::RootMotion::InPlace)));
    const auto floor = readCharacters(dir.path() / "out");
    const auto inPlace = readCharacters(other.path() / "out");
    ASSERT_EQ(floor.size(), 2u);
    ASSERT_EQ(inPlace.size(), 2u);
    for (std::size_t c = 0; c < 2; ++c) {
        const Motion& m = floor[c];
        ASSERT_EQ(m.skeleton().names[0], "root");
        ASSERT_EQ(m.skeleton().names[1], "mixamorig:Hips");
        ASSERT_EQ(m.skeleton().parents[1], 0);
        double travel = 0.0;
        std::vector<glm::vec3> pos(static_cast<std::size_t>(m.jointCount()));
        for (int f = 0; f < m.frameCount(); ++f) {
            worldPositions(m, f, pos);
            const glm::vec3 root = m.translations(f)[0];
            // The root is on the floor, under the hips; the hips are relative to it.
            EXPECT_NEAR(root.y, 0.0f, 1e-4f);
            EXPECT_NEAR(root.x, pos[1].x, 1e-3f);
            EXPECT_NEAR(root.z, pos[1].z, 1e-3f);
            const glm::vec3 hips = m.translations(f)[1];
            EXPECT_NEAR(hips.x, 0.0f, 1e-3f);
            EXPECT_NEAR(hips.z, 0.0f, 1e-3f);
            EXPECT_GT(hips.y, 0.05f);  // above the floor (a knocked-down boxer lies low)
            if (f > 0) travel += static_cast<double>(glm::length(root - m.translations(f - 1)[0]));
            // In place: the same skeleton, the root at the origin, the hips as above.
            const Motion& p = inPlace[c];
            EXPECT_NEAR(glm::length(p.translations(f)[0]), 0.0f, 1e-4f);
            EXPECT_NEAR(glm::length(p.translations(f)[1] - hips), 0.0f, 1e-3f);
        }
        EXPECT_GT(travel, 0.5) << "the root bone carries the trajectory";
    }
}

TEST(RigExport, CmuBaseSkeletonFbxWithoutMeshIsARigOfBones) {
    if (!requireSharedMocap()) return;
    const fs::path base = sharedMocap() / "cmu_fbx/Base.fbx";
    auto rig = loadRigSkeleton(base);
    ASSERT_TRUE(rig) << rig.error().message;
    EXPECT_FALSE(rig->skinned);
    ASSERT_FALSE(rig->warnings.empty());
    EXPECT_NE(rig->warnings[0].find("no mesh"), std::string::npos) << rig->warnings[0];
    TempFolder dir;
    auto o = optionsFor(exporter::Format::Gltf, dir.path());
    o.rig = rig->target;
    o.rootMotion = exporter::RootMotion::Floor;
    auto report = exporter::exportScene(exportDuel(), exportLibrary(), o);
    ASSERT_TRUE(report) << report.error().message;
    const std::string text = readBytes(dir / "duel.gltf");
    EXPECT_NE(text.find("\"Neo_Hips\""), std::string::npos);
    EXPECT_NE(text.find("\"root\""), std::string::npos);
}

// A skin of the rig's own: Fray's capsules on the skeleton, every vertex
// pushed 3 cm out along its normal (a coat no capsule body has), so a copy of
// the rig's mesh and a capsule body built on the rig's skeleton differ.
std::shared_ptr<const SkinnedMesh> coatSkin(const Skeleton& sk) {
    const exporter::ExportBody body = exporter::exportBody(sk, nullptr);
    auto skin = std::make_shared<SkinnedMesh>();
    for (std::size_t v = 0; v < body.positions.size(); ++v)
        skin->vertices.push_back({body.positions[v] + 0.03f * body.normals[v], body.normals[v], body.joints[v], body.weights[v]});
    skin->indices = body.indices;
    for (const glm::mat4& m : body.inverseBind) skin->inverseBind.push_back({glm::vec3(m[3]), glm::quat(1, 0, 0, 0)});
    skin->jointCount = sk.jointCount();
    skin->skeletonFingerprint = skeletonFingerprint(sk);
    return skin;
}

// Bone names of every mesh of an Assimp scene, and its vertex positions.
struct ReadBack {
    std::vector<std::set<std::string>> bones;
    std::vector<std::vector<glm::vec3>> vertices;
};
ReadBack readBack(const fs::path& file) {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(file.string(), aiProcess_ValidateDataStructure);
    EXPECT_TRUE(scene) << importer.GetErrorString();
    ReadBack out;
    for (unsigned m = 0; scene && m < scene->mNumMeshes; ++m) {
        const aiMesh* mesh = scene->mMeshes[m];
        std::set<std::string> names;
        for (unsigned b = 0; b < mesh->mNumBones; ++b) names.insert(mesh->mBones[b]->mName.C_Str());
        out.bones.push_back(std::move(names));
        std::vector<glm::vec3> v;
        for (unsigned i = 0; i < mesh->mNumVertices; ++i) v.emplace_back(mesh->mVertices[i].x, mesh->mVertices[i].y, mesh->mVertices[i].z);
        out.vertices.push_back(std::move(v));
    }
    return out;
}

// export --rig with a skinned rig: each retargeted character wears the rig's
// own mesh (its vertices, bind space, weights), not capsules; the FBX has a
// bone for every joint of the rig's skeleton (Blender shows them all).
TEST(RigExport, SkinnedRigsMeshIsCopiedAndEveryBoneWritten) {
    TempFolder dir;
    auto mixamo = loadMotion(writeText(dir, "mixamo.bvh", kMixamoRig));
    ASSERT_TRUE(mixamo) << mixamo.error().message;
    const Skeleton& sk = mixamo->skeleton();  // centimetres
    const fs::path rigFile = dir.path() / "mixamo_skinned.glb";
    {  // The rig as a GLB written by Fray's own glTF writer, one character in its rest pose.
        exporter::SampledScene rigScene;
        exporter::CharacterTake take;
        take.name = take.fileName = "mixamo";
        take.motion = Motion(sk, 30.0, 2);
        take.skin = coatSkin(sk);
        rigScene.characters.push_back(std::move(take));
        rigScene.frames = 2;
        std::ofstream f(rigFile, std::ios::binary);
        f << exporter::writeGltf(rigScene, "rig", exporter::GltfContainer::Binary);
    }
    auto rig = loadRigSkeleton(rigFile);
    ASSERT_TRUE(rig) << rig.error().message;
    ASSERT_TRUE(rig->skinned);
    ASSERT_TRUE(rig->skin.has_value()) << (rig->warnings.empty() ? "" : rig->warnings.back());
    const std::size_t vertices = rig->skin->vertices.size();
    const std::size_t capsuleVertices = exporter::exportBody(rig->target.skeleton, nullptr).positions.size();
    ASSERT_GT(vertices, 0u);
    for (auto format : {exporter::Format::Fbx, exporter::Format::Glb}) {
        TempFolder out;
        auto o = optionsFor(format, out.path() / "out");
        o.rig = rig->target;
        o.rigSkin = std::make_shared<const SkinnedMesh>(*rig->skin);
        o.rootMotion = exporter::RootMotion::Floor;
        auto report = exporter::exportScene(exportDuel(), exportLibrary(), o);
        ASSERT_TRUE(report) << report.error().message;
        bool said = false;
        for (const auto& n : report->notes) said = said || n.find("wear the rig's own skinned mesh") != std::string::npos;
        EXPECT_TRUE(said);
        const ReadBack back = readBack(out.path() / "out" / (format == exporter::Format::Fbx ? "duel.fbx" : "duel.glb"));
        ASSERT_EQ(back.vertices.size(), 2u);
        const float unit = format == exporter::Format::Fbx ? 0.01f : 1.0f;  // FBX in centimetres
        const std::vector<glm::vec3> capsules = exporter::exportBody(rig->target.skeleton, nullptr).positions;
        // Distance from p to the nearest of `points`.
        auto nearest = [](const glm::vec3& p, const std::vector<glm::vec3>& points) {
            float best = 1e9f;
            for (const glm::vec3& q : points) best = std::min(best, glm::length(p - q));
            return static_cast<double>(best);
        };
        std::vector<glm::vec3> rigVertices;
        for (const SkinnedVertex& v : rig->skin->vertices) rigVertices.push_back(v.position);
        for (std::size_t m = 0; m < 2; ++m) {
            // Assimp's FBX reader unshares vertices per face corner; glTF keeps them.
            if (format == exporter::Format::Glb) {
                EXPECT_EQ(back.vertices[m].size(), vertices);
            }
            EXPECT_GE(back.vertices[m].size(), vertices);
            // Every joint of the rig's skeleton and the root bone is a bone.
            EXPECT_EQ(back.bones[m].size(), static_cast<std::size_t>(rig->target.skeleton.jointCount() + 1));
            double worst = 0, offCapsules = 0;
            for (std::size_t v = 0; v < back.vertices[m].size(); v += 7) {
                worst = std::max(worst, nearest(back.vertices[m][v] * unit, rigVertices));
                offCapsules = std::max(offCapsules, nearest(back.vertices[m][v] * unit, capsules));
            }
            EXPECT_LT(worst, 1e-3) << "bind-space vertices are the rig's";
            EXPECT_GT(offCapsules, 0.02) << "not the capsule body";
        }
        std::printf("%s: %zu vertices per character (the rig's; capsules would be %zu), %zu bones\n",
                    format == exporter::Format::Fbx ? "FBX" : "GLB", back.vertices[0].size(), capsuleVertices, back.bones[0].size());
    }
}

// The CMU base skeleton (bones only): every joint is a bone of the FBX, the
// root bone included (Blender showed 18 of 23 when only joints with capsule
// vertices were bones), and the body stays Fray's capsules.
TEST(RigExport, BonesOnlyRigKeepsCapsulesWithEveryJointABone) {
    if (!requireSharedMocap()) return;
    auto rig = loadRigSkeleton(sharedMocap() / "cmu_fbx/Base.fbx");
    ASSERT_TRUE(rig) << rig.error().message;
    EXPECT_FALSE(rig->skin.has_value());
    TempFolder out;
    auto o = optionsFor(exporter::Format::Fbx, out.path() / "out");
    o.rig = rig->target;
    o.rootMotion = exporter::RootMotion::Floor;
    auto report = exporter::exportScene(exportDuel(), exportLibrary(), o);
    ASSERT_TRUE(report) << report.error().message;
    const ReadBack back = readBack(out.path() / "out" / "duel.fbx");
    ASSERT_EQ(back.bones.size(), 2u);
    const std::size_t capsules = exporter::exportBody(rig->target.skeleton, nullptr).positions.size();
    for (std::size_t m = 0; m < 2; ++m) {
        EXPECT_EQ(back.bones[m].size(), static_cast<std::size_t>(rig->target.skeleton.jointCount() + 1));
        EXPECT_GE(back.vertices[m].size(), capsules);
    }
}

TEST(RigExport, BadRigsAndTakesSayWhatIsMissing) {
    TempFolder dir;
    // A rig without legs.
    const fs::path noFeet = writeText(dir, "nofeet.bvh", R"(HIERARCHY
ROOT Hips
{
  OFFSET 0 100 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine
  {
    OFFSET 0 20 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT Head
    {
      OFFSET 0 40 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {
        OFFSET 0 20 0
      }
    }
  }
}
MOTION
Frames: 1
Frame Time: 0.0333333
0 100 0 0 0 0 0 0 0 0 0 0
)");
    auto r = loadRigSkeleton(noFeet);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("no feet found"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("leftFoot"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("nofeet.bvh"), std::string::npos) << r.error().message;
    // A take whose joints no convention names: what is missing, and its joints.
    std::string odd = kMixamoRig;
    int renamed = 0;
    for (const std::string from : {"LeftToeBase", "RightToeBase", "LeftFoot", "RightFoot", "LeftUpLeg", "RightUpLeg", "LeftLeg", "RightLeg"})
        for (std::size_t at; (at = odd.find(from)) != std::string::npos;) odd.replace(at, from.size(), "Bone" + std::to_string(renamed++));
    auto take = readBvhFromMemory(odd, "odd.bvh");
    ASSERT_TRUE(take) << take.error().message;
    auto target = loadMotion(writeText(dir, "mixamo.bvh", kMixamoRig));
    ASSERT_TRUE(target);
    auto out = retarget(*take, retargetTargetFromRest(target->skeleton(), "mixamo.bvh"));
    ASSERT_FALSE(out);
    EXPECT_NE(out.error().message.find("odd.bvh"), std::string::npos) << out.error().message;
    EXPECT_NE(out.error().message.find("rightFoot"), std::string::npos) << out.error().message;
    // Not a rig at all.
    auto missing = loadRigSkeleton(dir / "none.fbx");
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("file not found"), std::string::npos);
    const fs::path garbage = writeText(dir, "garbage.gltf", "{ not json");
    auto bad = loadRigSkeleton(garbage);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("garbage.gltf"), std::string::npos);
}

}  // namespace
}  // namespace fray::test
