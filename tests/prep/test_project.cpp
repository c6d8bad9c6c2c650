// Project file, derived-data cache, combination table, annotation proposals.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "fray/prep/annotations.h"
#include "fray/prep/pipeline.h"
#include "fray/prep/project.h"
#include "prep_fixture.h"

using namespace fray::prep;
namespace fs = std::filesystem;

namespace {

Project sampleProject() {
    Project p = makeProject("demo");
    p.vocabulary.push_back("taunt");
    ProjectMotion m;
    m.id = "walk";
    m.path = "takes/walk.bvh";
    m.units = "cm";
    m.actions = MotionActions::whole(300);
    m.actions.cuts = {100, 200};
    m.actions.actions.resize(3);
    m.actions.actions[1].name = "jab";
    m.actions.actions[1].annotations = {"punch", "taunt"};
    m.actions.actions[1].joints = {"RightHand"};
    m.actions.actions[1].attackDirection = "straight";
    m.actions.actions[1].initialConditions = InitialConditions{0.5, 1.2, -0.3, 0.3, 2.8, 3.4, 0.0, 0.2};
    m.contactLabels = {{10, 40, true, false}, {50, 60, std::nullopt, true}};
    p.motions.push_back(m);
    p.combos.set({"sway_back", "@punch", 1.5});
    p.combos.set({"@block", "jab", -0.5});
    p.settings.graphThreshold = 2.5;
    p.laterSections["pattern_lists"] = R"([{"name":"chase"}])";
    return p;
}

fs::path tempDir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / ("fray_prep_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(Project, RoundTripsEverythingAuthored) {
    const Project p = sampleProject();
    const std::string text = projectToJson(p);
    const auto back = projectFromJson(text, "p.frayproj");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(*back, p);
    EXPECT_EQ(projectToJson(*back), text);  // stable, diffable output
}

TEST(Project, ErrorsNameTheJsonPath) {
    const std::string good = projectToJson(sampleProject());
    struct Case {
        std::string from, to, expect;
    };
    const Case cases[] = {
        {"\"cuts\": [\n        100,", "\"cuts\": [\n        \"x\",", "p.frayproj: /motions/0/cuts/0: must be an integer"},
        {"\"cuts\": [\n        100,", "\"cuts\": [\n        250,", "/motions/0/cuts/1: cut 200 must be after 250"},
        {"\"taunt\"\n  ]", "\"Taunt!\"\n  ]", "/vocabulary/18: \"Taunt!\" must be"},
        {"\"version\": 1", "\"version\": 7", "/version: version 7 is not supported"},
        {"\"fray-project\"", "\"something\"", "/format: must be \"fray-project\""},
        {"\"units\": \"cm\"", "\"units\": \"furlong\"", "/motions/0/units: \"furlong\" must be one of"},
        {"\"last_frame\": 40", "\"last_frame\": 400", "/motions/0/contact_labels/0: frames 10..400 are outside"},
        {"\"suitability\": 1.5", "\"suitability\": \"high\"", "/combos/0/suitability: must be a number"},
        {"\"frame_count\": 300", "\"frame_count\": -3", "/motions/0/frame_count: must be at least 1"},
        {"\"name\": \"jab\"", "\"name\": 3", "/motions/0/actions/1/name: must be a string"},
        {"\"punch\",\n            \"taunt\"", "\"punch\",\n            \"kiss\"",
         "/motions/0/actions/1/annotations/1: \"kiss\" is not in the project vocabulary"},
    };
    for (const auto& c : cases) {
        std::string text = good;
        const auto at = text.find(c.from);
        ASSERT_NE(at, std::string::npos) << c.from;
        text.replace(at, c.from.size(), c.to);
        const auto r = projectFromJson(text, "p.frayproj");
        ASSERT_FALSE(r.ok()) << c.to;
        EXPECT_NE(r.error().message.find(c.expect), std::string::npos) << r.error().message;
    }
    // Found by fuzz_prep: a number too large for a double threw out_of_range.
    const auto huge = projectFromJson("{\"format\": 4444E00008000112672126706813412}", "p.frayproj");
    ASSERT_FALSE(huge.ok());
    EXPECT_NE(huge.error().message.find("p.frayproj: not valid JSON"), std::string::npos) << huge.error().message;
    const auto bad = projectFromJson("{\n  \"format\": \"fray-project\",\n  oops\n}", "p.frayproj");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("p.frayproj:3:"), std::string::npos) << bad.error().message;
}

