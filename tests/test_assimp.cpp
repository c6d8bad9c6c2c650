// Tests of the Assimp importer (fray::importWithAssimp).
//
// Real data: every FBX and every BVH in the shared mocap folder. For BVH files
// the importer is checked against our own reader: same frame count as listed in
// the shared README, same world joint positions (within 1e-4 m after identical
// normalisation) joint by joint. Where the two disagree because Assimp reads a
// file differently, the difference is asserted and documented in
// docs/ASSIMP_NOTES.md rather than skipped.
//
// Synthetic data (written to a temporary folder): small BVH files with
// position channels on non-root joints, and a glTF (two animations, a
// transformed parent above the skeleton, scale keys) and a DAE (matrix keys)
// with poses worked out by hand, which also pin down the aiQuaternion
// (w, x, y, z) -> glm conversion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "fray/core/kinematics.h"
#include "fray/core/normalize.h"
#include "fray/io/assimp_import.h"
#include "fray/io/bvh.h"
#include "fray/io/import.h"
#include "temp_dir.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace fray;

namespace {

fs::path mocapRoot() { return fray::test::sharedMocap(); }
bool haveMocap() { return fray::test::requireSharedMocap(); }
using fray::test::sharedFiles;

// Frame counts, joints and channels as listed in /work/shared/mocap/README.md.
struct ListedBvh {
    const char* file;  // relative to mocap/
    double fps;
    int frames;
    int joints;
    int channels;
};
constexpr ListedBvh kListedBvh[] = {
    {"bandai/dataset-1_call_normal_001.bvh", 30, 171, 22, 132},
    {"bandai/dataset-1_dash_active_001.bvh", 30, 85, 22, 132},
    {"bandai/dataset-1_dash_normal_001.bvh", 30, 20, 22, 132},
    {"bandai/dataset-1_dash_tired_001.bvh", 30, 93, 22, 132},
    {"bandai/dataset-1_guide_normal_001.bvh", 30, 86, 22, 132},
    {"bandai/dataset-1_respond_normal_001.bvh", 30, 106, 22, 132},
    {"bandai/dataset-1_run_active_001.bvh", 30, 72, 22, 132},
    {"bandai/dataset-1_run_normal_001.bvh", 30, 24, 22, 132},
    {"bandai/dataset-1_run_tired_001.bvh", 30, 133, 22, 132},
    {"bandai/dataset-1_walk-back_normal_001.bvh", 30, 31, 22, 132},
    {"bandai/dataset-1_walk-back_tired_001.bvh", 30, 217, 22, 132},
    {"bandai/dataset-1_walk-left_normal_001.bvh", 30, 135, 22, 132},
    {"bandai/dataset-1_walk-left_tired_001.bvh", 30, 138, 22, 132},
    {"bandai/dataset-1_walk-right_normal_001.bvh", 30, 135, 22, 132},
    {"bandai/dataset-1_walk-right_tired_001.bvh", 30, 134, 22, 132},
    {"bandai/dataset-1_walk_active_001.bvh", 30, 146, 22, 132},
    {"bandai/dataset-1_walk_normal_001.bvh", 30, 195, 22, 132},
    {"bandai/dataset-1_walk_tired_001.bvh", 30, 247, 22, 132},
    {"bandai/dataset-2_run_active_001.bvh", 30, 68, 22, 132},
    {"bandai/dataset-2_run_exhausted_001.bvh", 30, 147, 22, 132},
    {"bandai/dataset-2_run_normal_001.bvh", 30, 68, 22, 132},
    {"bandai/dataset-2_walk-turn-left_active_001.bvh", 30, 130, 22, 132},
    {"bandai/dataset-2_walk-turn-left_exhausted_001.bvh", 30, 205, 22, 132},
    {"bandai/dataset-2_walk-turn-left_normal_001.bvh", 30, 102, 22, 132},
    {"bandai/dataset-2_walk-turn-right_active_001.bvh", 30, 133, 22, 132},
    {"bandai/dataset-2_walk-turn-right_exhausted_001.bvh", 30, 248, 22, 132},
    {"bandai/dataset-2_walk-turn-right_normal_001.bvh", 30, 100, 22, 132},
    {"bandai/dataset-2_walk_exhausted_001.bvh", 30, 289, 22, 132},
    {"bandai/dataset-2_walk_normal_001.bvh", 30, 273, 22, 132},
    {"cmu135_karate/bassai.bvh", 120.005, 6116, 19, 66},
    {"cmu135_karate/empi001.bvh", 120.005, 5202, 19, 66},
    {"cmu135_karate/empi003.bvh", 120.005, 2749, 19, 66},
    {"cmu135_karate/frontkick001.bvh", 120.005, 1316, 19, 66},
    {"cmu135_karate/gedanbarai.bvh", 120.005, 2460, 19, 66},
    {"cmu135_karate/heiansyodan.bvh", 120.005, 3261, 19, 66},
    {"cmu135_karate/mawashigeri.bvh", 120.005, 1472, 19, 66},
    {"cmu135_karate/motorcycle.bvh", 120.005, 291, 19, 66},
    {"cmu135_karate/oiduki001.bvh", 120.005, 2150, 19, 66},
    {"cmu135_karate/syutouuke.bvh", 120.005, 2001, 19, 66},
    {"cmu135_karate/yokogeri001.bvh", 120.005, 2446, 19, 66},
    {"cmu14/14_14.bvh", 120, 4653, 31, 96},
    {"fair_animateddrawings/pick_something_up.bvh", 119.875, 1659, 27, 84},
    {"fair_animateddrawings/pushing.bvh", 119.875, 2475, 27, 84},
    {"lafan1/fallAndGetUp1_subject1.bvh", 30, 5047, 22, 69},
    {"lafan1/fallAndGetUp3_subject1.bvh", 30, 3066, 22, 69},
    {"lafan1/multipleActions1_subject1.bvh", 30, 4587, 22, 69},
    {"lafan1/push1_subject2.bvh", 30, 3066, 22, 69},
    {"lafan1/pushAndFall1_subject1.bvh", 30, 4959, 22, 69},
    {"lafan1/walk4_subject1.bvh", 30, 4918, 22, 69},
};

// Assimp's BVH loader turns "End Site" blocks into nodes named
// "EndSite_<joint>" (some versions "<joint>_End"); they are not joints of ours.
bool isEndSiteNode(std::string_view name) {
    return name.substr(0, 8) == "EndSite_" || (name.size() > 4 && name.substr(name.size() - 4) == "_End");
}

// Joints whose position channels our reader dropped as world positions,
// parsed from its warnings ("joint 'thorax': position channels hold world ...").
std::set<std::string> foreignPositionJoints(const Motion& m) {
    std::set<std::string> out;
    for (const auto& w : m.source().warnings) {
        if (w.find("position channels hold world positions") == std::string::npos) continue;
        const auto a = w.find('\'');
        const auto b = w.find('\'', a + 1);
        if (a != std::string::npos && b != std::string::npos) out.insert(w.substr(a + 1, b - a - 1));
    }
    return out;
}

// Names of the given joints and all their descendants.
std::set<std::string> withDescendants(const Skeleton& sk, const std::set<std::string>& names) {
    std::set<std::string> out;
    std::vector<char> in(static_cast<std::size_t>(sk.jointCount()), 0);
    for (int j = 0; j < sk.jointCount(); ++j) {
        const auto uj = static_cast<std::size_t>(j);
        in[uj] = names.count(sk.names[uj]) || (sk.parents[uj] >= 0 && in[static_cast<std::size_t>(sk.parents[uj])]);
        if (in[uj]) out.insert(sk.names[uj]);
    }
    return out;
}

struct WorldDiff {
    double max = 0.0;   // metres (or file units before normalisation)
    std::string where;  // joint and frame of the maximum
    int framesCompared = 0;
    int jointsCompared = 0;
};

// Largest distance between the world positions of joints with the same name,
// over frames 0, step, 2*step, ... and the last frame. Joints in `exclude` are
// skipped; every other joint of `a` must exist in `b`, and with `sameJoints`
// also the other way round (Assimp end-site nodes aside).
WorldDiff compareWorld(const Motion& a, const Motion& b, const std::set<std::string>& exclude, int step,
                       bool sameJoints = true) {
    WorldDiff d;
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    const Skeleton& sa = a.skeleton();
    const Skeleton& sb = b.skeleton();
    for (int j = 0; j < sa.jointCount(); ++j) {
        const std::string& name = sa.names[static_cast<std::size_t>(j)];
        const int k = sb.find(name);
        EXPECT_GE(k, 0) << "joint '" << name << "' missing from the second motion";
        if (k < 0 || exclude.count(name)) continue;
        pairs.emplace_back(static_cast<std::size_t>(j), static_cast<std::size_t>(k));
    }
    for (int k = 0; sameJoints && k < sb.jointCount(); ++k) {
        const std::string& name = sb.names[static_cast<std::size_t>(k)];
        if (!isEndSiteNode(name)) {
            EXPECT_GE(sa.find(name), 0) << "joint '" << name << "' missing from the first motion";
        }
    }
    d.jointsCompared = static_cast<int>(pairs.size());
    const int frames = std::min(a.frameCount(), b.frameCount());
    std::vector<glm::vec3> pa(static_cast<std::size_t>(a.jointCount())), pb(static_cast<std::size_t>(b.jointCount()));
    std::vector<glm::quat> ra(pa.size()), rb(pb.size());
    auto compareFrame = [&](int f) {
        worldTransforms(a, f, pa, ra);
        worldTransforms(b, f, pb, rb);
        ++d.framesCompared;
        for (const auto& [j, k] : pairs) {
            const double dist = static_cast<double>(glm::length(pa[j] - pb[k]));
            if (dist > d.max) {
                d.max = dist;
                d.where = sa.names[j] + " @ frame " + std::to_string(f);
            }
        }
    };
    for (int f = 0; f < frames; f += step) compareFrame(f);
    if (frames > 0 && (frames - 1) % step != 0) compareFrame(frames - 1);
    return d;
}

// Standing height: the height of the head joint (the joint named "...head")
// above the lowest joint along Y (normalised motion), 90th percentile over
// sampled frames: the actor upright, not crouched, kicking or on the floor
// (85_12 is mostly jumps and spins, its median is about 1.0 m).
double standingHeight(const Motion& m) {
    int head = -1;
    for (int j = 0; j < m.jointCount() && head < 0; ++j) {
        std::string n = m.skeleton().names[static_cast<std::size_t>(j)];
        std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (n.size() >= 4 && n.substr(n.size() - 4) == "head") head = j;
    }
    EXPECT_GE(head, 0) << "no joint named ...head";
    if (head < 0 || m.frameCount() == 0) return 0.0;
    std::vector<glm::vec3> pos(static_cast<std::size_t>(m.jointCount()));
    std::vector<double> heights;
    const int step = std::max(1, m.frameCount() / 200);
    for (int f = 0; f < m.frameCount(); f += step) {
        worldPositions(m, f, pos);
        float lowest = pos[0].y;
        for (const auto& p : pos) lowest = std::min(lowest, p.y);
        heights.push_back(static_cast<double>(pos[static_cast<std::size_t>(head)].y - lowest));
    }
    std::sort(heights.begin(), heights.end());
    return heights[heights.size() * 9 / 10];
}

// A fresh folder for a test's files.
struct TempDir : test::TempDir {
    TempDir() : test::TempDir("fray_assimp_test_") {}
};

void writeText(const fs::path& p, std::string_view text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
}

}  // namespace

