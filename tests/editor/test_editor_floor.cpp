// The floor tools on the editor's real Vulkan viewport (lavapipe, under Xvfb),
// driven with mouse events on the viewport window: a brush stroke paints a
// domino setup's floor as one undo step that undoes and redoes bit for bit;
// generating it makes the people standing in the painted area fall and leaves
// those well outside standing; a drawn trajectory lands in the setup; bad input
// (an empty trajectory, an imported file that is not an image) leaves a clear
// message and the project unchanged.
#include <gtest/gtest.h>

#include <QApplication>
#include <QCheckBox>
#include <QDir>
#include <QFile>
#include <QPushButton>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QTest>
#include <QUndoStack>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "fray/authoring/project_document.h"
#include "fray/render/image.h"
#include "fray/setup/scene_setup.h"
#include "fray/sim/patterns.h"
#include "scene_stage.h"
#include "editor_fixture.h"
#include "viewport_fixture.h"

namespace {

using fray::test::DemoCopy;
using fray::test::clickOnFloor;
using fray::test::dragOnFloor;
using fray::test::lookDown;
using fray::test::pixelOf;

namespace fs = std::filesystem;

bool paintedNear(const fray::setup::FloorPaint& f, glm::vec2 p, double radius) {
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            if (!f.at(x, y)) continue;
            const double cx = f.origin.x + (x + 0.5) * f.metresPerPixel, cz = f.origin.z + (y + 0.5) * f.metresPerPixel;
            if (std::hypot(cx - static_cast<double>(p.x), cz - static_cast<double>(p.y)) <= radius) return true;
        }
    return false;
}

bool paintedAt(const fray::setup::FloorPaint& f, glm::vec2 p) {
    const int x = static_cast<int>(std::floor((static_cast<double>(p.x) - f.origin.x) / f.metresPerPixel));
    const int y = static_cast<int>(std::floor((static_cast<double>(p.y) - f.origin.z) / f.metresPerPixel));
    return x >= 0 && y >= 0 && x < f.width && y < f.height && f.at(x, y);
}

struct FloorTools : fray::test::EditorOnFloor {};

TEST_F(FloorTools, BrushPaintsADominoAreaAsOneUndoStepAndPeopleThereFall) {
    ASSERT_TRUE(doc->addSetup("dominoes", fray::setup::SetupKind::Domino));
    ASSERT_TRUE(w->selectSetup("dominoes"));
    w->findChild<QCheckBox*>("sceneLive")->setChecked(false);  // generated once, below
    // The domino's PatternList (people falling onto people), its patches generated first.
    for (const auto& p : fray::sim::defaultPatterns())
        if (p.name == "fall-fall") {
            ASSERT_TRUE(doc->addPattern(p));
        }
    w->findChild<QPushButton*>("patternGenerateAll")->click();
    ASSERT_TRUE(QTest::qWaitFor([&] { return !w->busy(); }, 120000));
    ASSERT_NE(w->patchLibrary(), nullptr) << w->lastError().toStdString();
    ASSERT_TRUE(w->selectTool("Brush"));
    auto* brush = static_cast<fray::editor::BrushTool*>(w->tool("Brush"));
    brush->radius = 2.0;
    brush->startTime = 0.5;
    lookDown(editor.viewport, {0.0f, 0.0f}, 22.0f);
    const auto floorNow = [&] { return doc->sceneSetup("dominoes")->floor.value(); };
    const fray::setup::FloorPaint blank = floorNow();
    const int steps = doc->undoStack()->count();
    dragOnFloor(editor.viewport, {{-5.0f, 0.0f}, {-2.0f, 0.2f}, {0.0f, 0.0f}, {2.0f, -0.2f}, {5.0f, 0.0f}});
    EXPECT_EQ(doc->undoStack()->count(), steps + 1) << "one stroke, one undo step";
    const fray::setup::FloorPaint painted = floorNow();
    // Picked through the camera: painted where the pointer went, not elsewhere.
    EXPECT_TRUE(paintedAt(painted, {-4.0f, 0.0f}));
    EXPECT_TRUE(paintedAt(painted, {0.0f, 0.0f}));
    EXPECT_TRUE(paintedAt(painted, {3.9f, 0.0f}));
    EXPECT_FALSE(paintedAt(painted, {0.0f, 3.5f}));
    EXPECT_FALSE(paintedAt(painted, {7.0f, 0.0f}));
    // Undo and redo restore the bitmap bit for bit.
    doc->undoStack()->undo();
    EXPECT_EQ(floorNow(), blank);
    doc->undoStack()->redo();
    EXPECT_EQ(floorNow(), painted);
    // The stroke shows on the floor of the viewport.
    QTest::qWait(200);
    fray::render::Image view;
    ASSERT_TRUE(editor.viewport->renderer()->readback(view));
    QDir().mkpath(FRAY_EDITOR_SHOTS);
    (void)fray::render::writePng(QString(FRAY_EDITOR_SHOTS "/floor-brush.png").toStdString(), view);

    // Generate: the people standing in the painted area fall, those well outside do not.
    w->selectTool({});
    QTest::mouseClick(w->findChild<QPushButton*>("sceneGenerate"), Qt::LeftButton);
    ASSERT_TRUE(QTest::qWaitFor([&] { return !w->busy(); }, 120000));
    ASSERT_NE(w->scene(), nullptr) << w->lastError().toStdString();
    const fray::sim::Scene& scene = w->scene()->scene();
    const auto& lib = w->scene()->library();
    int inside = 0, insideFell = 0, outside = 0, outsideFell = 0;
    for (const auto& c : scene.characters) {
        if (c.track.empty()) continue;
        const glm::vec2 at = c.track.front().root.pos;
        bool fell = false;
        for (const auto& inst : c.track) {
            const auto& a = lib.actions()[static_cast<std::size_t>(inst.action)];
            fell = fell || a.has("falling") || a.has("fall");
        }
        if (paintedAt(painted, at)) {
            ++inside;
            insideFell += fell ? 1 : 0;
        } else if (!paintedNear(painted, at, 2.5)) {
            ++outside;
            outsideFell += fell ? 1 : 0;
        }
    }
    std::printf("editor: %d people stand in the painted area (%d fell), %d well outside (%d fell)\n", inside, insideFell, outside,
                outsideFell);
    EXPECT_GT(inside, 3);
    EXPECT_EQ(insideFell, inside);
    EXPECT_GT(outside, 3);
    EXPECT_EQ(outsideFell, 0);

    // Live re-plan: a small stroke far from the chain; the scene regenerates by
    // itself, and everyone the stroke cannot affect keeps a byte-identical track.
    w->findChild<QCheckBox*>("sceneLive")->setChecked(true);
    const auto* before = w->scene();
    ASSERT_TRUE(w->selectTool("Brush"));
    brush->radius = 0.4;
    brush->startTime.reset();
    dragOnFloor(editor.viewport, {{8.5f, 5.0f}, {9.0f, 5.2f}});
    EXPECT_TRUE(w->replanPending());
    ASSERT_TRUE(QTest::qWaitFor([&] { return w->scene() != before && !w->replanPending(); }, 120000));
    const QString status = w->statusBar()->currentMessage();
    std::printf("editor: %s\n", status.toUtf8().constData());
    EXPECT_TRUE(status.contains("kept their tracks")) << status.toStdString();
    EXPECT_GT(w->replanOthers(), 40);
    EXPECT_EQ(w->replanKept(), w->replanOthers());
}