TEST(Project, RandomCorruptionNeverCrashes) {
    const std::string good = projectToJson(sampleProject());
    std::mt19937 rng(7);
    for (int i = 0; i < 2000; ++i) {
        std::string text = good;
        const int edits = 1 + int(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const std::size_t at = rng() % text.size();
            switch (rng() % 3) {
                case 0: text[at] = static_cast<char>(rng() % 128); break;
                case 1: text.erase(at, 1 + rng() % 20); break;
                default: text.resize(at); break;
            }
            if (text.empty()) text = "{";
        }
        const auto r = projectFromJson(text, "fuzz.frayproj");
        if (!r.ok()) {
            EXPECT_EQ(r.error().message.rfind("fuzz.frayproj", 0), 0u) << r.error().message;
        }
    }
}

TEST(Project, SaveIsAtomicAndLoadErrorLeavesFileAlone) {
    const fs::path dir = tempDir("save");
    const fs::path file = dir / "p.frayproj";
    ASSERT_TRUE(saveProject(sampleProject(), file).ok());
    const auto loaded = loadProject(file);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(*loaded, sampleProject());
    {
        std::ofstream(file, std::ios::trunc) << "{ broken";
    }
    const std::string before = readAll(file);
    EXPECT_FALSE(loadProject(file).ok());
    EXPECT_EQ(readAll(file), before);
    EXPECT_NE(loadProject(dir / "missing.frayproj").error().message.find("cannot open"), std::string::npos);
    // Saving into a folder that does not exist fails and creates nothing.
    EXPECT_FALSE(saveProject(sampleProject(), dir / "nope" / "p.frayproj").ok());
    EXPECT_FALSE(fs::exists(dir / "nope"));
    fs::remove_all(dir);
}

TEST(Project, MissingMotionFileIsAClearError) {
    const fs::path dir = tempDir("missing");
    const fs::path file = dir / "p.frayproj";
    const Project p = sampleProject();
    ASSERT_TRUE(saveProject(p, file).ok());
    const auto r = loadProjectMotions(p, file, [](const fs::path&, const ProjectMotion&) -> fray::Result<fray::Motion> {
        return fray::makeError("loader must not be called");
    });
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("/motions/0/path: motion file"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("does not exist"), std::string::npos);
    fs::remove_all(dir);
}

TEST(Cache, RoundTripAndRejectsGarbage) {
    DerivedCache c;
    CachedContacts cc;
    cc.key = 42;
    cc.source = ContactSource::Svm;
    cc.contacts.left = {1, 0, 1};
    cc.contacts.right = {0, 0, 1};
    c.contacts.emplace_back("walk", cc);
    c.graph = CachedGraph{7, 3, {0, 1, 2}, {1, 2, 0}};
    const auto bytes = serializeCache(c);
    const auto back = deserializeCache(bytes);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_NE(back->findContacts("walk", 42), nullptr);
    EXPECT_EQ(back->findContacts("walk", 43), nullptr);
    EXPECT_EQ(back->findContacts("walk", 42)->contacts.right, cc.contacts.right);
    EXPECT_EQ(back->graph->endNode, c.graph->endNode);
    for (std::size_t n = 0; n < bytes.size(); ++n) {
        const std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
        EXPECT_FALSE(deserializeCache(cut).ok()) << n;
    }
    std::mt19937 rng(3);
    for (int i = 0; i < 500; ++i) {
        auto noisy = bytes;
        noisy[8 + rng() % (noisy.size() - 8)] = static_cast<std::uint8_t>(rng());
        (void)deserializeCache(noisy);  // must not crash; may or may not parse
    }
}