// ---------------------------------------------------------------------------
// FBX (CMU conversions in Unity humanoid naming)

TEST(AssimpFbx, EveryCmuFbxImportsWithAPlausibleActor) {
    if (!haveMocap()) return;
    const fs::path dir = mocapRoot() / "cmu_fbx";
    ASSERT_TRUE(fs::is_directory(dir)) << dir << " missing";
    int animated = 0;
    for (const auto& file : sharedFiles(".fbx")) {
        if (file.parent_path() != dir) continue;
        SCOPED_TRACE(file.string());
        auto m = importWithAssimp(file);
        if (file.filename() == "Base.fbx") {
            ASSERT_FALSE(m.ok()) << "Base.fbx has no animation; the import must fail";
            EXPECT_NE(m.error().message.find("no animation"), std::string::npos) << m.error().message;
            EXPECT_NE(m.error().message.find("Base.fbx"), std::string::npos) << m.error().message;
            EXPECT_EQ(m.error().message.find('\n'), std::string::npos) << "one-line message expected";
            continue;
        }
        ASSERT_TRUE(m.ok()) << m.error().message;
        ++animated;
        const Skeleton& sk = m->skeleton();
        EXPECT_FALSE(sk.validate().has_value()) << *sk.validate();
        EXPECT_GE(m->jointCount(), 15);
        EXPECT_LE(m->jointCount(), 80);
        EXPECT_GE(m->frameCount(), 100);
        EXPECT_LE(m->frameCount(), 100000);
        EXPECT_NEAR(m->fps(), 30.0, 1e-6);  // the files' keys are 30 fps frames
        EXPECT_EQ(m->source().format, "fbx");
        EXPECT_EQ(m->source().path, file.string());
        for (const auto& n : sk.names) EXPECT_EQ(n.find("$AssimpFbx$"), std::string::npos) << n;
        EXPECT_EQ(sk.names[0], "Neo_Hips");
        EXPECT_EQ(sk.channels[0].size(), 6u);
        for (int j = 1; j < sk.jointCount(); ++j) {
            const auto& ch = sk.channels[static_cast<std::size_t>(j)];
            ASSERT_TRUE(ch.size() == 3 || ch.size() == 6) << sk.names[static_cast<std::size_t>(j)];
            EXPECT_EQ(ch[ch.size() - 3], Channel::Zrotation);
            EXPECT_EQ(sk.rotationOrders[static_cast<std::size_t>(j)], RotationOrder::ZXY);
        }

        auto n = loadMotion(file);
        ASSERT_TRUE(n.ok()) << n.error().message;
        EXPECT_TRUE(n->source().normalized);
        EXPECT_EQ(n->source().unitName, "cm");
        EXPECT_EQ(n->source().sourceUp, UpAxis::Y);
        const double h = standingHeight(*n);
        std::cout << "[ fbx      ] " << file.filename().string() << ": " << n->jointCount() << " joints, "
                  << n->frameCount() << " frames, standing height " << h << " m\n";
        EXPECT_GE(h, 1.4);
        EXPECT_LE(h, 2.0);
    }
    EXPECT_EQ(animated, 3) << "expected 135_01, 135_02 and 85_12 in " << dir;
}

