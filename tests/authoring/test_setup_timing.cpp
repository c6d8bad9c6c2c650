// Timing of floor painting through the document (docs/BENCHMARKS.md), not run
// by default: fray_authoring_tests --gtest_also_run_disabled_tests
// --gtest_filter='SetupTiming.*'. Prints the time of one brush step of a drag
// (merged into one undo step), of reading the setups back, and of the undo.
#include <gtest/gtest.h>
#include <chrono>
#include <cstdio>
#include "document_fixture.h"
#include "fray/authoring/project_document.h"
#include "fray/setup/plan_setup.h"
using namespace fray;
TEST(SetupTiming, DISABLED_BrushStrokes) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    for (int side : {200, 1000, 4000}) {
        setup::SceneSetup s = setup::makeSetup("d" + std::to_string(side), setup::SetupKind::Domino);
        s.floor->width = side; s.floor->height = side; s.floor->painted.assign(static_cast<std::size_t>(side) * static_cast<std::size_t>(side), 0);
        ASSERT_TRUE(doc->addSetup(s).ok());
        setup::FloorStroke b; b.radius = 0.3;
        const auto drag = doc->beginDrag();
        const int n = 20;
        auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < n; ++i) {
            b.points = {{-5.0 + 0.2 * i, 0}, {-4.8 + 0.2 * i, 0.1}};
            ASSERT_TRUE(doc->paintFloor(s.name, b, drag).ok());
        }
        auto t1 = std::chrono::steady_clock::now();
        auto t2 = std::chrono::steady_clock::now();
        auto list = doc->setups();
        auto t3 = std::chrono::steady_clock::now();
        doc->undoStack()->undo();
        auto t4 = std::chrono::steady_clock::now();
        std::printf("floor %d x %d: paint step %.2f ms, setups() %.2f ms, undo %.2f ms, section %zu bytes\n", side, side,
                    std::chrono::duration<double, std::milli>(t1 - t0).count() / n,
                    std::chrono::duration<double, std::milli>(t3 - t2).count(),
                    std::chrono::duration<double, std::milli>(t4 - t3).count(), doc->project().laterSections.at("scene").size());
    }
}

// The check of a duel parameter edit (setup::checkPlanSetup, docs/BENCHMARKS.md):
// a refused edit is read before and after it. Until 2026-11-27 each read built
// the presets and the action catalogue again (two builds per refused edit);
// now the edit builds them once. Both ways timed in the same run on the demo
// project, and the whole document edit (accepted: red's w_r; refused: -1).
TEST(SetupTiming, DISABLED_ParameterChecks) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    ASSERT_TRUE(doc->addSetup(setup::makeSetup("duel", setup::SetupKind::Duel)).ok());
    const setup::SceneSetup good = *doc->sceneSetup("duel");
    setup::SceneSetup bad = good;
    ASSERT_TRUE(setup::setParameter(bad, "/characters/0/weights/w_r", "-1"));
    const prep::Project& project = doc->project();
    const int n = 200;
    using clock = std::chrono::steady_clock;
    const auto ms = [](clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
    auto t0 = clock::now();
    for (int i = 0; i < n; ++i) {
        ASSERT_FALSE(setup::checkPlanSetup(bad, project, "demo.frayproj"));  // as before: two builds
        ASSERT_TRUE(setup::checkPlanSetup(good, project, "demo.frayproj"));
    }
    auto t1 = clock::now();
    for (int i = 0; i < n; ++i) {
        auto context = setup::planCheckContext(project, "demo.frayproj");  // now: one
        ASSERT_TRUE(context);
        ASSERT_FALSE(setup::checkPlanSetup(bad, *context));
        ASSERT_TRUE(setup::checkPlanSetup(good, *context));
    }
    auto t2 = clock::now();
    for (int i = 0; i < n; ++i) auto context = setup::planCheckContext(project, "demo.frayproj");
    auto t3 = clock::now();
    for (int i = 0; i < n; ++i) ASSERT_TRUE(doc->setSetupParameter("duel", "/characters/0/weights/w_r", i % 2 ? "12" : "14"));
    auto t4 = clock::now();
    for (int i = 0; i < n; ++i) ASSERT_FALSE(doc->setSetupParameter("duel", "/characters/0/weights/w_r", "-1"));
    auto t5 = clock::now();
    std::printf("refused duel edit's check: before and after with two catalogue builds %.3f ms, with one %.3f ms "
                "(one build of presets and catalogue %.3f ms); the document edit: accepted %.3f ms, refused %.3f ms\n",
                ms(t1 - t0) / n, ms(t2 - t1) / n, ms(t3 - t2) / n, ms(t4 - t3) / n, ms(t5 - t4) / n);
}
