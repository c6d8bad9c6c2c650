// The Interaction Graph's scene kinds in the editor, on the real Vulkan
// viewport (lavapipe, under Xvfb): a graph-carry setup made with the Scene
// panel's kind chooser, its parameters edited (each one undo step), the
// box's path drawn with the Circle tool by mouse events on the viewport,
// generated in the background: the carriers follow the drawn circle; and a
// graph-duel generated on the demo project, its action track shown, the
// graph built once and reused by the next generate.
#include <gtest/gtest.h>

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QImage>
#include <QLabel>
#include <QPainter>
#include <QProcess>
#include <QPushButton>
#include <QSpinBox>
#include <QTemporaryDir>
#include <QTest>
#include <QUndoStack>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "fray/authoring/project_document.h"
#include "fray/render/image.h"
#include "fray/setup/graph_setup.h"
#include "gantt_view.h"
#include "scene_stage.h"
#include "editor_fixture.h"
#include "viewport_fixture.h"

namespace {

using fray::test::clickOnFloor;
using fray::test::lookDown;

void shots(fray::test::VulkanEditor& editor, const char* name) {
    // Room for every row of the action track (its dock starts at 130 px).
    if (auto* gantt = editor.window->findChild<QDockWidget*>("GanttDock")) editor.window->resizeDocks({gantt}, {170}, Qt::Vertical);
    QTest::qWait(300);
    QDir().mkpath(FRAY_EDITOR_SHOTS);
    fray::render::Image view;
    ASSERT_TRUE(editor.viewport->renderer()->readback(view));
    (void)fray::render::writePng(std::string(FRAY_EDITOR_SHOTS "/") + name + "-viewport.png", view);
    // The window with the viewport's frame in its place (a widget grab leaves the Vulkan window blank).
    QImage window = editor.window->grab().toImage();
    const QImage frame(view.rgba.data(), view.width, view.height, view.width * 4, QImage::Format_RGBA8888);
    const QPoint at = editor.viewport->mapToGlobal(QPoint(0, 0)) - editor.window->mapToGlobal(QPoint(0, 0));
    QPainter painter(&window);
    painter.drawImage(QRect(at * window.devicePixelRatio(), editor.viewport->size() * window.devicePixelRatio()), frame);
    painter.end();
    window.save(QString(FRAY_EDITOR_SHOTS "/") + name + "-window.png");
    if (auto* panel = editor.window->findChild<QWidget*>("scenePanel")) panel->grab().save(QString(FRAY_EDITOR_SHOTS "/") + name + "-scene.png");
    if (auto* gantt = editor.window->findChild<QWidget*>("gantt")) gantt->grab().save(QString(FRAY_EDITOR_SHOTS "/") + name + "-gantt.png");
}

// Adds a setup of `kind` with the Scene panel's chooser and New setup button.
void newSetupWithChooser(fray::editor::MainWindow* w, const char* kind) {
    auto* chooser = w->findChild<QComboBox*>("sceneNewKind");
    ASSERT_NE(chooser, nullptr);
    const int i = chooser->findData(QString(kind));
    ASSERT_GE(i, 0) << kind << " is not offered";
    chooser->setCurrentIndex(i);
    QTest::mouseClick(w->findChild<QPushButton*>("sceneNewSetup"), Qt::LeftButton);
    ASSERT_EQ(w->currentSetup(), QString(kind)) << w->lastError().toStdString();
    w->findChild<QCheckBox*>("sceneLive")->setChecked(false);  // generated when the test says so
}

// A parameter typed into its widget: one undo step.
template <class Box, class V>
void setParam(fray::editor::MainWindow* w, const char* name, V value) {
    auto* box = w->findChild<Box*>(name);
    ASSERT_NE(box, nullptr) << name;
    ASSERT_TRUE(box->isVisible()) << name << " is not shown for this kind";
    const int steps = w->document()->undoStack()->count();
    box->setValue(value);
    EXPECT_EQ(w->document()->undoStack()->count(), steps + 1) << name << ": " << w->lastError().toStdString();
}

void generateAndWait(fray::editor::MainWindow* w) {
    w->selectTool({});
    QTest::mouseClick(w->findChild<QPushButton*>("sceneGenerate"), Qt::LeftButton);
    ASSERT_TRUE(QTest::qWaitFor([&] { return !w->busy(); }, 180000));
    ASSERT_NE(w->scene(), nullptr) << w->lastError().toStdString();
}

}  // namespace