// Folding Assimp's "$AssimpFbx$" helper nodes (pre-rotation, ...) must give the
// same motion as letting Assimp bake them.
TEST(AssimpFbx, PivotHelperNodesFoldIntoTheirJoints) {
    if (!haveMocap()) return;
    const fs::path file = mocapRoot() / "cmu_fbx/135_01.fbx";
    auto baked = importWithAssimp(file);
    AssimpImportOptions opt;
    opt.preserveFbxPivots = true;
    auto folded = importWithAssimp(file, opt);
    ASSERT_TRUE(baked.ok()) << baked.error().message;
    ASSERT_TRUE(folded.ok()) << folded.error().message;
    EXPECT_EQ(baked->skeleton().names, folded->skeleton().names);
    EXPECT_EQ(baked->skeleton().parents, folded->skeleton().parents);
    ASSERT_EQ(baked->frameCount(), folded->frameCount());
    for (std::size_t j = 0; j < baked->skeleton().offsets.size(); ++j)
        EXPECT_LT(glm::length(baked->skeleton().offsets[j] - folded->skeleton().offsets[j]), 1e-3f)
            << baked->skeleton().names[j];
    const WorldDiff d = compareWorld(*baked, *folded, {}, 1);
    EXPECT_LT(d.max, 1e-2) << "cm, at " << d.where;  // 0.1 mm
}

TEST(AssimpFbx, ErrorsNameTheFileAndTheProblem) {
    if (!haveMocap()) return;
    const fs::path file = mocapRoot() / "cmu_fbx/135_02.fbx";
    AssimpImportOptions opt;
    opt.animation = "no such take";
    auto m = importWithAssimp(file, opt);
    ASSERT_FALSE(m.ok());
    const std::string& msg = m.error().message;
    EXPECT_NE(msg.find("135_02.fbx"), std::string::npos) << msg;
    EXPECT_NE(msg.find("no such take"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'135_02'"), std::string::npos) << "available names must be listed: " << msg;

    opt.animation = "135_02";
    EXPECT_TRUE(importWithAssimp(file, opt).ok());

    AssimpImportOptions rootOpt;
    rootOpt.skeletonRoot = "Neo_Spine2";
    auto upper = importWithAssimp(file, rootOpt);
    ASSERT_TRUE(upper.ok()) << upper.error().message;
    EXPECT_EQ(upper->skeleton().names[0], "Neo_Spine2");
    EXPECT_GE(upper->skeleton().find("Neo_Head"), 0);
    EXPECT_LT(upper->skeleton().find("Neo_LeftFoot"), 0);
    // The upper body keeps its place in the scene: same world positions as in
    // the full skeleton.
    auto full = importWithAssimp(file);
    ASSERT_TRUE(full.ok());
    EXPECT_LT(upper->jointCount(), full->jointCount());
    const WorldDiff d = compareWorld(*upper, *full, {}, 7, /*sameJoints=*/false);
    EXPECT_LT(d.max, 1e-3) << d.where;

    rootOpt.skeletonRoot = "Nobody";
    auto none = importWithAssimp(file, rootOpt);
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().message.find("'Nobody'"), std::string::npos) << none.error().message;

    auto missing = importWithAssimp(mocapRoot() / "cmu_fbx/does_not_exist.fbx");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("does_not_exist.fbx"), std::string::npos) << missing.error().message;
    EXPECT_EQ(missing.error().message.find('\n'), std::string::npos) << missing.error().message;
}