TEST_F(FloorTools, TrajectoriesAndBadInputKeepTheProjectUnchanged) {
    ASSERT_TRUE(doc->addSetup("duel", fray::setup::SetupKind::Duel));
    ASSERT_TRUE(w->selectSetup("duel"));
    ASSERT_TRUE(w->selectToolCharacter("red")) << "the duel setup's characters are offered";
    lookDown(editor.viewport, {0.0f, 0.0f}, 14.0f);
    // An empty trajectory: Enter with no points.
    ASSERT_TRUE(w->selectTool("Polyline"));
    const std::string before = doc->serialized();
    QTest::keyClick(editor.viewport, Qt::Key_Return);
    EXPECT_TRUE(w->lastError().contains("empty")) << w->lastError().toStdString();
    EXPECT_EQ(doc->serialized(), before);
    // A circle: the centre, then a point on it.
    ASSERT_TRUE(w->selectTool("Circle"));
    QTest::mouseClick(editor.viewport, Qt::LeftButton, Qt::NoModifier, pixelOf(editor.viewport, {0.0f, 0.0f}));
    QTest::mouseClick(editor.viewport, Qt::LeftButton, Qt::NoModifier, pixelOf(editor.viewport, {2.0f, 0.0f}));
    auto s = doc->sceneSetup("duel");
    ASSERT_TRUE(s);
    ASSERT_EQ(s->trajectories.size(), 1u);
    EXPECT_EQ(s->trajectories[0].character, "red");
    EXPECT_EQ(s->trajectories[0].shape, fray::setup::TrajectoryShape::Circle);
    EXPECT_NEAR(s->trajectories[0].points[1].x, 2.0, 0.1);
    EXPECT_NEAR(s->trajectories[0].points[1].z, 0.0, 0.1);
    // The circle on the floor, its start and rim points and the characters' starts.
    QTest::qWait(200);
    fray::render::Image view;
    ASSERT_TRUE(editor.viewport->renderer()->readback(view));
    (void)fray::render::writePng(QString(FRAY_EDITOR_SHOTS "/floor-circle.png").toStdString(), view);
    // Drag its rim point with the Move tool: one undo step.
    ASSERT_TRUE(w->selectTool("Move"));
    const int steps = doc->undoStack()->count();
    dragOnFloor(editor.viewport, {{2.0f, 0.0f}, {2.5f, 0.5f}, {3.0f, 0.0f}});
    EXPECT_EQ(doc->undoStack()->count(), steps + 1);
    EXPECT_NEAR(doc->sceneSetup("duel")->trajectories[0].points[1].x, 3.0, 0.1);
    // A file that is not an image as the floor: refused, naming the file; nothing changed.
    ASSERT_TRUE(doc->addSetup("floor", fray::setup::SetupKind::Domino));
    ASSERT_TRUE(w->selectSetup("floor"));
    QFile junk(demo.dir.filePath("notes.png"));
    ASSERT_TRUE(junk.open(QIODevice::WriteOnly));
    junk.write("these are my notes, not a picture\n");
    junk.close();
    const std::string beforeImport = doc->serialized();
    EXPECT_FALSE(w->importFloorPng(junk.fileName()));
    EXPECT_TRUE(w->lastError().contains("notes.png")) << w->lastError().toStdString();
    EXPECT_EQ(doc->serialized(), beforeImport);
}

}  // namespace

int main(int argc, char** argv) { return fray::test::runWindowTests(argc, argv, "xcb"); }
