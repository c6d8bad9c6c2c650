// Timing of floor painting through the document (docs/BENCHMARKS.md), not run
// by default: fray_authoring_tests --gtest_also_run_disabled_tests
// --gtest_filter='SetupTiming.*'. Prints the time of one brush step of a drag
// (merged into one undo step), of reading the setups back, and of the undo.
#include <gtest/gtest.h>
#include <chrono>
#include <cstdio>
#include "document_fixture.h"
#include "fray/authoring/project_document.h"
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