// ---------------------------------------------------------------------------
// BVH: Assimp against our reader on every shared file

TEST(AssimpBvh, FrameCountsMatchTheReadme) {
    if (!haveMocap()) return;
    std::set<std::string> listed;
    for (const ListedBvh& l : kListedBvh) listed.insert(l.file);
    std::set<std::string> present;
    for (const auto& p : sharedFiles(".bvh")) present.insert(fs::relative(p, mocapRoot()).generic_string());
    EXPECT_EQ(listed, present) << "the table in this test must list exactly the shared BVH files";
    for (const ListedBvh& l : kListedBvh) {
        SCOPED_TRACE(l.file);
        auto a = importWithAssimp(mocapRoot() / l.file);
        ASSERT_TRUE(a.ok()) << a.error().message;
        EXPECT_EQ(a->frameCount(), l.frames);
        EXPECT_EQ(a->jointCount(), l.joints);
        EXPECT_NEAR(a->fps(), l.fps, 0.01);
    }
}

TEST(AssimpBvh, SameWorldPositionsAsOurReaderOnEverySharedFile) {
    if (!haveMocap()) return;
    const auto start = std::chrono::steady_clock::now();
    std::map<std::string, double> maxPerFolder;
    for (const ListedBvh& l : kListedBvh) {
        const fs::path file = mocapRoot() / l.file;
        const std::string folder = fs::path(l.file).parent_path().string();
        SCOPED_TRACE(l.file);
        auto ours = readBvh(file);
        auto theirs = importWithAssimp(file);
        ASSERT_TRUE(ours.ok()) << ours.error().message;
        ASSERT_TRUE(theirs.ok()) << theirs.error().message;
        EXPECT_EQ(ours->frameCount(), l.frames);
        EXPECT_EQ(theirs->frameCount(), l.frames);
        EXPECT_EQ(ours->skeleton().channelCount(), l.channels);
        EXPECT_NEAR(theirs->fps(), ours->fps(), 1e-3 * ours->fps());
        EXPECT_EQ(theirs->source().format, "bvh");

        // Documented deviation (docs/ASSIMP_NOTES.md, "CMU-135"): these files
        // store world positions in the position channels of inner joints. Our
        // reader detects and drops them; Assimp uses them as local
        // translations, which moves those joints and everything below them.
        const std::set<std::string> foreign = foreignPositionJoints(*ours);
        const std::set<std::string> expected =
            folder == "cmu135_karate" ? std::set<std::string>{"thorax", "head"} : std::set<std::string>{};
        EXPECT_EQ(foreign, expected) << "world-position channels found where none are documented (or vice versa)";
        const std::set<std::string> exclude = withDescendants(ours->skeleton(), foreign);

        // Bandai files give every joint 6 channels; only Hips' positions move.
        // Assimp keeps all of them as position keys; our importer turns the
        // static ones back into rotation-only channels.
        if (folder == "bandai") {
            for (int j = 0; j < theirs->jointCount(); ++j) {
                const std::string& name = theirs->skeleton().names[static_cast<std::size_t>(j)];
                const bool moves = theirs->skeleton().hasPositionChannels(j);
                EXPECT_EQ(moves, j == 0 || name == "Hips") << name;
            }
        }

        normalize(*ours);
        NormalizeOptions same;
        same.unitScale = ours->source().unitScale;
        same.upAxis = ours->source().sourceUp;
        normalize(*theirs, same);
        const WorldDiff d = compareWorld(*ours, *theirs, exclude, 1);
        EXPECT_EQ(d.framesCompared, l.frames);
        EXPECT_EQ(d.jointsCompared, l.joints - static_cast<int>(exclude.size()));
        EXPECT_LT(d.max, 1e-4) << "metres, at " << d.where;
        double& worst = maxPerFolder[folder];
        worst = std::max(worst, d.max);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (const auto& [folder, worst] : maxPerFolder)
        std::cout << "[ bvh      ] " << folder << ": max world position difference " << worst << " m\n";
    std::cout << "[ bvh      ] " << std::size(kListedBvh) << " files compared in " << seconds << " s\n";
}

// The CMU-135 deviation in detail: read literally (world-position detection
// off), our reader agrees with Assimp on every joint, and the thorax/head
// positions Assimp produces are far off where the skeleton puts them.
TEST(AssimpBvh, Cmu135WorldPositionChannelsAreTakenLiterallyByAssimp) {
    if (!haveMocap()) return;
    BvhReadOptions literal;
    literal.ignoreForeignJointPositions = false;
    for (const ListedBvh& l : kListedBvh) {
        if (std::string_view(l.file).substr(0, 14) != "cmu135_karate/") continue;
        const fs::path file = mocapRoot() / l.file;
        SCOPED_TRACE(l.file);
        auto ours = readBvh(file);
        auto raw = readBvh(file, literal);
        auto theirs = importWithAssimp(file);
        ASSERT_TRUE(ours.ok() && raw.ok() && theirs.ok());
        normalize(*ours);
        NormalizeOptions same;
        same.unitScale = ours->source().unitScale;
        same.upAxis = ours->source().sourceUp;
        EXPECT_NEAR(same.unitScale.value_or(0.0), 0.0254, 1e-9);  // inches
        normalize(*raw, same);
        normalize(*theirs, same);

        const WorldDiff literalDiff = compareWorld(*raw, *theirs, {}, 3);
        EXPECT_LT(literalDiff.max, 1e-4) << "at " << literalDiff.where;

        // Assimp's thorax and head sit far from ours (more than 30 cm on average:
        // the world position is applied a second time on top of the pelvis).
        const int thorax = ours->skeleton().find("thorax");
        const int head = ours->skeleton().find("head");
        const int ta = theirs->skeleton().find("thorax");
        const int ha = theirs->skeleton().find("head");
        ASSERT_TRUE(thorax >= 0 && head >= 0 && ta >= 0 && ha >= 0);
        EXPECT_TRUE(theirs->skeleton().hasPositionChannels(ta));
        EXPECT_TRUE(theirs->skeleton().hasPositionChannels(ha));
        std::vector<glm::vec3> po(static_cast<std::size_t>(ours->jointCount())),
            pt(static_cast<std::size_t>(theirs->jointCount()));
        double thoraxSum = 0.0, headSum = 0.0, boneSum = 0.0;
        int n = 0;
        for (int f = 0; f < ours->frameCount(); f += 10, ++n) {
            worldPositions(*ours, f, po);
            worldPositions(*theirs, f, pt);
            const auto ut = static_cast<std::size_t>(thorax), uh = static_cast<std::size_t>(head);
            thoraxSum += static_cast<double>(glm::length(po[ut] - pt[static_cast<std::size_t>(ta)]));
            headSum += static_cast<double>(glm::length(po[uh] - pt[static_cast<std::size_t>(ha)]));
            boneSum += static_cast<double>(glm::length(pt[static_cast<std::size_t>(ha)] - pt[static_cast<std::size_t>(ta)]));
        }
        const double meanThorax = thoraxSum / n, meanHead = headSum / n, meanNeck = boneSum / n;
        std::cout << "[ cmu135   ] " << fs::path(l.file).filename().string() << ": Assimp thorax off by " << meanThorax
                  << " m, head by " << meanHead << " m on average; Assimp thorax-head distance " << meanNeck
                  << " m (skeleton: " << 0.0254 * 18.21355 << " m)\n";
        EXPECT_GT(meanThorax, 0.3);
        EXPECT_GT(meanHead, 0.3);
    }
}

// ---------------------------------------------------------------------------
// Synthetic files (no shared data needed)

// A non-root joint with moving position channels, another with static ones,
// mixed rotation orders and an End Site: Assimp's reading equals ours.
TEST(AssimpBvh, PositionChannelsOnInnerJointsAndRotationOrders) {
    TempDir tmp;
    const fs::path file = tmp.path() / "inner.bvh";
    writeText(file,
              "HIERARCHY\n"
              "ROOT Hips\n{\n  OFFSET 1 2 3\n  CHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation\n"
              "  JOINT Chest\n  {\n    OFFSET 0 10 0\n    CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n"
              "    JOINT Head\n    {\n      OFFSET 0 8 1\n      CHANNELS 3 Xrotation Zrotation Yrotation\n"
              "      End Site\n      {\n        OFFSET 0 5 0\n      }\n    }\n  }\n"
              "  JOINT Leg\n  {\n    OFFSET 3 -2 0\n    CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
              "    End Site\n    {\n      OFFSET 0 -20 0\n    }\n  }\n}\n"
              "MOTION\nFrames: 4\nFrame Time: 0.04\n"
              "0 90 0 0 0 0   0 10 0 0 0 0   0 0 0   3 -2 0 0 0 0\n"
              "1 91 2 10 20 30   0.5 11 -1 40 -50 60   15 25 -35   3 -2 0 10 20 30\n"
              "2 92 4 -80 45 170   -1 9 2 -90 89 1   100 -120 60   3 -2 0 -30 0 45\n"
              "3 93 6 179 -179 0   0 10.5 0 0 180 -90   -45 45 -45   3 -2 0 0 90 0\n");
    auto ours = readBvh(file);
    auto theirs = importWithAssimp(file);
    ASSERT_TRUE(ours.ok()) << ours.error().message;
    ASSERT_TRUE(theirs.ok()) << theirs.error().message;
    EXPECT_EQ(theirs->frameCount(), 4);
    EXPECT_NEAR(theirs->fps(), 25.0, 1e-4);
    EXPECT_EQ(theirs->skeleton().names, (std::vector<std::string>{"Hips", "Chest", "Head", "Leg"}));
    EXPECT_EQ(theirs->skeleton().parents, (std::vector<int>{-1, 0, 1, 0}));
    EXPECT_TRUE(theirs->skeleton().hasPositionChannels(1));   // Chest moves
    EXPECT_FALSE(theirs->skeleton().hasPositionChannels(2));  // Head: rotation only
    EXPECT_FALSE(theirs->skeleton().hasPositionChannels(3));  // Leg: 6 channels, static
    for (const auto& o : theirs->skeleton().endSites) EXPECT_FALSE(o.has_value());
    EXPECT_EQ(glm::length(theirs->skeleton().offsets[0] - glm::vec3(1, 2, 3)), 0.0f);
    const WorldDiff d = compareWorld(*ours, *theirs, {}, 1);
    EXPECT_EQ(d.framesCompared, 4);
    EXPECT_LT(d.max, 1e-4) << "file units, at " << d.where;
    // Local data too: translations (rest offset included) and rotations.
    for (int f = 0; f < 4; ++f)
        for (int j = 0; j < 4; ++j) {
            const auto uj = static_cast<std::size_t>(j);
            EXPECT_LT(glm::length(ours->translations(f)[uj] - theirs->translations(f)[uj]), 1e-4f) << f << "/" << j;
            EXPECT_GT(std::abs(glm::dot(ours->rotations(f)[uj], theirs->rotations(f)[uj])), 1.0f - 1e-6f) << f << "/" << j;
        }
    // Resampling on request: 50 fps over 0.12 s gives 7 frames.
    AssimpImportOptions opt;
    opt.fps = 50.0;
    auto fast = importWithAssimp(file, opt);
    ASSERT_TRUE(fast.ok());
    EXPECT_EQ(fast->frameCount(), 7);
    EXPECT_DOUBLE_EQ(fast->fps(), 50.0);
    // Frame 1 of the 50 fps take lies halfway between the first two frames.
    const glm::vec3 mid = 0.5f * (ours->rootTranslation(0) + ours->rootTranslation(1));
    EXPECT_LT(glm::length(fast->rootTranslation(1) - mid), 1e-4f);
}

// Documented deviation (docs/ASSIMP_NOTES.md, "Position channels"): Assimp's
// BVH loader reads position channels only on joints with exactly 6 channels.
// A joint with 3 position channels and no rotation keeps its rest offset in
// Assimp; our reader moves it.
TEST(AssimpBvh, PositionOnlyChannelsAreIgnoredByAssimp) {
    TempDir tmp;
    const fs::path file = tmp.path() / "posonly.bvh";
    writeText(file,
              "HIERARCHY\nROOT A\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
              " JOINT B\n {\n  OFFSET 0 1 0\n  CHANNELS 3 Xposition Yposition Zposition\n"
              "  End Site\n  {\n   OFFSET 0 2 0\n  }\n }\n}\n"
              "MOTION\nFrames: 2\nFrame Time: 0.5\n0 0 0 0 0 0 5 5 5\n1 0 0 0 0 0 6 6 6\n");
    auto ours = readBvh(file);
    auto theirs = importWithAssimp(file);
    ASSERT_TRUE(ours.ok()) << ours.error().message;
    ASSERT_TRUE(theirs.ok()) << theirs.error().message;
    ASSERT_EQ(theirs->frameCount(), 2);
    for (int f = 0; f < 2; ++f) {
        const float v = 5.0f + static_cast<float>(f);
        EXPECT_EQ(ours->translations(f)[1], glm::vec3(v, v, v));
        EXPECT_EQ(theirs->translations(f)[1], glm::vec3(0, 1, 0));  // the offset, channels ignored
        EXPECT_EQ(theirs->rootTranslation(f), ours->rootTranslation(f));
    }
    EXPECT_FALSE(theirs->skeleton().hasPositionChannels(1));
}

namespace {

// Minimal glTF: Armature (moved, turned 90 degrees about Y) > Hips > Spine > Head,
// plus a static "Prop" node. Animation "Wave" moves Hips, turns Spine 0 -> 90
// degrees about Z over one second, keys Head's rotation (constant) and scale
// (1 -> 2). Animation "Idle" keys only Spine, at 0 and 2 seconds.
void writeGltf(const fs::path& dir) {
    const float s = std::sqrt(0.5f);
    const std::vector<float> data = {
        0, 1,                    // 0: times 0..1 s             (offset 0)
        0, 0, 0, 1, 0, 0, s, s,  // 1: rotations, x y z w       (offset 8)
        0, 1, 0, 1, 1, 0,        // 2: Hips translations        (offset 40)
        1, 1, 1, 2, 2, 2,        // 3: Head scales              (offset 64)
        0, 0, 0, 1, 0, 0, 0, 1,  // 4: identity rotations       (offset 88)
        0, 2,                    // 5: times 0..2 s             (offset 120)
    };
    {
        std::ofstream bin(dir / "anim.bin", std::ios::binary);
        bin.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size() * sizeof(float)));
    }
    writeText(dir / "anim.gltf", R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 4]}],
  "nodes": [
    {"name": "Armature", "translation": [2, 0, 0], "rotation": [0, 0.70710678, 0, 0.70710678], "children": [1]},
    {"name": "Hips", "translation": [0, 1, 0], "children": [2]},
    {"name": "Spine", "translation": [0, 0.5, 0], "children": [3]},
    {"name": "Head", "translation": [0, 0.5, 0]},
    {"name": "Prop", "translation": [5, 0, 0]}
  ],
  "buffers": [{"uri": "anim.bin", "byteLength": 128}],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 8},
    {"buffer": 0, "byteOffset": 8, "byteLength": 32},
    {"buffer": 0, "byteOffset": 40, "byteLength": 24},
    {"buffer": 0, "byteOffset": 64, "byteLength": 24},
    {"buffer": 0, "byteOffset": 88, "byteLength": 32},
    {"buffer": 0, "byteOffset": 120, "byteLength": 8}
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
    {"bufferView": 1, "componentType": 5126, "count": 2, "type": "VEC4"},
    {"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"},
    {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
    {"bufferView": 4, "componentType": 5126, "count": 2, "type": "VEC4"},
    {"bufferView": 5, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [2]}
  ],
  "animations": [
    {"name": "Wave",
     "samplers": [{"input": 0, "output": 1}, {"input": 0, "output": 2}, {"input": 0, "output": 3}, {"input": 0, "output": 4}],
     "channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}},
                  {"sampler": 1, "target": {"node": 1, "path": "translation"}},
                  {"sampler": 2, "target": {"node": 3, "path": "scale"}},
                  {"sampler": 3, "target": {"node": 3, "path": "rotation"}}]},
    {"name": "Idle",
     "samplers": [{"input": 5, "output": 4}],
     "channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}}]}
  ]
})");
}

}  // namespace

