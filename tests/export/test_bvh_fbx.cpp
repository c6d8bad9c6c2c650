// BVH and FBX export read back: our BVH reader and Assimp (BVH, FBX), joint
// for joint against forward kinematics of the scene poser.
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/scene.h>

#include "export_fixture.h"
#include "fbx_writer.h"
#include "fray/core/kinematics.h"
#include "fray/io/assimp_import.h"
#include "fray/io/bvh.h"

namespace fray::test {
namespace {

using exporter::Format;

// World joint positions of character c at frame f of the export (30 fps), in metres.
std::vector<glm::vec3> expectedWorld(const sim::ScenePoser& poser, int c, int frame) {
    std::vector<glm::vec3> out;
    poser.worldPositions(c, frame / 30.0, out);
    return out;
}

double maxWorldError(const Motion& m, const sim::ScenePoser& poser, int c, float scale, const std::vector<int>& jointOf) {
    double worst = 0;
    std::vector<glm::vec3> got(static_cast<std::size_t>(m.jointCount()));
    for (int f = 0; f < m.frameCount(); f += 7) {
        worldPositions(m, f, got);
        const auto want = expectedWorld(poser, c, f);
        for (std::size_t j = 0; j < jointOf.size(); ++j) {
            const glm::vec3 g = got[static_cast<std::size_t>(jointOf[j])] / scale;
            worst = std::max(worst, static_cast<double>(glm::length(g - want[j])));
        }
    }
    return worst;
}

// Joint index in `m` of every joint of `sk`, by name (with an optional prefix in m).
std::vector<int> matchJoints(const Skeleton& sk, const Motion& m, const std::string& prefix = "") {
    std::vector<int> out;
    for (const auto& name : sk.names) {
        const int j = m.skeleton().find(prefix + name);
        EXPECT_GE(j, 0) << "joint " << prefix + name << " missing";
        out.push_back(std::max(j, 0));
    }
    return out;
}

TEST(ExportBvh, OneFilePerCharacterInSceneSpaceReadByOurReader) {
    TempFolder dir;
    const auto& scene = exportDuel();
    auto report = exporter::exportScene(scene, exportLibrary(), optionsFor(Format::Bvh, dir.path()));
    ASSERT_TRUE(report) << report.error().message;
    ASSERT_EQ(report->files.size(), scene.characters.size() + 1);
    const sim::ScenePoser poser(scene, exportLibrary());
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        const auto& ch = scene.characters[c];
        EXPECT_EQ(report->files[c], dir / ("duel_" + ch.name + ".bvh"));
        auto m = readBvh(report->files[c]);
        ASSERT_TRUE(m) << m.error().message;
        const Skeleton& sk = poser.skeleton(static_cast<int>(c));
        EXPECT_EQ(m->jointCount(), sk.jointCount());
        EXPECT_EQ(m->frameCount(), report->frames);
        EXPECT_NEAR(m->fps(), 30.0, 1e-9);
        // The first frame's root is where the scene places the character at
        // time 0 (its first action may start part-way into the clip).
        const auto& first = ch.track.front();
        ASSERT_EQ(first.start, 0.0);
        const sim::RootXf placed = first.placementAt(exportLibrary(), first.offset);
        const glm::vec3 root = m->rootTranslation(0);
        EXPECT_LT(glm::length(glm::vec2(root.x, root.z) - placed.pos), 1e-3f);
        std::vector<glm::vec3> posed;
        poser.worldPositions(static_cast<int>(c), 0.0, posed);
        EXPECT_NEAR(root.y, posed[0].y, 1e-3f);
        std::vector<int> same(static_cast<std::size_t>(sk.jointCount()));
        for (int j = 0; j < sk.jointCount(); ++j) same[static_cast<std::size_t>(j)] = j;
        EXPECT_LT(maxWorldError(*m, poser, static_cast<int>(c), 1.0f, same), 1e-4);
    }
}

TEST(ExportBvh, AssimpReadsTheSameMotion) {
    TempFolder dir;
    const auto& scene = exportDuel();
    auto report = exporter::exportScene(scene, exportLibrary(), optionsFor(Format::Bvh, dir.path()));
    ASSERT_TRUE(report) << report.error().message;
    const sim::ScenePoser poser(scene, exportLibrary());
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        AssimpImportOptions o;
        o.fps = 30.0;
        auto m = importWithAssimp(report->files[c], o);
        ASSERT_TRUE(m) << m.error().message;
        const Skeleton& sk = poser.skeleton(static_cast<int>(c));
        EXPECT_EQ(m->jointCount(), sk.jointCount());
        EXPECT_EQ(m->frameCount(), report->frames);
        EXPECT_LT(maxWorldError(*m, poser, static_cast<int>(c), 1.0f, matchJoints(sk, *m)), 1e-4);
    }
}