// The carry set (docs/DEMO_ACTOR.md) written by fray-cli into a folder the test owns.
struct EditorGraphCarry : ::testing::Test {
    void SetUp() override {
        QProcess cli;
        cli.start(FRAY_CLI, {"demo-library", dir.filePath("carry"), "--set", "carry", "--minutes", "1"});
        ASSERT_TRUE(cli.waitForFinished(120000));
        ASSERT_EQ(cli.exitCode(), 0) << cli.readAllStandardError().toStdString();
        ASSERT_TRUE(editor.open(dir.filePath("carry/demo.frayproj")));
        w = editor.window.get();
        ASSERT_TRUE(QTest::qWaitForWindowExposed(w));
        ASSERT_TRUE(QTest::qWaitFor([&] { return w->analysis() != nullptr; }, 120000));
        ASSERT_NE(w->document(), nullptr);
    }
    QTemporaryDir dir;
    fray::test::VulkanEditor editor;
    fray::editor::MainWindow* w = nullptr;
};

TEST_F(EditorGraphCarry, CircleDrawnOnTheViewportIsFollowedWithinHalfAMetre) {
    auto* doc = w->document();
    newSetupWithChooser(w, "graph-carry");
    // Parameters: a smaller carry graph (the tests' size) and 30 s; each edit one undo step.
    setParam<QSpinBox>(w, "param_carry_states", 3000);
    setParam<QDoubleSpinBox>(w, "param_duration", 30.0);
    EXPECT_FALSE(w->findChild<QWidget*>("param_opponent")->isVisible()) << "duel parameters are hidden for carry";
    // A bad value is refused with a message naming the field; the project is unchanged.
    const std::string before = doc->serialized();
    EXPECT_FALSE(doc->setSetupParameter("graph-carry", "/weights/gamma", "2"));
    EXPECT_EQ(doc->serialized(), before);
    // The box's path: a circle of 2.5 m about (1, -1), drawn with the Circle tool by clicks on the viewport.
    ASSERT_TRUE(w->selectToolCharacter("box"));
    lookDown(editor.viewport, {1.0f, -1.0f}, 14.0f);
    ASSERT_TRUE(w->selectTool("Circle"));
    const int steps = doc->undoStack()->count();
    clickOnFloor(editor.viewport, {1.0f, -1.0f});
    clickOnFloor(editor.viewport, {3.5f, -1.0f});
    EXPECT_EQ(doc->undoStack()->count(), steps + 1) << "a redrawn path is one undo step";
    const auto s = doc->sceneSetup("graph-carry");
    ASSERT_TRUE(s);
    const fray::setup::Trajectory* t = fray::setup::carryTrajectory(*s);
    ASSERT_NE(t, nullptr);
    ASSERT_EQ(t->shape, fray::setup::TrajectoryShape::Circle);
    const double cx = t->points[0].x, cz = t->points[0].z;
    const double radius = std::hypot(t->points[1].x - cx, t->points[1].z - cz);
    EXPECT_NEAR(cx, 1.0, 0.1);
    EXPECT_NEAR(cz, -1.0, 0.1);
    EXPECT_NEAR(radius, 2.5, 0.1);
    shots(editor, "igraph-carry-drawn");

    generateAndWait(w);
    const fray::sim::Scene& scene = w->scene()->scene();
    const auto& lib = w->scene()->library();
    ASSERT_EQ(scene.characters.size(), 3u);
    EXPECT_EQ(scene.characters[0].name, "carrier A");
    EXPECT_EQ(scene.characters[1].name, "carrier B");
    // Path error measured here: the carriers' midpoint (the box's middle) to the drawn circle, every 0.1 s.
    double sum = 0, worst = 0, turned = 0, last = std::nan("");
    int samples = 0;
    for (double time = 0; time <= scene.duration; time += 0.1) {
        glm::vec2 p[2];
        bool both = true;
        for (int c = 0; c < 2; ++c) {
            const int i = scene.instanceAt(c, time);
            if (i < 0) {
                both = false;
                break;
            }
            const auto& inst = scene.characters[static_cast<std::size_t>(c)].track[static_cast<std::size_t>(i)];
            p[c] = inst.placementAt(lib, inst.clipTimeAt(time)).pos;
        }
        if (!both) continue;
        const double mx = 0.5 * (static_cast<double>(p[0].x) + static_cast<double>(p[1].x)),
                     mz = 0.5 * (static_cast<double>(p[0].y) + static_cast<double>(p[1].y));
        const double e = std::fabs(std::hypot(mx - cx, mz - cz) - radius);
        sum += e, worst = std::max(worst, e), ++samples;
        const double a = std::atan2(mz - cz, mx - cx);
        if (!std::isnan(last)) turned += std::remainder(a - last, 2 * std::numbers::pi);
        last = a;
    }
    ASSERT_GT(samples, 250);
    const double mean = sum / samples;
    std::printf("editor: graph-carry on a drawn circle of %.2f m: path error mean %.3f m, max %.3f m, %.2f rad round the circle in %.0f s; %s\n",
                radius, mean, worst, turned, scene.duration, w->findChild<QLabel*>("sceneInfo")->text().toUtf8().constData());
    EXPECT_LT(mean, 0.5);
    EXPECT_GT(std::fabs(turned), 2.0) << "the pair goes round the circle, not stays at its start";
    EXPECT_TRUE(w->findChild<QLabel*>("sceneInfo")->text().contains("path error mean"));
    // The action track shows the carriers.
    auto* gantt = w->findChild<fray::editor::GanttView*>("gantt");
    ASSERT_NE(gantt, nullptr);
    EXPECT_GE(gantt->data().rows.size(), 2u);
    w->seek(12.0);
    shots(editor, "igraph-carry");
}