namespace {

// The same scene and "Wave" motion as the glTF above, as COLLADA: matrix keys
// (Assimp decomposes them), no scale keys.
void writeDae(const fs::path& file) {
    writeText(file, R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_animations>
    <animation id="Hips_anim">
      <source id="Hips_in"><float_array id="Hips_in_a" count="2">0 1</float_array>
        <technique_common><accessor source="#Hips_in_a" count="2" stride="1"><param name="TIME" type="float"/></accessor></technique_common></source>
      <source id="Hips_out"><float_array id="Hips_out_a" count="32">1 0 0 0 0 1 0 1 0 0 1 0 0 0 0 1  1 0 0 1 0 1 0 1 0 0 1 0 0 0 0 1</float_array>
        <technique_common><accessor source="#Hips_out_a" count="2" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
      <source id="Hips_interp"><Name_array id="Hips_interp_a" count="2">LINEAR LINEAR</Name_array>
        <technique_common><accessor source="#Hips_interp_a" count="2" stride="1"><param name="INTERPOLATION" type="name"/></accessor></technique_common></source>
      <sampler id="Hips_sampler"><input semantic="INPUT" source="#Hips_in"/><input semantic="OUTPUT" source="#Hips_out"/><input semantic="INTERPOLATION" source="#Hips_interp"/></sampler>
      <channel source="#Hips_sampler" target="Hips/transform"/>
    </animation>
    <animation id="Spine_anim">
      <source id="Spine_in"><float_array id="Spine_in_a" count="2">0 1</float_array>
        <technique_common><accessor source="#Spine_in_a" count="2" stride="1"><param name="TIME" type="float"/></accessor></technique_common></source>
      <source id="Spine_out"><float_array id="Spine_out_a" count="32">1 0 0 0 0 1 0 0.5 0 0 1 0 0 0 0 1  0 -1 0 0 1 0 0 0.5 0 0 1 0 0 0 0 1</float_array>
        <technique_common><accessor source="#Spine_out_a" count="2" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
      <source id="Spine_interp"><Name_array id="Spine_interp_a" count="2">LINEAR LINEAR</Name_array>
        <technique_common><accessor source="#Spine_interp_a" count="2" stride="1"><param name="INTERPOLATION" type="name"/></accessor></technique_common></source>
      <sampler id="Spine_sampler"><input semantic="INPUT" source="#Spine_in"/><input semantic="OUTPUT" source="#Spine_out"/><input semantic="INTERPOLATION" source="#Spine_interp"/></sampler>
      <channel source="#Spine_sampler" target="Spine/transform"/>
    </animation>
    <animation id="Head_anim">
      <source id="Head_in"><float_array id="Head_in_a" count="2">0 1</float_array>
        <technique_common><accessor source="#Head_in_a" count="2" stride="1"><param name="TIME" type="float"/></accessor></technique_common></source>
      <source id="Head_out"><float_array id="Head_out_a" count="32">1 0 0 0 0 1 0 0.5 0 0 1 0 0 0 0 1  1 0 0 0 0 1 0 0.5 0 0 1 0 0 0 0 1</float_array>
        <technique_common><accessor source="#Head_out_a" count="2" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
      <source id="Head_interp"><Name_array id="Head_interp_a" count="2">LINEAR LINEAR</Name_array>
        <technique_common><accessor source="#Head_interp_a" count="2" stride="1"><param name="INTERPOLATION" type="name"/></accessor></technique_common></source>
      <sampler id="Head_sampler"><input semantic="INPUT" source="#Head_in"/><input semantic="OUTPUT" source="#Head_out"/><input semantic="INTERPOLATION" source="#Head_interp"/></sampler>
      <channel source="#Head_sampler" target="Head/transform"/>
    </animation>
  </library_animations>
  <library_visual_scenes>
    <visual_scene id="Scene" name="Scene">
      <node id="Armature" name="Armature" type="NODE">
        <matrix sid="transform">0 0 1 2 0 1 0 0 -1 0 0 0 0 0 0 1</matrix>
        <node id="Hips" name="Hips" sid="Hips" type="JOINT">
          <matrix sid="transform">1 0 0 0 0 1 0 1 0 0 1 0 0 0 0 1</matrix>
          <node id="Spine" name="Spine" sid="Spine" type="JOINT">
            <matrix sid="transform">1 0 0 0 0 1 0 0.5 0 0 1 0 0 0 0 1</matrix>
            <node id="Head" name="Head" sid="Head" type="JOINT">
              <matrix sid="transform">1 0 0 0 0 1 0 0.5 0 0 1 0 0 0 0 1</matrix>
            </node>
          </node>
        </node>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>)");
}

// Checks the "Wave" motion sampled at 4 fps against poses worked out by hand:
// the Armature turns +90 degrees about Y (x -> -z, z -> x) and sits at (2, 0, 0);
// Hips moves along its x by 1 and Spine turns 0 -> 90 degrees about Z over 1 s.
void expectWavePoses(const Motion& m) {
    EXPECT_EQ(m.skeleton().names, (std::vector<std::string>{"Hips", "Spine", "Head"}));
    EXPECT_EQ(m.skeleton().parents, (std::vector<int>{-1, 0, 1}));
    ASSERT_EQ(m.frameCount(), 5);
    EXPECT_DOUBLE_EQ(m.fps(), 4.0);
    EXPECT_FALSE(m.skeleton().validate().has_value());
    // Rest offsets; the root's includes the Armature transform.
    EXPECT_LT(glm::length(m.skeleton().offsets[0] - glm::vec3(2, 1, 0)), 1e-5f);
    EXPECT_LT(glm::length(m.skeleton().offsets[1] - glm::vec3(0, 0.5f, 0)), 1e-6f);
    EXPECT_TRUE(m.skeleton().hasPositionChannels(0));
    EXPECT_FALSE(m.skeleton().hasPositionChannels(1));
    EXPECT_FALSE(m.skeleton().hasPositionChannels(2));

    std::vector<glm::vec3> p(3);
    worldPositions(m, 0, p);
    EXPECT_LT(glm::length(p[0] - glm::vec3(2, 1, 0)), 1e-5f);
    EXPECT_LT(glm::length(p[1] - glm::vec3(2, 1.5f, 0)), 1e-5f);
    EXPECT_LT(glm::length(p[2] - glm::vec3(2, 2, 0)), 1e-5f);
    worldPositions(m, 2, p);  // t = 0.5 s: Hips moved by (0.5, 0, 0), Spine turned 45 degrees (slerp)
    EXPECT_LT(glm::length(p[0] - glm::vec3(2, 1, -0.5f)), 1e-5f);
    EXPECT_LT(glm::length(p[1] - glm::vec3(2, 1.5f, -0.5f)), 1e-5f);
    const float h = 0.5f * std::sqrt(0.5f);
    EXPECT_LT(glm::length(p[2] - glm::vec3(2, 1.5f + h, -0.5f + h)), 1e-5f) << p[2].x << " " << p[2].y << " " << p[2].z;
    worldPositions(m, 4, p);  // t = 1 s: Spine turned 90 degrees about Z
    EXPECT_LT(glm::length(p[0] - glm::vec3(2, 1, -1)), 1e-5f);
    EXPECT_LT(glm::length(p[2] - glm::vec3(2, 1.5f, -0.5f)), 1e-5f) << p[2].x << " " << p[2].y << " " << p[2].z;
    // Local rotation of Spine at t = 1 s: 90 degrees about Z, (x, y, z, w) = +-(0, 0, s, s).
    const glm::quat r = m.rotations(4)[1];
    EXPECT_NEAR(static_cast<double>(std::abs(r.z)), std::sqrt(0.5), 1e-5);
    EXPECT_NEAR(static_cast<double>(std::abs(r.w)), std::sqrt(0.5), 1e-5);
    EXPECT_GT(static_cast<double>(r.z * r.w), 0.0);  // +90 degrees, not -90
    EXPECT_NEAR(static_cast<double>(r.x), 0.0, 1e-6);
    EXPECT_NEAR(static_cast<double>(r.y), 0.0, 1e-6);
}

}  // namespace

