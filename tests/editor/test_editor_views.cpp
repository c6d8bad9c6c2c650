// The timeline and motion-graph panels on real demo data, driven with real
// mouse and key events: what each gesture asks the document for, and that
// each panel draws something (neither blank nor uniform).
#include <gtest/gtest.h>

#include <QApplication>
#include <QDir>
#include <QImage>
#include <QSignalSpy>
#include <QTest>
#include <QWheelEvent>
#include <set>

#include "fray/core/joint_guess.h"
#include "fray/demo/demo_actor.h"
#include "fray/prep/contacts.h"
#include "fray/prep/segmentation.h"
#include "fray/prep/signals.h"
#include "gantt_view.h"
#include "graph_view.h"
#include "timeline_view.h"

namespace {

using fray::editor::GraphView;
using fray::editor::GraphViewData;
using fray::editor::TimelineData;
using fray::editor::TimelineView;

// One demo take (seed 1), segmented as `fray-cli segment` does by default.
const TimelineData& demoTimeline() {
    static const TimelineData data = [] {
        fray::demo::LibraryOptions options;
        options.seed = 1;
        TimelineData d;
        for (const auto& spec : fray::demo::planLibrary(options)) {
            if (spec.name != "shadowbox_energetic") continue;
            const auto take = fray::demo::generateTake(spec, fray::demo::takeSeed(options.seed, spec.name));
            const auto joints = fray::guessStandardJoints(take.motion.skeleton());
            auto signals = fray::prep::computeSignals(take.motion, joints);
            if (!signals) throw std::runtime_error(signals.error().message);
            const auto contacts = fray::prep::heuristicContacts(*signals);
            const auto seg = fray::prep::segment(*signals, contacts);
            d.frameCount = signals->frameCount;
            d.fps = signals->fps;
            d.acceleration = seg.smoothed;
            d.threshold = seg.threshold;
            d.highAccel = seg.highAccel;
            d.contactLeft = contacts.left;
            d.contactRight = contacts.right;
            d.cuts = seg.cuts;
            for (std::size_t a = 0; a <= seg.cuts.size(); ++a) d.actionNames.push_back(a % 3 == 0 ? "jab?" : "guard");
            d.labels.push_back({300, 420, true, std::nullopt});
        }
        if (d.frameCount == 0) throw std::runtime_error("demo take shadowbox_energetic not planned");
        return d;
    }();
    return data;
}

// Distinct colours in the image, and whether it is all one colour.
int distinctColours(const QImage& image) {
    std::set<QRgb> colours;
    for (int y = 0; y < image.height(); y += 2)
        for (int x = 0; x < image.width(); x += 2) colours.insert(image.pixel(x, y));
    return static_cast<int>(colours.size());
}

void saveShot(const QImage& image, const char* name) {
    QDir().mkpath(FRAY_EDITOR_SHOTS);
    image.save(QString(FRAY_EDITOR_SHOTS) + "/" + name);
}

struct ShownTimeline {
    TimelineView view;
    ShownTimeline() {
        view.resize(1000, 220);
        view.setData(demoTimeline());
        view.show();
        EXPECT_TRUE(QTest::qWaitForWindowExposed(&view));
    }
};

TEST(TimelineView, DrawsCurveBandsCutsAndActions) {
    ShownTimeline t;
    const QImage shot = t.view.grab().toImage();
    saveShot(shot, "timeline.png");
    EXPECT_GT(distinctColours(shot), 12) << "the timeline looks blank";
    // Zoomed in, the frame numbers stay in range and the view narrows.
    const double before = t.view.viewLast() - t.view.viewFirst();
    QWheelEvent wheel(QPointF(500, t.view.curveY()), t.view.mapToGlobal(QPointF(500, t.view.curveY())), QPoint(),
                      QPoint(0, 240), Qt::NoButton, Qt::NoModifier, Qt::NoScrollPhase, false);
    QApplication::sendEvent(&t.view, &wheel);
    EXPECT_LT(t.view.viewLast() - t.view.viewFirst(), before * 0.7);
    EXPECT_GE(t.view.viewFirst(), 0.0);
    saveShot(t.view.grab().toImage(), "timeline-zoomed.png");
}

TEST(TimelineView, DraggingACutReportsOneDragFromItsStartFrame) {
    ShownTimeline t;
    const TimelineData& d = demoTimeline();
    ASSERT_GE(d.cuts.size(), 3u);
    const int cut = d.cuts[1];
    QSignalSpy spy(&t.view, &TimelineView::cutDragged);
    const QPoint start(t.view.xOfFrame(cut), t.view.actionsY());
    QTest::mousePress(&t.view, Qt::LeftButton, Qt::NoModifier, start);
    // Move towards the previous cut, in steps, as a hand would.
    const int target = (d.cuts[0] + cut) / 2 + 1;
    const int targetX = t.view.xOfFrame(target);
    for (int x = start.x(); x >= targetX; x -= 3) QTest::mouseMove(&t.view, QPoint(x, start.y()));
    QTest::mouseMove(&t.view, QPoint(targetX, start.y()));
    QTest::mouseRelease(&t.view, Qt::LeftButton, Qt::NoModifier, QPoint(targetX, start.y()));
    ASSERT_GE(spy.count(), 2);
    for (const auto& args : spy) EXPECT_EQ(args.at(0).toInt(), cut) << "every step names the cut's start frame";
    const auto last = spy.takeLast();
    EXPECT_TRUE(last.at(2).toBool()) << "the release finishes the drag";
    EXPECT_NEAR(last.at(1).toInt(), target, 3);
    EXPECT_GT(last.at(1).toInt(), d.cuts[0]) << "a dragged cut never passes its neighbour";
}

TEST(TimelineView, DoubleClickAddsACutAndFootDragsLabelContacts) {
    ShownTimeline t;
    const TimelineData& d = demoTimeline();
    QSignalSpy add(&t.view, &TimelineView::cutAddRequested);
    // In the middle of the longest action on screen, well away from its cuts.
    std::size_t widest = 1;
    for (std::size_t i = 1; i < d.cuts.size() && d.cuts[i] < t.view.viewLast(); ++i)
        if (d.cuts[i] - d.cuts[i - 1] > d.cuts[widest] - d.cuts[widest - 1]) widest = i;
    const int frame = (d.cuts[widest - 1] + d.cuts[widest]) / 2;
    QTest::mouseDClick(&t.view, Qt::LeftButton, Qt::NoModifier, QPoint(t.view.xOfFrame(frame), t.view.curveY()));
    ASSERT_EQ(add.count(), 1);
    EXPECT_NEAR(add.takeFirst().at(0).toInt(), frame, 2);

    QSignalSpy label(&t.view, &TimelineView::contactLabelRequested);
    const int a = 100, b = 260;  // frames, inside the initial view
    QTest::mousePress(&t.view, Qt::LeftButton, Qt::NoModifier, QPoint(t.view.xOfFrame(a), t.view.footY(0)));
    QTest::mouseMove(&t.view, QPoint(t.view.xOfFrame(b), t.view.footY(0)));
    QTest::mouseRelease(&t.view, Qt::LeftButton, Qt::NoModifier, QPoint(t.view.xOfFrame(b), t.view.footY(0)));
    QTest::mousePress(&t.view, Qt::RightButton, Qt::NoModifier, QPoint(t.view.xOfFrame(b), t.view.footY(1)));
    QTest::mouseMove(&t.view, QPoint(t.view.xOfFrame(a), t.view.footY(1)));
    QTest::mouseRelease(&t.view, Qt::RightButton, Qt::NoModifier, QPoint(t.view.xOfFrame(a), t.view.footY(1)));
    ASSERT_EQ(label.count(), 2);
    const auto left = label.at(0), right = label.at(1);
    EXPECT_EQ(left.at(0).toInt(), 0);
    EXPECT_NEAR(left.at(1).toInt(), a, 2);
    EXPECT_NEAR(left.at(2).toInt(), b, 2);
    EXPECT_TRUE(left.at(3).toBool());
    EXPECT_EQ(right.at(0).toInt(), 1);
    EXPECT_LE(right.at(1).toInt(), right.at(2).toInt()) << "a right-to-left drag still gives first <= last";
    EXPECT_FALSE(right.at(3).toBool());
}

TEST(TimelineView, PlaybackKeysStepThePlayhead) {
    ShownTimeline t;
    t.view.setFocus();
    QSignalSpy spy(&t.view, &TimelineView::playheadRequested);
    t.view.setPlayhead(50);
    QTest::keyClick(&t.view, Qt::Key_Right);
    EXPECT_EQ(t.view.playhead(), 51);
    QTest::keyClick(&t.view, Qt::Key_Up);
    EXPECT_EQ(t.view.playhead(), 61);
    QTest::keyClick(&t.view, Qt::Key_Down);
    QTest::keyClick(&t.view, Qt::Key_Left);
    EXPECT_EQ(t.view.playhead(), 50);
    QTest::keyClick(&t.view, Qt::Key_Home);
    EXPECT_EQ(t.view.playhead(), 0);
    EXPECT_EQ(spy.count(), 5);
    QSignalSpy play(&t.view, &TimelineView::playToggled);
    QTest::keyClick(&t.view, Qt::Key_Space);
    EXPECT_EQ(play.count(), 1);
}

TEST(GraphView, DrawsNodesAndSelectsTheClickedOne) {
    // A small graph with a dead end (node 3 outside the largest SCC).
    GraphViewData g;
    g.nodeCount = 5;
    g.startNode = {0, 1, 2, 0, 2, 1, 4, 3};
    g.endNode = {1, 2, 0, 2, 1, 4, 0, 3};
    g.inLargestScc = {1, 1, 1, 1, 1, 1, 1, 0};
    g.summary = "5 nodes, 8 edges";
    GraphView view;
    view.resize(420, 360);
    view.setData(g);
    view.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&view));
    const QImage shot = view.grab().toImage();
    saveShot(shot, "graph.png");
    EXPECT_GT(distinctColours(shot), 8);
    // Nodes are apart from each other after the layout.
    for (int i = 0; i < g.nodeCount; ++i)
        for (int j = i + 1; j < g.nodeCount; ++j)
            EXPECT_GT((view.nodePosition(i) - view.nodePosition(j)).manhattanLength(), 12) << i << " " << j;
    QSignalSpy spy(&view, &GraphView::nodeSelected);
    QTest::mouseClick(&view, Qt::LeftButton, Qt::NoModifier, view.nodePosition(3));
    ASSERT_EQ(spy.count(), 1);
    EXPECT_EQ(spy.at(0).at(0).toInt(), 3);
    EXPECT_EQ(view.selectedNode(), 3);
    // The same graph lays out the same way.
    GraphView again;
    again.resize(420, 360);
    again.setData(g);
    for (int i = 0; i < g.nodeCount; ++i) EXPECT_EQ(again.nodePosition(i), view.nodePosition(i));
}

