// Issue 21 (export hardening): FBX animation timing, continuous Euler
// channels (BVH and FBX), per-export summaries with honest units, both ends of
// the scene sampled, file-safe names, and every character of a multi-character
// file read back.
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <charconv>
#include <sstream>

#include "export_fixture.h"
#include "fray/core/atomic_file.h"
#include "fbx_writer.h"
#include "fray/core/rotation.h"
#include "fray/io/assimp_import.h"
#include "fray/io/bvh.h"

namespace fray::test {
namespace {

using exporter::Format;

constexpr double kFbxSecond = 46186158000.0;  // FBX time units per second

exporter::ExportOptions at(Format format, const fs::path& dir, double fps) {
    auto o = optionsFor(format, dir);
    o.fps = fps;
    return o;
}

// The last value of the Properties70 entry `name` under `path` (its type code
// first), read from the file's bytes.
std::string_view p70(std::string_view bytes, std::initializer_list<std::string_view> path, std::string_view name) {
    // Properties70 entries are "P" records whose first property is the name
    // string: find "name" preceded by its 'S' code and length, then skip the
    // type strings to the value. Good enough for the fields tested here.
    const auto props = exporter::fbxPropertyOffset(bytes, path);
    if (!props) return {};
    std::string key = "S";
    const auto n = static_cast<std::uint32_t>(name.size());
    for (int i = 0; i < 4; ++i) key.push_back(static_cast<char>((n >> (8 * i)) & 0xffu));
    key.append(name);
    std::size_t at = bytes.find(key, *props);
    if (at == std::string_view::npos) return {};
    at += key.size();
    for (int s = 0; s < 3; ++s) at += 5 + le32(bytes, at + 1);  // type, label, flags strings
    return bytes.substr(at);
}

std::int64_t le64(std::string_view b) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(b[i])) << (8 * i);
    return static_cast<std::int64_t>(v);
}

// Item 14: the stack spans the keys, the frame rate is the keys' rate, and
// Assimp reads every key back at that rate.
TEST(ExportFbxTiming, StackAndFrameRateMatchTheKeysReadBackByAssimp) {
    // A scene that does not end on a whole second (Assimp cut the stack there).
    sim::Scene scene = exportDuel();
    scene.duration = 5.45;
    for (double fps : {30.0, 24.0, 7.3}) {
        TempFolder dir;
        auto report = exporter::exportScene(scene, exportLibrary(), at(Format::Fbx, dir.path(), fps));
        ASSERT_TRUE(report) << report.error().message;
        const int frames = report->frames;
        const double lastTime = scene.duration;  // both ends sampled
        Assimp::Importer importer;
        const aiScene* ai = importer.ReadFile(report->files.front().string(), 0);
        ASSERT_NE(ai, nullptr) << importer.GetErrorString();
        ASSERT_EQ(ai->mNumAnimations, 1u);
        const aiAnimation* anim = ai->mAnimations[0];
        // Assimp reads CustomFrameRate as a float.
        EXPECT_NEAR(anim->mTicksPerSecond, fps, 1e-6 * fps) << fps << " fps";
        EXPECT_NEAR(anim->mDuration / anim->mTicksPerSecond, lastTime, 1e-6) << fps << " fps";
        ASSERT_GT(anim->mNumChannels, 0u);
        for (unsigned c = 0; c < anim->mNumChannels; ++c) {
            const aiNodeAnim* ch = anim->mChannels[c];
            ASSERT_EQ(ch->mNumPositionKeys, static_cast<unsigned>(frames)) << ch->mNodeName.C_Str() << " at " << fps;
            // No keys dropped at the end, none inserted between (Assimp adds
            // keys where an Euler angle jumps by more than 180 degrees).
            ASSERT_EQ(ch->mNumRotationKeys, static_cast<unsigned>(frames)) << ch->mNodeName.C_Str() << " at " << fps;
            EXPECT_NEAR(ch->mRotationKeys[frames - 1].mTime / anim->mTicksPerSecond, lastTime, 1e-6);
            EXPECT_NEAR(ch->mPositionKeys[1].mTime, 1.0, 1e-6) << "one tick per frame";
        }
        // The file's own fields.
        const std::string bytes = readBytes(report->files.front());
        const auto stop = p70(bytes, {"Objects", "AnimationStack"}, "LocalStop");
        ASSERT_FALSE(stop.empty());
        ASSERT_EQ(stop[0], 'L');
        EXPECT_NEAR(static_cast<double>(le64(stop.substr(1))) / kFbxSecond, lastTime, 1e-6);
        const auto span = p70(bytes, {"GlobalSettings"}, "TimeSpanStop");
        ASSERT_FALSE(span.empty());
        EXPECT_EQ(le64(span.substr(1)), le64(stop.substr(1)));
        const auto mode = p70(bytes, {"GlobalSettings"}, "TimeMode");
        ASSERT_EQ(mode[0], 'I');
        EXPECT_EQ(le32(mode, 1), fps == 30.0 ? 6u : fps == 24.0 ? 11u : 14u) << fps;
        EXPECT_EQ(frames, exporter::exportFrameCount(5.45, fps));
        const auto rate = p70(bytes, {"GlobalSettings"}, "CustomFrameRate");
        ASSERT_EQ(rate[0], 'D');
        double value = 0;
        std::memcpy(&value, rate.data() + 1, sizeof value);
        EXPECT_EQ(value, fps);
    }
}