TEST(AssimpGltf, KnownPosesThroughAParentTransformAndSlerp) {
    TempDir tmp;
    writeGltf(tmp.path());
    const fs::path file = tmp.path() / "anim.gltf";
    AssimpImportOptions opt;
    opt.fps = 4.0;
    auto m = importWithAssimp(file, opt);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->source().format, "gltf");
    expectWavePoses(*m);
    bool scaleWarning = false;
    for (const auto& w : m->source().warnings) scaleWarning = scaleWarning || w.find("'Head': scale keys") != std::string::npos;
    EXPECT_TRUE(scaleWarning) << "scale keys must be reported as ignored";

    // Default rate: keys one second apart give 1 fps, 2 frames.
    auto byKeys = importWithAssimp(file);
    ASSERT_TRUE(byKeys.ok()) << byKeys.error().message;
    EXPECT_EQ(byKeys->frameCount(), 2);
    EXPECT_NEAR(byKeys->fps(), 1.0, 1e-9);
}

TEST(AssimpDae, KnownPosesFromMatrixKeys) {
    TempDir tmp;
    const fs::path file = tmp.path() / "anim.dae";
    writeDae(file);
    AssimpImportOptions opt;
    opt.fps = 4.0;
    auto m = importWithAssimp(file, opt);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->source().format, "dae");
    expectWavePoses(*m);
    EXPECT_TRUE(m->source().warnings.empty()) << m->source().warnings.front();
}