TEST(ExportFbx, AssimpReadsSkinnedMeshesAndOneAnimation) {
    TempFolder dir;
    const auto& scene = exportDuel();
    auto report = exporter::exportScene(scene, exportLibrary(), optionsFor(Format::Fbx, dir.path()));
    ASSERT_TRUE(report) << report.error().message;
    Assimp::Importer importer;
    const aiScene* ai = importer.ReadFile(report->files.front().string(), 0);
    ASSERT_NE(ai, nullptr) << importer.GetErrorString();
    const sim::ScenePoser poser(scene, exportLibrary());
    ASSERT_EQ(ai->mNumMeshes, scene.characters.size());
    for (unsigned i = 0; i < ai->mNumMeshes; ++i) {
        EXPECT_GT(ai->mMeshes[i]->mNumBones, 0u);
        EXPECT_GT(ai->mMeshes[i]->mNumFaces, 0u);
    }
    ASSERT_EQ(ai->mNumAnimations, 1u);
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        const Skeleton& sk = poser.skeleton(static_cast<int>(c));
        for (const auto& name : sk.names) {
            EXPECT_NE(ai->mRootNode->FindNode((scene.characters[c].name + "_" + name).c_str()), nullptr) << name;
        }
    }
}

// Assimp 5.2's own FBX output needs repairs before Assimp reads it back (see
// fbx_writer.h); after them its reader reports no error at all.
TEST(ExportFbx, AssimpReadsItWithoutErrors) {
    TempFolder dir;
    auto report = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Fbx, dir.path()));
    ASSERT_TRUE(report) << report.error().message;
    struct Lines : Assimp::LogStream {
        std::vector<std::string> lines;
        void write(const char* message) override { lines.emplace_back(message); }
    };
    Lines errors;
    Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(&errors, Assimp::Logger::Err);
    Assimp::Importer importer;
    const aiScene* ai = importer.ReadFile(report->files.front().string(), 0);
    Assimp::DefaultLogger::get()->detachStream(&errors, Assimp::Logger::Err);
    Assimp::DefaultLogger::kill();
    ASSERT_NE(ai, nullptr) << importer.GetErrorString();
    EXPECT_TRUE(errors.lines.empty()) << errors.lines.size() << " errors, the first: " << errors.lines.front();
}

TEST(ExportFbx, AnimationMatchesTheScenePoserInCentimetres) {
    TempFolder dir;
    const auto& scene = exportDuel();
    auto report = exporter::exportScene(scene, exportLibrary(), optionsFor(Format::Fbx, dir.path()));
    ASSERT_TRUE(report) << report.error().message;
    const sim::ScenePoser poser(scene, exportLibrary());
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        const std::string prefix = scene.characters[c].name + "_";
        AssimpImportOptions o;
        o.fps = 30.0;
        o.skeletonRoot = prefix + poser.skeleton(static_cast<int>(c)).names.front();
        auto m = importWithAssimp(report->files.front(), o);
        ASSERT_TRUE(m) << m.error().message;
        EXPECT_EQ(m->frameCount(), report->frames);
        const auto joints = matchJoints(poser.skeleton(static_cast<int>(c)), *m, prefix);
        EXPECT_LT(maxWorldError(*m, poser, static_cast<int>(c), 100.0f, joints), 1e-4);
    }
}

TEST(ExportFbx, CreationTimeIsFixedSoTheFileIsReproducible) {
    TempFolder dir;
    auto report = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Fbx, dir.path()));
    ASSERT_TRUE(report) << report.error().message;
    const std::string bytes = readBytes(report->files.front());
    for (const auto& [field, value] : {std::pair{"Year", 1970}, {"Month", 1}, {"Day", 1}, {"Hour", 10}, {"Second", 0}}) {
        const auto at = exporter::fbxPropertyOffset(bytes, {"FBXHeaderExtension", "CreationTimeStamp", field});
        ASSERT_TRUE(at) << field;
        ASSERT_EQ(bytes[*at], 'I');
        EXPECT_EQ(static_cast<int>(le32(bytes, *at + 1)), value) << field;
    }
    EXPECT_FALSE(exporter::fbxPropertyOffset(bytes, {"FBXHeaderExtension", "NoSuchNode"}));
    EXPECT_FALSE(exporter::fbxPropertyOffset("not an FBX file", {"FBXHeaderExtension"}));
}

}  // namespace
}  // namespace fray::test
