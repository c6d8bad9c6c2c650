// Rig loader (fray::loadRig): Fray's own GLB and FBX exports bound back to
// the skeleton they came from, hand-made glTF rigs whose names, bind frames
// and axes differ from the skeleton's, and broken files as clear errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <stdexcept>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include "fray/core/body_mesh.h"
#include "fray/core/kinematics.h"
#include "fray/demo/demo_actor.h"
#include "fray/io/bvh.h"
#include "assimp_errors.h"  // core/io
#include "fray/io/rig_import.h"
#include "rig_fixture.h"
#include "rig.h"  // core/export/src: the exporter's bind pose
#include "temp_dir.h"

namespace fray::test {
namespace {

namespace fs = std::filesystem;

const Skeleton& demoSkeleton() {
    static const Skeleton sk = demo::makeDemoSkeleton();
    return sk;
}

// A pose with every joint turned a little (about changing axes) and the root moved.
struct Posed {
    std::vector<glm::vec3> positions;
    std::vector<glm::quat> rotations;
};
Posed somePose(const Skeleton& sk) {
    const auto n = static_cast<std::size_t>(sk.jointCount());
    std::vector<glm::vec3> t(sk.offsets.begin(), sk.offsets.end());
    std::vector<glm::quat> r(n);
    for (std::size_t j = 0; j < n; ++j) {
        const float a = 0.15f + 0.05f * static_cast<float>(j % 5);
        r[j] = glm::angleAxis(a, glm::normalize(glm::vec3(std::sin(1.7f * static_cast<float>(j)), 1.0f, std::cos(0.9f * static_cast<float>(j)))));
    }
    t[0] += glm::vec3(0.4f, 0.9f, -0.3f);
    Posed p;
    p.positions.resize(n);
    p.rotations.resize(n);
    forwardKinematics(sk, t, r, p.positions, p.rotations);
    return p;
}

// The capsules posed as the renderer poses them (vertices in joint space).
std::vector<glm::vec3> posedCapsules(const Skeleton& sk, const Posed& p) {
    std::vector<glm::vec3> out;
    for (const BodyVertex& v : buildBodyMesh(sk).vertices) out.push_back(p.positions[v.joint] + p.rotations[v.joint] * v.position);
    return out;
}

float maxDistance(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    float d = 0.0f;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) d = std::max(d, glm::length(a[i] - b[i]));
    return d;
}

// Smallest box around the points.
std::pair<glm::vec3, glm::vec3> box(const std::vector<glm::vec3>& pts) {
    glm::vec3 lo(1e9f), hi(-1e9f);
    for (const glm::vec3& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
    return {lo, hi};
}

void expectWellFormed(const SkinnedMesh& m, const Skeleton& sk) {
    EXPECT_TRUE(checkSkinnedMesh(m, sk).ok());
    for (const SkinnedVertex& v : m.vertices) {
        const float sum = v.weights.x + v.weights.y + v.weights.z + v.weights.w;
        ASSERT_NEAR(sum, 1.0f, 1e-5f);
        ASSERT_GT(v.weights.x, 0.0f);
        ASSERT_GE(v.weights.x, v.weights.y);
        for (int k = 0; k < 4; ++k) ASSERT_LT(v.joints[static_cast<std::size_t>(k)], sk.jointCount());
    }
}

Result<SkinnedMesh> loadText(const TempDir& dir, const std::string& name, const std::string& text, const Skeleton& sk) {
    writeBytes(dir / name, text);
    return loadRig(dir / name, sk);
}

void expectError(const Result<SkinnedMesh>& r, const fs::path& file, std::initializer_list<const char*> parts) {
    ASSERT_FALSE(r.ok()) << "expected an error for " << file;
    const std::string& msg = r.error().message;
    EXPECT_EQ(msg.rfind(file.string() + ": ", 0), 0u) << "the message must start with the file: " << msg;
    for (const char* p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
}

TEST(RigImport, FraysGlbBindsEveryVertexAndPosesLikeTheCapsules) {
    TempDir dir("fray_rig_test_");
    const Skeleton& sk = demoSkeleton();
    writeExportedRig(sk, dir / "rig.glb", false);
    auto rig = loadRig(dir / "rig.glb", sk);
    ASSERT_TRUE(rig.ok()) << rig.error().message;
    expectWellFormed(*rig, sk);
    EXPECT_TRUE(rig->warnings.empty()) << rig->warnings.front();
    EXPECT_EQ(rig->vertices.size(), exporter::bindMesh(sk).positions.size());
    EXPECT_EQ(rig->indices.size(), buildBodyMesh(sk).indices.size());
    EXPECT_EQ(rig->source, (dir / "rig.glb").string());
    // Every joint found its bone, and sits where the exporter's bind pose has it.
    const auto bind = exporter::bindPositions(sk);
    const auto rigBind = jointBindPositions(*rig);
    for (int j = 0; j < sk.jointCount(); ++j) {
        const auto u = static_cast<std::size_t>(j);
        EXPECT_EQ(rig->boneOfJoint[u], sk.names[u]);
        EXPECT_LT(glm::length(rigBind[u] - bind[u]), 1e-5f) << sk.names[u];
    }
    // Posed, the rig is the capsule body: vertex for vertex (the exporter
    // writes the capsules in order, rigidly bound).
    const Posed p = somePose(sk);
    EXPECT_LT(maxDistance(skinOnCpu(*rig, p.positions, p.rotations), posedCapsules(sk, p)), 1e-4f);
    // The body reaches about a capsule radius (plus the head's length) beyond its joints.
    EXPECT_GT(rig->reach, 0.05f);
    EXPECT_LT(rig->reach, 0.5f);
}

TEST(RigImport, FraysFbxInCentimetresFitsTheSkeletonInMetres) {
    TempDir dir("fray_rig_test_");
    const Skeleton& sk = demoSkeleton();
    writeExportedRig(sk, dir / "rig.fbx", true, "red");
    auto rig = loadRig(dir / "rig.fbx", sk);
    ASSERT_TRUE(rig.ok()) << rig.error().message;
    expectWellFormed(*rig, sk);
    // Joints are "red_Hips", ...: matched without the shared prefix.
    for (int j = 0; j < sk.jointCount(); ++j) EXPECT_EQ(rig->boneOfJoint[static_cast<std::size_t>(j)], "red_" + sk.names[static_cast<std::size_t>(j)]);
    const auto bind = exporter::bindPositions(sk);
    const auto rigBind = jointBindPositions(*rig);
    for (std::size_t j = 0; j < bind.size(); ++j) EXPECT_LT(glm::length(rigBind[j] - bind[j]), 1e-4f) << sk.names[j];
    // The FBX has one vertex per triangle corner: compare the posed bodies' extents.
    const Posed p = somePose(sk);
    const auto [lo, hi] = box(skinOnCpu(*rig, p.positions, p.rotations));
    const auto [clo, chi] = box(posedCapsules(sk, p));
    EXPECT_LT(glm::length(lo - clo), 1e-3f);
    EXPECT_LT(glm::length(hi - chi), 1e-3f);
}

TEST(RigImport, NamesMatchIgnoringCaseAndNamespaces) {
    TempDir dir("fray_rig_test_");
    const Skeleton& sk = demoSkeleton();
    const std::vector<std::pair<std::string, std::string>> styles{{"mixamorig:", ""}, {"Armature|", ""}, {"", "upper"}};
    for (std::size_t style = 0; style < styles.size(); ++style) {
        const auto& [prefix, mode] = styles[style];
        Skeleton renamed = sk;
        for (std::string& n : renamed.names) {
            if (mode == "upper") std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
            n = prefix + n;
        }
        const fs::path file = dir / ("rig" + std::to_string(style) + ".glb");
        writeExportedRig(renamed, file, false);
        auto rig = loadRig(file, sk);
        ASSERT_TRUE(rig.ok()) << rig.error().message;
        for (std::size_t j = 0; j < sk.names.size(); ++j) EXPECT_EQ(rig->boneOfJoint[j], renamed.names[j]);
        // The exporter sized the capsules by the renamed joints' roles.
        const Posed p = somePose(sk);
        EXPECT_LT(maxDistance(skinOnCpu(*rig, p.positions, p.rotations), posedCapsules(renamed, p)), 1e-4f) << file;
    }
}

TEST(RigImport, BonesThatMatchNoJointAreNamed) {
    TempDir dir("fray_rig_test_");
    const Skeleton& sk = demoSkeleton();
    Skeleton renamed = sk;
    renamed.names[static_cast<std::size_t>(sk.find("LeftHand"))] = "Tail";
    renamed.names[static_cast<std::size_t>(sk.find("Head"))] = "Antenna";
    writeExportedRig(renamed, dir / "odd.glb", false);
    expectError(loadRig(dir / "odd.glb", sk), dir / "odd.glb", {"2 bones match no joint", "'Tail'", "'Antenna'", "'Hips'"});
}

TEST(RigImport, AssimpsInternalChecksThrowInsteadOfAborting) {
    // Debian's Assimp has its assertions on; fray_io replaces the handler
    // (core/io/assimp_errors.cpp) so a failed one throws, which Assimp's
    // importer reports as a read error, instead of calling abort().
    EXPECT_THROW(Assimp::aiAssertViolation("out_idx != nullptr", "FBXConverter.cpp", 1523), std::runtime_error);
}

// When its check throws, Assimp leaks what it had built so far (about 640 KB,
// all allocated in libassimp): LeakSanitizer is told to ignore allocations
// made during these loads only.
Result<SkinnedMesh> loadRigIgnoringAssimpsLeaks(const fs::path& file, const Skeleton& sk) {
#if defined(__SANITIZE_ADDRESS__)
    __lsan_disable();
    auto rig = loadRig(file, sk);
    __lsan_enable();
    return rig;
#else
    return loadRig(file, sk);
#endif
}

TEST(RigImport, DamagedFbxIsAnErrorNotACrash) {
    // One byte changed in Fray's FBX of the demo skeleton: with the exporter
    // of this writing, each of these makes Assimp's FBX converter fail an
    // internal check (FBXConverter.cpp:1523), which used to abort the process.
    TempDir dir("fray_rig_test_");
    const Skeleton& sk = demoSkeleton();
    writeExportedRig(sk, dir / "whole.fbx", true);
    std::ifstream in(dir / "whole.fbx", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const auto& [at, value] : {std::pair<std::size_t, int>{191563, 130}, {208556, 40}, {200351, 201}}) {
        if (at >= bytes.size()) continue;
        std::string damaged = bytes;
        damaged[at] = static_cast<char>(value);
        const fs::path file = dir / ("damaged" + std::to_string(at) + ".fbx");
        writeBytes(file, damaged);
        const auto rig = loadRigIgnoringAssimpsLeaks(file, sk);  // returns, whatever the file holds
        if (!rig.ok()) {
            std::printf("%s\n", rig.error().message.c_str());
            expectError(rig, file, {"Assimp cannot read the file: "});
        }
    }
}

TEST(RigImport, UnreadableFilesGiveAssimpsReason) {
    TempDir dir("fray_rig_test_");
    const Skeleton& sk = demoSkeleton();
    writeExportedRig(sk, dir / "whole.glb", false);
    std::ifstream in(dir / "whole.glb", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    writeBytes(dir / "cut.glb", bytes.substr(0, bytes.size() / 2));
    expectError(loadRig(dir / "cut.glb", sk), dir / "cut.glb", {"Assimp cannot read the file: "});
    expectError(loadText(dir, "notes.txt", "This is not a rig, just some notes.\n", sk), dir / "notes.txt",
                {"Assimp cannot read the file: "});
    expectError(loadText(dir, "notes.glb", "This is not a rig either.\n", sk), dir / "notes.glb", {"Assimp cannot read the file: "});
    expectError(loadRig(dir / "missing.glb", sk), dir / "missing.glb", {"file not found"});
}

TEST(RigImport, AFileWithoutASkinnedMeshSaysSo) {
    TempDir dir("fray_rig_test_");
    MiniRig mini;
    const Skeleton sk = mini.skeleton();
    mini.skinned = false;
    expectError(loadText(dir, "static.gltf", mini.gltf(), sk), dir / "static.gltf", {"no skinned mesh", "1 meshes has bones"});
    expectError(loadText(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", sk), dir / "tri.obj", {"no skinned mesh"});
    // A motion file has bones but no mesh.
    writeBytes(dir / "walk.bvh", writeBvhToString(Motion(demoSkeleton(), 30.0, 2)));
    expectError(loadRig(dir / "walk.bvh", demoSkeleton()), dir / "walk.bvh", {"no mesh in the file"});
}

TEST(RigImport, VerticesWithoutWeightsAreAnError) {
    TempDir dir("fray_rig_test_");
    MiniRig mini;
    mini.unweightedVertex = 6;
    expectError(loadText(dir, "holes.gltf", mini.gltf(), mini.skeleton()), dir / "holes.gltf",
                {"1 of 21 vertices have no bone weights", "vertex 6 of mesh 'body'"});
}

TEST(RigImport, SharedVerticesBlendTheirJoints) {
    TempDir dir("fray_rig_test_");
    MiniRig mini;
    const Skeleton sk = mini.skeleton();
    auto rig = loadText(dir, "mini.gltf", mini.gltf(), sk);
    ASSERT_TRUE(rig.ok()) << rig.error().message;
    expectWellFormed(*rig, sk);
    const SkinnedVertex& shared = rig->vertices.back();
    EXPECT_NEAR(shared.weights.x, 0.5f, 1e-6f);
    EXPECT_NEAR(shared.weights.y, 0.5f, 1e-6f);
    // Posed: halfway between where each joint alone would carry it.
    const Posed p = somePose(sk);
    const auto posed = skinOnCpu(*rig, p.positions, p.rotations);
    const glm::vec3 rest = mini.vertices().back().position;
    const auto restPos = mini.restPositions();  // the bind pose is the rest pose here
    glm::vec3 expected(0.0f);
    for (std::size_t j : {std::size_t{0}, std::size_t{1}}) expected += 0.5f * (p.positions[j] + p.rotations[j] * (rest - restPos[j]));
    EXPECT_LT(glm::length(posed.back() - expected), 1e-5f);
}

// The rigidly bound tetrahedra of MiniRig, posed as capsules would be: each
// keeps its place in its joint's frame of the bind pose.
std::vector<glm::vec3> posedMini(const MiniRig& mini, const Posed& p) {
    const auto bind = mini.bindJoints();
    std::vector<glm::vec3> out;
    const auto verts = mini.vertices();
    for (std::size_t i = 0; i + 1 < verts.size(); ++i) {
        const std::size_t j = verts[i].joints[0];
        const glm::vec3 local = glm::conjugate(bind[j].rotation) * (verts[i].position - bind[j].translation);
        out.push_back(p.positions[j] + p.rotations[j] * local);
    }
    return out;
}

// How far (m) the rig's rigidly bound vertices land, skinned to somePose(),
// from where posedMini puts them (its last, two-joint vertex left out).
float miniSkinningError(const SkinnedMesh& rig, const MiniRig& mini, const Skeleton& sk) {
    const Posed p = somePose(sk);
    auto posed = skinOnCpu(rig, p.positions, p.rotations);
    posed.pop_back();
    return maxDistance(posed, posedMini(mini, p));
}

TEST(RigImport, ARigInAnotherPoseWithTheSkeletonsFramesUsesItsOffsetMatrices) {
    // Modelled with the chest bent and the arm down (as a rig and a motion
    // from the same source: its bone frames are the skeleton's joint frames
    // in that pose): the rest pose would misplace every part above the hips.
    TempDir dir("fray_rig_test_");
    MiniRig mini;
    const Skeleton sk = mini.skeleton();
    mini.bindPose.assign(mini.names.size(), glm::quat(1, 0, 0, 0));
    mini.bindPose[1] = glm::angleAxis(0.5f, glm::vec3(1, 0, 0));
    mini.bindPose[2] = glm::angleAxis(-0.3f, glm::vec3(0, 0, 1));
    mini.bindPose[4] = glm::angleAxis(-1.1f, glm::vec3(0, 0, 1));
    auto rig = loadText(dir, "bent.gltf", mini.gltf(), sk);
    ASSERT_TRUE(rig.ok()) << rig.error().message;
    EXPECT_TRUE(rig->warnings.empty()) << rig->warnings.front();
    EXPECT_LT(miniSkinningError(*rig, mini, sk), 1e-4f);
}

TEST(RigImport, ABindPoseThatFitsNeitherWayIsAWarning) {
    // The arm's bone sits 10 cm from where the skeleton has it.
    TempDir dir("fray_rig_test_");
    MiniRig mini;
    const Skeleton sk = mini.skeleton();
    mini.offsets[4].x += 0.1f;
    auto rig = loadText(dir, "off.gltf", mini.gltf(), sk);
    ASSERT_TRUE(rig.ok()) << rig.error().message;
    ASSERT_EQ(rig->warnings.size(), 1u);
    EXPECT_NE(rig->warnings[0].find("joint 'Arm' is 10.0 cm from where the skeleton puts it"), std::string::npos) << rig->warnings[0];
}

TEST(RigImport, BoneFramesOtherThanTheSkeletonsUseTheRestPose) {
    // Every bone's bind frame turned about its own origin (as tools that aim
    // bones along their length do): the offset matrices alone would twist
    // each part; the rig is in the skeleton's rest pose, so that is its bind.
    TempDir dir("fray_rig_test_");
    MiniRig mini;
    const Skeleton sk = mini.skeleton();
    for (std::size_t j = 0; j < mini.names.size(); ++j)
        mini.boneTurn.push_back(glm::angleAxis(0.4f + 0.3f * static_cast<float>(j), glm::normalize(glm::vec3(1, 2, 0.5f))));
    auto rig = loadText(dir, "turned.gltf", mini.gltf(), sk);
    ASSERT_TRUE(rig.ok()) << rig.error().message;
    EXPECT_TRUE(rig->warnings.empty()) << rig->warnings.front();
    EXPECT_LT(miniSkinningError(*rig, mini, sk), 1e-4f);
}

TEST(RigImport, AZUpRigInCentimetresComesOutYUpInMetres) {
    TempDir dir("fray_rig_test_");
    MiniRig mini;
    const Skeleton sk = mini.skeleton();
    // Y-up to Z-up (+Y -> +Z), metres to centimetres, and the bones turned
    // too, so only the rest pose and the axis search can place it.
    mini.model = glm::scale(glm::mat4(1.0f), glm::vec3(100.0f)) * glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0));
    for (std::size_t j = 0; j < mini.names.size(); ++j) mini.boneTurn.push_back(glm::angleAxis(0.3f * static_cast<float>(j + 1), glm::vec3(0, 0, 1)));
    auto rig = loadText(dir, "zup.gltf", mini.gltf(), sk);
    ASSERT_TRUE(rig.ok()) << rig.error().message;
    const auto bind = jointBindPositions(*rig);
    const auto rest = mini.restPositions();
    for (std::size_t j = 0; j < rest.size(); ++j) EXPECT_LT(glm::length(bind[j] - rest[j]), 1e-4f) << mini.names[j];
    EXPECT_LT(miniSkinningError(*rig, mini, sk), 1e-4f);
    EXPECT_GT(rig->vertices[3].position.y, rig->vertices[0].position.y) << "the bind mesh is upright";
}

TEST(RigImport, ARigOfAnotherSkeletonIsRefusedByTheCheck) {
    TempDir dir("fray_rig_test_");
    MiniRig mini;
    auto rig = loadText(dir, "mini.gltf", mini.gltf(), mini.skeleton());
    ASSERT_TRUE(rig.ok()) << rig.error().message;
    Skeleton other = mini.skeleton();
    other.offsets[1].y += 0.1f;
    const Status s = checkSkinnedMesh(*rig, other);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("bound to another skeleton"), std::string::npos) << s.error().message;
    SkinnedMesh broken = *rig;
    broken.indices.push_back(0);
    EXPECT_FALSE(checkSkinnedMesh(broken, mini.skeleton()).ok());
    broken = *rig;
    broken.vertices[0].weights = glm::vec4(0.7f, 0.0f, 0.0f, 0.0f);
    EXPECT_FALSE(checkSkinnedMesh(broken, mini.skeleton()).ok());
}

}  // namespace
}  // namespace fray::test