// Item 15 (FBX): no rotation curve moves by more than 180 degrees between keys.
TEST(ExportFbxTiming, RotationCurvesAreContinuous) {
    TempFolder dir;
    const auto& scene = exportDuel();
    auto report = exporter::exportScene(scene, exportLibrary(), optionsFor(Format::Fbx, dir.path()));
    ASSERT_TRUE(report) << report.error().message;
    const std::string bytes = readBytes(report->files.front());
    const auto curves = exporter::fbxRotationCurves(bytes);
    const sim::ScenePoser poser(scene, exportLibrary());
    std::size_t joints = 0;
    for (std::size_t c = 0; c < scene.characters.size(); ++c)
        joints += static_cast<std::size_t>(poser.skeleton(static_cast<int>(c)).jointCount());
    ASSERT_EQ(curves.size(), joints) << "one rotation curve node per joint";
    int jumps = 0;
    float worst = 0;
    for (const auto& r : curves) {
        ASSERT_EQ(r.axes[0].count, static_cast<std::size_t>(report->frames));
        auto prev = exporter::fbxRotationKey(bytes, r, 0);
        for (std::size_t k = 1; k < r.axes[0].count; ++k) {
            const auto e = exporter::fbxRotationKey(bytes, r, k);
            for (std::size_t a = 0; a < 3; ++a) {
                worst = std::max(worst, std::abs(e[a] - prev[a]));
                jumps += std::abs(e[a] - prev[a]) > 180.0f;
            }
            prev = e;
        }
    }
    EXPECT_EQ(jumps, 0) << "largest step " << worst << " degrees";
}

TEST(ContinuousEuler, NearestEquivalentTripleIsTheSameRotation) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> angle(-180.0, 180.0), prevAngle(-900.0, 900.0);
    for (RotationOrder order : {RotationOrder::XYZ, RotationOrder::XZY, RotationOrder::YXZ, RotationOrder::YZX,
                                RotationOrder::ZXY, RotationOrder::ZYX}) {
        for (int i = 0; i < 200; ++i) {
            const glm::dvec3 e(angle(rng), angle(rng) / 2, angle(rng));
            const glm::dvec3 prev(prevAngle(rng), prevAngle(rng), prevAngle(rng));
            const glm::dvec3 n = nearestEquivalentEuler(e, prev, order);
            const glm::quat a = eulerToQuat(e, order), b = eulerToQuat(n, order);
            EXPECT_GT(std::abs(glm::dot(a, b)), 1.0f - 1e-5f) << "order " << toString(order);
            // Never farther than the plain triple moved by whole turns.
            double plain = 0, got = 0;
            for (int k = 0; k < 3; ++k) {
                plain += std::abs(e[k] - 360.0 * std::round((e[k] - prev[k]) / 360.0) - prev[k]);
                got += std::abs(n[k] - prev[k]);
            }
            EXPECT_LE(got, plain + 1e-9);
        }
        // A wrap: 179 -> -179 about the first axis becomes 181.
        const glm::dvec3 n = nearestEquivalentEuler(glm::dvec3(-179.0, 0.0, 0.0), glm::dvec3(179.0, 0.0, 0.0), order);
        EXPECT_NEAR(n.x, 181.0, 1e-9) << toString(order);
    }
}

// The rotation channels of a BVH text, frame by frame (degrees).
std::vector<std::vector<double>> bvhRotationColumns(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    std::vector<bool> rotation;
    while (std::getline(in, line) && line.rfind("MOTION", 0) != 0) {
        const auto at = line.find("CHANNELS");
        if (at == std::string::npos) continue;
        std::istringstream words(line.substr(at + 8));
        int n = 0;
        words >> n;
        for (std::string w; words >> w;) rotation.push_back(w.find("rotation") != std::string::npos);
    }
    std::getline(in, line);  // Frames:
    std::getline(in, line);  // Frame Time:
    std::vector<std::vector<double>> frames;
    while (std::getline(in, line)) {
        std::istringstream values(line);
        std::vector<double> row;
        double v = 0;
        for (std::size_t c = 0; values >> v; ++c)
            if (c < rotation.size() && rotation[c]) row.push_back(v);
        frames.push_back(std::move(row));
    }
    return frames;
}

