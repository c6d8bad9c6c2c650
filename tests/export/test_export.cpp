// Export as a job: same scene -> same bytes, never overwriting other files,
// every invalid input refused with a message naming it, progress and
// cancellation, and the summary (who does which action when and where).
#include <unistd.h>

#include "export_fixture.h"
#include "fray/core/atomic_file.h"

namespace fray::test {
namespace {

using exporter::Format;

const std::array<Format, 4> kAll = {Format::Gltf, Format::Glb, Format::Bvh, Format::Fbx};

TEST(Export, FormatNamesRoundTrip) {
    for (Format f : kAll) EXPECT_EQ(exporter::parseFormat(exporter::toString(f)), f);
    EXPECT_FALSE(exporter::parseFormat("obj"));
    EXPECT_FALSE(exporter::parseFormat("GLTF"));
}

TEST(Export, SameSceneGivesByteIdenticalFiles) {
    for (Format f : kAll) {
        TempFolder a, b;
        auto ra = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(f, a.path()));
        auto rb = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(f, b.path()));
        ASSERT_TRUE(ra && rb);
        ASSERT_EQ(ra->files.size(), rb->files.size());
        for (std::size_t i = 0; i < ra->files.size(); ++i) {
            EXPECT_EQ(ra->files[i].filename(), rb->files[i].filename());
            const std::string x = readBytes(ra->files[i]);
            EXPECT_GT(x.size(), 100u);
            EXPECT_TRUE(x == readBytes(rb->files[i])) << ra->files[i] << " differs between two exports";
        }
    }
}

TEST(Export, RefusesToOverwriteFilesItDidNotWrite) {
    TempFolder dir;
    ASSERT_TRUE(writeFileAtomically(dir / "duel.gltf", "my notes"));
    auto r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Gltf, dir.path()));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message,
              (dir / "duel.gltf").string() + ": exists and is not a file of an earlier Fray export; refusing to overwrite it");
    EXPECT_EQ(readBytes(dir / "duel.gltf"), "my notes");
    EXPECT_FALSE(fs::exists(dir / "duel.gltf.scene.json")) << "nothing written";

    TempFolder other;
    ASSERT_TRUE(writeFileAtomically(other / "duel.bvh.scene.json", "{\"my\": \"data\"}"));
    r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Bvh, other.path()));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("duel.bvh.scene.json: exists and is not a Fray export summary"), std::string::npos);
    EXPECT_FALSE(fs::exists(other / "duel_a.bvh"));
}

TEST(Export, ReplacesItsOwnFilesAndRemembersThoseItNoLongerWrites) {
    TempFolder dir;
    for (Format f : {Format::Gltf, Format::Bvh, Format::Gltf, Format::Fbx, Format::Bvh}) {
        auto r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(f, dir.path()));
        ASSERT_TRUE(r) << exporter::toString(f) << ": " << r.error().message;
    }
    json summary = json::parse(readBytes(dir / "duel.bvh.scene.json"));
    EXPECT_EQ(summary["files"], json::array({"duel_a.bvh", "duel_b.bvh"}));
    EXPECT_EQ(summary["earlier_files"], json::array());
    // Character b renamed: its old file is an earlier file of this export.
    sim::Scene renamed = exportDuel();
    renamed.characters[1].name = "c";
    ASSERT_TRUE(exporter::exportScene(renamed, exportLibrary(), optionsFor(Format::Bvh, dir.path())));
    summary = json::parse(readBytes(dir / "duel.bvh.scene.json"));
    EXPECT_EQ(summary["files"], json::array({"duel_a.bvh", "duel_c.bvh"}));
    EXPECT_EQ(summary["earlier_files"], json::array({"duel_b.bvh"}));
    // A file an earlier export wrote but that was removed since is forgotten.
    fs::remove(dir / "duel_b.bvh");
    ASSERT_TRUE(exporter::exportScene(renamed, exportLibrary(), optionsFor(Format::Bvh, dir.path())));
    EXPECT_EQ(json::parse(readBytes(dir / "duel.bvh.scene.json"))["earlier_files"], json::array());
}

TEST(Export, InvalidOptionsAreRefusedWithTheReason) {
    TempFolder dir;
    auto tryWith = [&](auto edit) {
        auto o = optionsFor(Format::Gltf, dir / "out");
        edit(o);
        auto r = exporter::exportScene(exportDuel(), exportLibrary(), o);
        return r ? std::string("ok") : r.error().message;
    };
    EXPECT_EQ(tryWith([](auto& o) { o.fps = 0; }), "export: --fps must be between 1 and 1000, got 0.000000");
    EXPECT_NE(tryWith([](auto& o) { o.fps = 5000; }).find("--fps must be between 1 and 1000"), std::string::npos);
    EXPECT_NE(tryWith([](auto& o) { o.fps = std::nan(""); }).find("--fps"), std::string::npos);
    for (const char* bad : {"", "a/b", ".hidden", ".."}) {
        EXPECT_NE(tryWith([&](auto& o) { o.name = bad; }).find("must be a plain file name"), std::string::npos) << bad;
    }
    EXPECT_EQ(tryWith([](auto& o) { o.outDir.clear(); }), "export: no output folder given");
    EXPECT_FALSE(fs::exists(dir / "out")) << "invalid options create nothing";
}