TEST(AssimpGltf, AnimationChosenByNameAndFallbackRate) {
    TempDir tmp;
    writeGltf(tmp.path());
    const fs::path file = tmp.path() / "anim.gltf";
    AssimpImportOptions opt;
    opt.animation = "Idle";
    auto idle = importWithAssimp(file, opt);
    ASSERT_TRUE(idle.ok()) << idle.error().message;
    // Only Spine is keyed: it is the skeleton root, placed by Armature and Hips;
    // the unkeyed bone below it (Head) stays a joint.
    EXPECT_EQ(idle->skeleton().names, (std::vector<std::string>{"Spine", "Head"}));
    EXPECT_LT(glm::length(idle->skeleton().offsets[0] - glm::vec3(2, 1.5f, 0)), 1e-5f);
    // Keys 2 s apart (0.5 fps) are not a frame rate: 30 fps over 2 s, with a warning.
    EXPECT_NEAR(idle->fps(), 30.0, 1e-9);
    EXPECT_EQ(idle->frameCount(), 61);
    bool rateWarning = false;
    for (const auto& w : idle->source().warnings) rateWarning = rateWarning || w.find("30 fps") != std::string::npos;
    EXPECT_TRUE(rateWarning);

    opt.animation = "Run";
    auto run = importWithAssimp(file, opt);
    ASSERT_FALSE(run.ok());
    EXPECT_NE(run.error().message.find("'Run'"), std::string::npos) << run.error().message;
    EXPECT_NE(run.error().message.find("'Wave', 'Idle'"), std::string::npos) << run.error().message;
    EXPECT_NE(run.error().message.find("anim.gltf"), std::string::npos) << run.error().message;
}

TEST(AssimpErrors, UnreadableFileGivesAssimpsReason) {
    TempDir tmp;
    const fs::path junk = tmp.path() / "junk.fbx";
    writeText(junk, "this is not an FBX file at all\n");
    auto m = importWithAssimp(junk);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().message.find(junk.string()), std::string::npos) << m.error().message;
    EXPECT_NE(m.error().message.find("Assimp"), std::string::npos) << m.error().message;
    EXPECT_EQ(m.error().message.find('\n'), std::string::npos) << m.error().message;

    // A scene without animation: the skeleton alone.
    const fs::path still = tmp.path() / "still.gltf";
    writeText(still, R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"name": "Hips"}]})");
    auto s = importWithAssimp(still);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("no animation"), std::string::npos) << s.error().message;
}