// Item 15 (BVH): channels continuous, the motion unchanged.
TEST(ExportBvhEuler, ChannelsNeverJumpByMoreThan180Degrees) {
    TempFolder dir;
    const auto& scene = exportDuel();
    auto report = exporter::exportScene(scene, exportLibrary(), optionsFor(Format::Bvh, dir.path()));
    ASSERT_TRUE(report) << report.error().message;
    int wrapsBefore = 0;
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        const std::string text = readBytes(report->files[c]);
        const auto frames = bvhRotationColumns(text);
        ASSERT_EQ(frames.size(), static_cast<std::size_t>(report->frames));
        int jumps = 0;
        for (std::size_t f = 1; f < frames.size(); ++f) {
            ASSERT_EQ(frames[f].size(), frames[0].size());
            for (std::size_t k = 0; k < frames[f].size(); ++k) jumps += std::abs(frames[f][k] - frames[f - 1][k]) > 180.0;
        }
        EXPECT_EQ(jumps, 0) << report->files[c];
        // The same motion written frame by frame in the principal range does
        // wrap (so this scene exercises the unwrapping).
        auto m = readBvh(report->files[c]);
        ASSERT_TRUE(m) << m.error().message;
        const auto plain = bvhRotationColumns(writeBvhToString(*m));
        for (std::size_t f = 1; f < plain.size(); ++f)
            for (std::size_t k = 0; k < plain[f].size(); ++k) wrapsBefore += std::abs(plain[f][k] - plain[f - 1][k]) > 180.0;
    }
    EXPECT_GT(wrapsBefore, 0) << "the test scene should have angles that wrap";
}

// Item 16: the last frame is at the scene's duration whatever the rate.
TEST(ExportSampling, BothEndsOfTheSceneAreSampled) {
    const auto& scene = exportDuel();
    ASSERT_EQ(scene.duration, 6.0);
    TempFolder dir;
    auto report = exporter::exportScene(scene, exportLibrary(), at(Format::Gltf, dir.path(), 7.3));
    ASSERT_TRUE(report) << report.error().message;
    EXPECT_EQ(report->frames, 45);  // 0, 1/7.3, ..., 43/7.3 = 5.89 s, then 6 s
    const Gltf g = Gltf::fromGltf(readBytes(report->files.front()));
    const int input = g.doc["animations"][0]["samplers"][0]["input"];
    const auto times = g.floats(input);
    ASSERT_EQ(times.size(), 45u);
    EXPECT_EQ(times.front(), 0.0f);
    EXPECT_EQ(times.back(), 6.0f);
    EXPECT_NEAR(times[43], 43 / 7.3, 1e-6);
    EXPECT_EQ(exporter::exportFrameCount(6.0, 30.0), 181);
    EXPECT_EQ(exporter::exportFrameCount(6.0, 7.3), 45);
    const json s = json::parse(readBytes(dir / "duel.gltf.scene.json"));
    EXPECT_EQ(s["last_frame_time"], 6.0);
}

// Item 16: one summary per export, named after it; units say what they measure.
TEST(ExportSummaryFiles, OnePerExportAndHonestUnits) {
    TempFolder dir;
    for (Format f : {Format::Gltf, Format::Fbx, Format::Bvh}) {
        ASSERT_TRUE(exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(f, dir.path())));
    }
    const json gltf = json::parse(readBytes(dir / "duel.gltf.scene.json"));
    const json fbx = json::parse(readBytes(dir / "duel.fbx.scene.json"));
    const json bvh = json::parse(readBytes(dir / "duel.bvh.scene.json"));
    EXPECT_FALSE(fs::exists(dir / "duel.scene.json"));
    EXPECT_EQ(gltf["version"], 2);
    EXPECT_EQ(gltf["export_format"], "gltf");
    EXPECT_EQ(gltf["files"], json::array({"duel.gltf"}));
    EXPECT_EQ(fbx["export_format"], "fbx");
    EXPECT_EQ(fbx["files"], json::array({"duel.fbx"}));
    EXPECT_EQ(bvh["files"], json::array({"duel_a.bvh", "duel_b.bvh"}));
    // The summary's positions are metres whatever the file's unit.
    EXPECT_EQ(fbx["units"], "m");
    EXPECT_EQ(fbx["file_units"], "cm");
    EXPECT_EQ(gltf["units"], "m");
    EXPECT_EQ(gltf["file_units"], "m");
    EXPECT_EQ(gltf["hits"], fbx["hits"]);
    const json& action = fbx["characters"][0]["actions"][0];
    const auto& first = exportLibrary().actions()[static_cast<std::size_t>(exportDuel().characters[0].track[0].action)];
    EXPECT_EQ(action["motion_fps"], exportLibrary().motion(first.motion).motion.fps());
    EXPECT_EQ(action["first_frame"], first.firstFrame);
    ASSERT_FALSE(fbx["hits"].empty());
    EXPECT_TRUE(fbx["hits"][0].contains("action"));
}

