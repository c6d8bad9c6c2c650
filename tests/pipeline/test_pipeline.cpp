// The pipeline library (core/pipeline) on a copy of the demo project: a
// session opens with its motions, contacts and graph; cancelling through the
// progress callback is told from a failure by the error's kind; a damaged
// cache is reported through the note callback and rebuilt.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fray/pipeline/prep_session.h"
#include "fray/pipeline/sim_session.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using namespace fray;

// The demo library written by the build, copied so the test may write the cache.
fs::path demoCopy(const test::TempDir& dir) {
    const fs::path from = fs::path(FRAY_DEMO_PROJECT).parent_path();
    for (const auto& e : fs::directory_iterator(from))
        if (e.path().extension() == ".bvh" || e.path().extension() == ".frayproj")
            fs::copy_file(e.path(), dir.path() / e.path().filename());
    return dir.path() / "demo.frayproj";
}

TEST(Pipeline, OpensASimSessionWithContactsGraphAndLibrary) {
    test::TempDir dir;
    const fs::path project = demoCopy(dir);
    std::vector<std::string> stages;
    auto ss = pipeline::openSimSession(project, [&](double, std::string_view stage) {
        if (stages.empty() || stages.back() != stage) stages.emplace_back(stage);
        return true;
    }, {});
    ASSERT_TRUE(ss) << ss.error().message;
    EXPECT_EQ((*ss)->session.motions.size(), 6u);
    EXPECT_GT((*ss)->graph.graph.nodeCount, 5);
    EXPECT_GT((*ss)->library.size(), 100);
    EXPECT_GT(stages.size(), 2u) << "progress reports its stages";
    EXPECT_TRUE(fs::exists(prep::cachePath(project))) << "the derived data is cached beside the project";
}

TEST(Pipeline, CancelIsToldFromFailureByItsKind) {
    test::TempDir dir;
    const fs::path project = demoCopy(dir);
    int calls = 0;
    auto cancelled = pipeline::openSession(project, true, [&](double, std::string_view) { return ++calls < 3; }, {});
    ASSERT_FALSE(cancelled);
    EXPECT_TRUE(cancelled.error().isCancelled()) << cancelled.error().message;
    auto missing = pipeline::openSession(dir.path() / "none.frayproj", true, {}, {});
    ASSERT_FALSE(missing);
    EXPECT_FALSE(missing.error().isCancelled());
    EXPECT_NE(missing.error().message.find("none.frayproj"), std::string::npos) << missing.error().message;
}

TEST(Pipeline, ADamagedCacheIsNotedAndRebuilt) {
    test::TempDir dir;
    const fs::path project = demoCopy(dir);
    ASSERT_TRUE(pipeline::openSimSession(project, {}, {}));
    const fs::path cache = prep::cachePath(project);
    ASSERT_TRUE(fs::exists(cache));
    {
        std::fstream f(cache, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(fs::file_size(cache) / 2));
        char c = 0;
        f.read(&c, 1);
        f.seekp(static_cast<std::streamoff>(fs::file_size(cache) / 2));
        c = static_cast<char>(c ^ 0x10);
        f.write(&c, 1);
    }
    std::vector<std::string> notes;
    auto ss = pipeline::openSimSession(project, {}, [&](std::string_view n) { notes.emplace_back(n); });
    ASSERT_TRUE(ss) << ss.error().message;
    ASSERT_FALSE(notes.empty());
    EXPECT_NE(notes.front().find("rebuilding it"), std::string::npos) << notes.front();
    // Rebuilt: the next open has nothing to say.
    notes.clear();
    ASSERT_TRUE(pipeline::openSimSession(project, {}, [&](std::string_view n) { notes.emplace_back(n); }));
    EXPECT_TRUE(notes.empty()) << notes.front();
}

// An existing output is overwritten only when it is a scene file: JSON (to
// its end, within the limits on size and nesting), an object whose "format"
// is "fray-scene" (the last of the key, as the parsed document has it) and
// whose "project" is a string. Read without building the document (issue 27:
// a 10,000-character scene is tens of MB).
TEST(Pipeline, OverwritesOnlyASceneFile) {
    test::TempDir dir;
    const fs::path out = dir.path() / "out.frayscene";
    auto with = [&](const std::string& text) {
        std::ofstream(out, std::ios::binary) << text;
        return static_cast<bool>(pipeline::checkSceneOutput(out));
    };
    EXPECT_TRUE(static_cast<bool>(pipeline::checkSceneOutput(dir.path() / "none.frayscene")));
    EXPECT_TRUE(with(R"({"format": "fray-scene", "version": 2, "project": "p.frayproj", "characters": [{"name": "a"}]})"));
    EXPECT_TRUE(with(R"({"x": {"format": 1, "project": 2}, "project": "p", "format": "fray-scene"})"));
    EXPECT_FALSE(with(R"({"format": "fray-scene", "project": "p", "characters": [)"));  // cut short
    EXPECT_FALSE(with(R"({"format": "fray-scene", "project": "p"} trailing)"));
    EXPECT_FALSE(with(R"({"format": "fray-scene", "project": 3})"));
    EXPECT_FALSE(with(R"({"format": "fray-scene", "project": ["p"]})"));
    EXPECT_FALSE(with(R"({"format": "fray-scene"})"));
    EXPECT_FALSE(with(R"({"format": "fray-scene", "project": "p", "format": "other"})"));
    EXPECT_FALSE(with(R"({"format": {"fray-scene": 1}, "project": "p"})"));
    EXPECT_FALSE(with(R"([{"format": "fray-scene", "project": "p"}])"));
    EXPECT_FALSE(with("a cover letter"));
    EXPECT_FALSE(with(""));
    // Nested deeper than prep's limit (64 levels), as parseJson refuses it.
    const std::string deep = std::string(64, '[') + std::string(64, ']');
    EXPECT_TRUE(with(R"({"format": "fray-scene", "project": "p", "x": )" + std::string(63, '[') + std::string(63, ']') + "}"));
    EXPECT_FALSE(with(R"({"format": "fray-scene", "project": "p", "x": )" + deep + "}"));
}

}  // namespace