TEST(Export, UnusableFoldersAreRefusedBeforeWritingAnything) {
    TempFolder dir;
    ASSERT_TRUE(writeFileAtomically(dir / "notes.txt", "x"));
    auto r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Gltf, dir / "notes.txt" / "out"));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message.rfind((dir / "notes.txt" / "out").string() + ": cannot create the output folder: ", 0), 0u)
        << r.error().message;
    r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Gltf, dir / "notes.txt"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("notes.txt: "), std::string::npos) << r.error().message;
    // Nobody, root included, can create files in /proc/self.
    r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Gltf, "/proc/self"));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, "/proc/self: cannot write in the output folder (permission denied?)");
    // A read-only folder (only meaningful when not running as root).
    if (geteuid() != 0) {
        fs::create_directories(dir / "ro");
        fs::permissions(dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
        r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Glb, dir / "ro"));
        fs::permissions(dir / "ro", fs::perms::owner_all);
        ASSERT_FALSE(r);
        EXPECT_NE(r.error().message.find("cannot write in the output folder"), std::string::npos);
        EXPECT_TRUE(fs::is_empty(dir / "ro"));
    }
}

TEST(Export, ScenesWithNothingToExportAreRefused) {
    TempFolder dir;
    sim::Scene empty = exportDuel();
    empty.characters.clear();
    auto r = exporter::exportScene(empty, exportLibrary(), optionsFor(Format::Gltf, dir.path()));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, "the scene has no characters: nothing to export");
    sim::Scene idle = exportDuel();
    idle.characters[1].track.clear();
    r = exporter::exportScene(idle, exportLibrary(), optionsFor(Format::Bvh, dir.path()));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, "character 'b' has no action: nothing to export");
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(Export, PosesThatAreNotFiniteAreRefused) {
    TempFolder dir;
    sim::Scene broken = exportDuel();
    broken.characters[0].track.front().root.pos.x = std::nanf("");
    auto r = exporter::exportScene(broken, exportLibrary(), optionsFor(Format::Gltf, dir.path()));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, "character 'a': the pose of joint Hips at 0.000000 s is not finite");
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(Export, ReportsProgressAndCanBeCancelled) {
    TempFolder dir;
    std::vector<double> seen;
    auto r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Glb, dir.path()),
                                   [&](double f, std::string_view) { seen.push_back(f); return true; });
    ASSERT_TRUE(r);
    ASSERT_GE(seen.size(), 3u);
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    EXPECT_EQ(seen.back(), 1.0);
    TempFolder other;
    r = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(Format::Glb, other.path()),
                              [](double, std::string_view) { return false; });
    ASSERT_FALSE(r);
    EXPECT_TRUE(r.error().isCancelled()) << r.error().message;
    EXPECT_TRUE(fs::is_empty(other.path()));
}

TEST(ExportSummary, WhoDoesWhichActionWhenAndWhere) {
    TempFolder dir;
    const auto& scene = exportDuel();
    const auto& lib = exportLibrary();
    ASSERT_TRUE(exporter::exportScene(scene, lib, optionsFor(Format::Glb, dir.path())));
    const json s = json::parse(readBytes(dir / "duel.glb.scene.json"));
    EXPECT_EQ(s["format"], "fray-export");
    EXPECT_EQ(s["source"], "duel.frayscene");
    EXPECT_EQ(s["export_format"], "glb");
    EXPECT_EQ(s["frames"], 181);
    EXPECT_EQ(s["files"], json::array({"duel.glb"}));
    ASSERT_EQ(s["characters"].size(), scene.characters.size());
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        const auto& ch = scene.characters[c];
        const json& cj = s["characters"][c];
        EXPECT_EQ(cj["name"], ch.name);
        EXPECT_EQ(cj["side"], ch.side);
        EXPECT_EQ(cj["enter"].get<double>(), ch.track.front().start);
        ASSERT_EQ(cj["actions"].size(), ch.track.size());
        for (std::size_t k = 0; k < ch.track.size(); ++k) {
            const json& a = cj["actions"][k];
            const auto& inst = ch.track[k];
            EXPECT_EQ(a["label"], lib.actions()[static_cast<std::size_t>(inst.action)].label());
            EXPECT_EQ(a["annotations"], lib.actions()[static_cast<std::size_t>(inst.action)].annotations);
            EXPECT_EQ(a["start"].get<double>(), inst.start);
            EXPECT_EQ(a["end"].get<double>(), inst.end);
            EXPECT_EQ(a["forced"], inst.forced);
            EXPECT_NEAR(a["root"]["x"].get<double>(), inst.root.pos.x, 1e-4);
            EXPECT_NEAR(a["root"]["heading_deg"].get<double>(), inst.root.heading * 180 / 3.14159265358979, 1e-3);
        }
    }
    // Hits: where = the attacker's effector, which was touching the defender's body.
    ASSERT_FALSE(scene.hits.empty()) << "the test scene should have hits";
    ASSERT_EQ(s["hits"].size(), scene.hits.size());
    const sim::ScenePoser poser(scene, lib);
    for (std::size_t h = 0; h < scene.hits.size(); ++h) {
        const json& hj = s["hits"][h];
        const auto& hit = scene.hits[h];
        EXPECT_EQ(hj["attacker"], scene.characters[static_cast<std::size_t>(hit.attacker)].name);
        EXPECT_EQ(hj["defender"], scene.characters[static_cast<std::size_t>(hit.defender)].name);
        ASSERT_TRUE(hj.contains("position"));
        const glm::vec3 at(hj["position"][0].get<float>(), hj["position"][1].get<float>(), hj["position"][2].get<float>());
        std::vector<glm::vec3> body;
        poser.worldPositions(hit.defender, hit.time, body);
        float nearest = 1e9f;
        for (const auto& p : body) nearest = std::min(nearest, glm::length(p - at));
        EXPECT_LT(nearest, 0.35f) << "hit " << h << " at " << hit.time << " s is not on the defender";
        EXPECT_GT(at.y, 0.5f) << "hits land on the head, torso or pelvis";
    }
}

}  // namespace
}  // namespace fray::test