// A folder exported by version 1 (one NAME.scene.json): its files may be
// replaced, and the old summary is left alone with a note.
TEST(ExportSummaryFiles, FoldersOfVersionOneCanBeExportedAgain) {
    TempFolder dir;
    ASSERT_TRUE(writeFileAtomically(dir / "duel.gltf", "an old export"));
    ASSERT_TRUE(writeFileAtomically(dir / "duel.scene.json",
                                    R"({"format": "fray-export", "version": 1, "files": ["duel.gltf"]})"));
    auto r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Gltf, dir.path()));
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->notes.size(), 1u);
    EXPECT_NE(r->notes[0].find("duel.scene.json is an older summary"), std::string::npos) << r->notes[0];
    EXPECT_NE(readBytes(dir / "duel.gltf"), "an old export");
    EXPECT_EQ(json::parse(readBytes(dir / "duel.scene.json"))["version"], 1) << "left as it was";
    // It grants nothing it does not list.
    ASSERT_TRUE(writeFileAtomically(dir / "duel.glb", "mine"));
    r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Glb, dir.path()));
    ASSERT_FALSE(r);
    EXPECT_EQ(readBytes(dir / "duel.glb"), "mine");
    // A file of that name that is not a summary of ours is neither read as one nor mentioned.
    TempFolder other;
    ASSERT_TRUE(writeFileAtomically(other / "duel.scene.json", "my notes"));
    r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Gltf, other.path()));
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_TRUE(r->notes.empty());
    EXPECT_EQ(readBytes(other / "duel.scene.json"), "my notes");
}

// Item 16: names that are not file-safe are refused, saying what to use.
TEST(ExportNames, NamesWithSpacesAreRefusedWithASuggestion) {
    TempFolder dir;
    auto o = optionsFor(Format::Gltf, dir / "out", "my duel");
    auto r = exporter::exportScene(exportDuel(), exportLibrary(), o);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message,
              "export: the name 'my duel' has the character ' '; use only letters, digits, '_', '-' and '.' "
              "(e.g. 'my_duel')");
    EXPECT_FALSE(fs::exists(dir / "out"));
    EXPECT_EQ(exporter::fileSafeName("my duel:1"), "my_duel_1");
}

// Item 16: `info` reads every character of Fray's own multi-character files,
// each with its own joints, at the export's rate.
TEST(ExportReadBack, EveryCharacterOfGltfAndFbx) {
    const auto& scene = exportDuel();
    for (Format f : {Format::Glb, Format::Fbx}) {
        TempFolder dir;
        auto report = exporter::exportScene(scene, exportLibrary(), at(f, dir.path(), 24.0));
        ASSERT_TRUE(report) << report.error().message;
        auto all = importAllWithAssimp(report->files.front());
        ASSERT_TRUE(all) << all.error().message;
        ASSERT_EQ(all->size(), scene.characters.size()) << exporter::toString(f);
        for (std::size_t c = 0; c < all->size(); ++c) {
            const Motion& m = (*all)[c];
            EXPECT_EQ(m.jointCount(), 24) << exporter::toString(f) << " character " << c;
            EXPECT_NEAR(m.fps(), 24.0, 1e-3) << exporter::toString(f);
            EXPECT_EQ(m.frameCount(), report->frames) << exporter::toString(f);
            const std::string prefix = f == Format::Fbx ? scene.characters[c].name + "_" : "";
            EXPECT_EQ(m.skeleton().names.front(), prefix + "Hips");
        }
        // A file with one skeleton still gives one.
        AssimpImportOptions one;
        one.skeletonRoot = (f == Format::Fbx ? scene.characters[1].name + "_" : std::string()) + "Hips";
        if (f == Format::Fbx) {
            auto single = importAllWithAssimp(report->files.front(), one);
            ASSERT_TRUE(single) << single.error().message;
            EXPECT_EQ(single->size(), 1u);
        }
    }
}

}  // namespace
}  // namespace fray::test