// A two-character scene's track: what a click on a bar or on an empty part of
// a row asks for, and that bars are drawn in their annotation's colour.
fray::editor::GanttData twoBoxers() {
    using fray::editor::GanttBar;
    fray::editor::GanttData d;
    d.duration = 10.0;
    fray::editor::GanttRow red{"red", QColor(220, 60, 50), {}};
    red.bars = {GanttBar{0.0, 2.0, "guard_idle", "idle", false, false, 1},
                GanttBar{2.0, 2.8, "jab", "punch", false, false, 2},
                GanttBar{2.8, 6.0, "front_kick", "kick", false, false, 3},
                GanttBar{6.0, 10.0, "guard_idle", "idle", false, false, 1}};
    fray::editor::GanttRow blue{"blue", QColor(120, 60, 220), {}};
    blue.bars = {GanttBar{0.0, 2.5, "idle_stand", "idle", false, false, 4},
                 GanttBar{2.5, 5.0, "knocked_back", "pushed", true, false, 5},
                 GanttBar{7.0, 9.0, "block_high", "block", false, false, 6}};
    d.rows = {red, blue};
    d.hits = {{2.5, 0, 1, false}, {8.0, 0, 1, true}};
    return d;
}

TEST(GanttView, ClickingABarSelectsTheCharacterAndSeeksToItsStart) {
    fray::editor::GanttView view;
    view.resize(900, 150);
    view.setData(twoBoxers());
    view.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&view));
    QSignalSpy bars(&view, &fray::editor::GanttView::barClicked);
    QSignalSpy seeks(&view, &fray::editor::GanttView::seekRequested);
    // The kick of the first row, clicked in its middle.
    QTest::mouseClick(&view, Qt::LeftButton, Qt::NoModifier, QPoint(view.xOfTime(4.4), view.rowY(0)));
    ASSERT_EQ(bars.count(), 1);
    EXPECT_EQ(bars.at(0).at(0).toInt(), 0);
    EXPECT_EQ(bars.at(0).at(1).toInt(), 2);
    ASSERT_EQ(seeks.count(), 1);
    EXPECT_DOUBLE_EQ(seeks.at(0).at(0).toDouble(), 2.8);
    EXPECT_EQ(view.selectedRow(), 0);
    // The gap in the second row: its character, the time under the pointer.
    QTest::mouseClick(&view, Qt::LeftButton, Qt::NoModifier, QPoint(view.xOfTime(6.0), view.rowY(1)));
    ASSERT_EQ(bars.count(), 2);
    EXPECT_EQ(bars.at(1).at(0).toInt(), 1);
    EXPECT_EQ(bars.at(1).at(1).toInt(), -1);
    ASSERT_EQ(seeks.count(), 2);
    EXPECT_NEAR(seeks.at(1).at(0).toDouble(), 6.0, 10.0 / 800);
    EXPECT_EQ(view.selectedRow(), 1);
    // Below the rows: nothing.
    QTest::mouseClick(&view, Qt::LeftButton, Qt::NoModifier, QPoint(view.xOfTime(4.0), view.rowY(2) + 2));
    EXPECT_EQ(bars.count(), 2);

    // Each bar in its annotation's colour (sampled away from labels and marks).
    view.setTime(9.9);
    const QImage shot = view.grab().toImage();
    saveShot(shot, "GanttDock.png");
    EXPECT_GT(distinctColours(shot), 8);
    const auto colourAt = [&](double t, int row) {
        return QColor(shot.pixel(view.xOfTime(t), view.rowY(row) + 5));
    };
    const QColor punch = fray::editor::GanttView::annotationColour("punch");
    const QColor kick = fray::editor::GanttView::annotationColour("kick");
    const QColor block = fray::editor::GanttView::annotationColour("block");
    EXPECT_NE(punch, kick);
    EXPECT_EQ(colourAt(2.05, 0), punch);
    EXPECT_EQ(colourAt(5.9, 0), kick);
    EXPECT_EQ(colourAt(8.9, 1), block);
    EXPECT_NE(colourAt(6.5, 1), block);  // the gap stays background
    // Zooming in keeps the time under the pointer.
    const int x = view.xOfTime(5.0);
    QWheelEvent wheel(QPointF(x, view.rowY(0)), view.mapToGlobal(QPointF(x, view.rowY(0))), QPoint(), QPoint(0, 240),
                      Qt::NoButton, Qt::NoModifier, Qt::NoScrollPhase, false);
    QApplication::sendEvent(&view, &wheel);
    EXPECT_NEAR(view.timeAtX(x), 5.0, 0.05);
    EXPECT_LT(view.timeAtX(view.width()) - view.timeAtX(view.xOfTime(0) + 90), 10.0);
}

}  // namespace

int main(int argc, char** argv) {
    if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
    QApplication app(argc, argv);
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