struct EditorGraphDuel : fray::test::EditorOnFloor {};

TEST_F(EditorGraphDuel, GeneratesADuelAndReusesTheGraph) {
    newSetupWithChooser(w, "graph-duel");
    setParam<QSpinBox>(w, "param_graph_states", 3000);
    setParam<QDoubleSpinBox>(w, "param_duration", 8.0);
    auto* opponent = w->findChild<QComboBox*>("param_opponent");
    ASSERT_NE(opponent, nullptr);
    const int steps = doc->undoStack()->count();
    opponent->setCurrentText("static");
    EXPECT_EQ(doc->undoStack()->count(), steps + 1);
    EXPECT_EQ(*fray::setup::parameter(*doc->sceneSetup("graph-duel"), "/opponent"), "\"static\"");
    // Undo gives the old value back, in the widget too.
    doc->undoStack()->undo();
    EXPECT_EQ(opponent->currentText(), "graph");
    doc->undoStack()->redo();
    EXPECT_EQ(opponent->currentText(), "static");
    EXPECT_FALSE(w->findChild<QWidget*>("param_red")->isVisible()) << "team sizes are hidden for a duel";

    generateAndWait(w);
    const auto& scene = w->scene()->scene();
    ASSERT_EQ(scene.characters.size(), 2u);
    EXPECT_EQ(scene.characters[0].name, "you");
    EXPECT_EQ(scene.characters[1].name, "opponent");
    EXPECT_NEAR(scene.duration, 8.0, 1e-9);
    const QString info = w->findChild<QLabel*>("sceneInfo")->text();
    EXPECT_TRUE(info.contains("graph: built in memory (3000 states asked")) << info.toStdString();
    auto* gantt = w->findChild<fray::editor::GanttView*>("gantt");
    ASSERT_EQ(gantt->data().rows.size(), 2u);
    EXPECT_GT(gantt->data().rows[0].bars.size(), 2u);
    const std::string first = fray::sim::sceneToJson(scene, w->scene()->library());
    w->seek(4.0);
    shots(editor, "igraph-duel");
    // Again: the graph built above is reused, and the same seed gives the same scene.
    generateAndWait(w);
    EXPECT_TRUE(w->findChild<QLabel*>("sceneInfo")->text().contains("built in memory earlier"));
    EXPECT_EQ(fray::sim::sceneToJson(w->scene()->scene(), w->scene()->library()), first);
}

int main(int argc, char** argv) { return fray::test::runWindowTests(argc, argv, "xcb"); }