TEST(Combos, QueryCsvAndErrors) {
    ComboTable t;
    t.set({"sway_back", "uppercut_right", 2.0});
    t.set({"sway_back", "@punch", 0.5});
    t.set({"@avoid", "@punch", 0.25});
    EXPECT_DOUBLE_EQ(t.query("sway_back", {"avoid"}, "uppercut_right", {"punch"}), 2.0);  // exact pair wins
    EXPECT_DOUBLE_EQ(t.query("sway_back", {"avoid"}, "jab", {"punch"}), 0.75);
    EXPECT_DOUBLE_EQ(t.query("duck", {"avoid"}, "jab", {"punch"}), 0.25);
    EXPECT_DOUBLE_EQ(t.query("jab", {"punch"}, "jab", {"punch"}), 0.0);
    EXPECT_EQ(t.set({"sway_back", "@punch", 1.0}), 0.5);
    const auto back = ComboTable::fromCsv(t.toCsv(), "c.csv");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(*back, t);
    EXPECT_TRUE(t.remove("sway_back", "@punch").has_value());
    EXPECT_FALSE(t.find("sway_back", "@punch"));
    const std::string h = "mine,theirs,suitability\n";
    EXPECT_NE(ComboTable::fromCsv(h + "a,b,x\n", "c.csv").error().message.find("c.csv:2: suitability"),
              std::string::npos);
    EXPECT_NE(ComboTable::fromCsv(h + "a b,b,1\n", "c.csv").error().message.find("c.csv:2: mine"),
              std::string::npos);
    EXPECT_NE(ComboTable::fromCsv(h + "a,b,1\na,b,2\n", "c.csv").error().message.find("appears twice"),
              std::string::npos);
    EXPECT_NE(ComboTable::fromCsv("x,y\n", "c.csv").error().message.find("c.csv:1: header"), std::string::npos);
}

// Proposals on the demo truth: attacks found, idles and falls recognised.
TEST(Annotations, ProposalsAgreeWithTheDemoTruth) {
    int attacks = 0, attacksFound = 0, falls = 0, fallsFound = 0, locomotion = 0, locomotionFound = 0;
    for (const auto& [name, t] : fray::test::demoTakes()) {
        for (const auto& a : t.take.truth.actions) {
            const auto p = proposeAnnotations(t.take.motion, t.joints, t.signals, a.firstFrame, a.lastFrame);
            auto has = [&](const char* w) {
                return std::find(p.annotations.begin(), p.annotations.end(), w) != p.annotations.end();
            };
            if (a.has("punch") || a.has("kick")) {
                ++attacks;
                attacksFound += has(a.has("punch") ? "punch" : "kick") ? 1 : 0;
            }
            if (a.name.rfind("fall_", 0) == 0) {
                ++falls;
                fallsFound += has("falling") ? 1 : 0;
            }
            if (a.has("walk") || a.has("run")) {
                ++locomotion;
                locomotionFound += has("walk") || has("run") ? 1 : 0;
            }
        }
    }
    std::printf("attacks %d/%d, falls %d/%d, locomotion %d/%d\n", attacksFound, attacks, fallsFound, falls,
                locomotionFound, locomotion);
    EXPECT_GE(attacksFound, attacks * 8 / 10);
    EXPECT_GE(fallsFound, falls * 8 / 10);
    EXPECT_GE(locomotionFound, locomotion * 8 / 10);
}

// The contacts of every motion depend on all labels and on the files they
// label: moving a label to another motion, or editing a labelled file, must
// make the cached contacts stale.
TEST(Cache, TrainingKeyFollowsLabelsAndLabelledFiles) {
    Project p = makeProject("k");
    p.motions.resize(2);
    p.motions[0].id = "a";
    p.motions[1].id = "b";
    std::vector<LoadedMotion> loaded(2);
    loaded[0].fileKey = 11;
    loaded[1].fileKey = 22;
    p.motions[0].contactLabels = {{0, 9, true, false}};
    const auto base = trainingKey(p, loaded);
    EXPECT_EQ(trainingKey(p, loaded), base);
    std::swap(p.motions[0].contactLabels, p.motions[1].contactLabels);
    EXPECT_NE(trainingKey(p, loaded), base);
    std::swap(p.motions[0].contactLabels, p.motions[1].contactLabels);
    loaded[0].fileKey = 12;
    EXPECT_NE(trainingKey(p, loaded), base);
    loaded[0].fileKey = 11;
    loaded[1].fileKey = 23;  // unlabelled file: the SVM does not change
    EXPECT_EQ(trainingKey(p, loaded), base);
    EXPECT_NE(contactsKey(loaded[0], base, true), contactsKey(loaded[0], base, false));
    EXPECT_EQ(contactsKey(loaded[0], base, false), contactsKey(loaded[0], base + 1, false));
}
