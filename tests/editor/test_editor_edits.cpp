// Editing the demo project in the main window with real mouse and key
// events, offscreen: every gesture is one undo command on the document, Undo
// and Redo through the Edit menu give back the exact bytes, Save writes what
// the document holds, and a crash after an autosave is recovered exactly.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QMimeData>
#include <QRegularExpression>
#include <QUrl>
#include <QWidget>
#include <QDockWidget>
#include <QFile>
#include <QLineEdit>
#include <QProcess>
#include <QStandardItemModel>
#include <QStatusBar>
#include <QTableView>
#include <QTemporaryDir>
#include <QTest>
#include <QToolButton>
#include <QTreeWidget>
#include <QUndoStack>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include "fray/authoring/autosave.h"
#include "fray/authoring/project_document.h"
#include "editor_fixture.h"
#include "main_window.h"
#include "takes.h"
#include "timeline_view.h"

namespace {

namespace fs = std::filesystem;
using fray::editor::EditorOptions;
using fray::editor::MainWindow;
using fray::test::DemoCopy;

// A copy of the demo library (takes and project) in a temporary folder.
std::unique_ptr<MainWindow> openWindow(const QString& project, EditorOptions::Recovery recovery) {
    auto w = fray::test::openEditorWindow(project, recovery);
    if (w && !QTest::qWaitForWindowExposed(w.get())) ADD_FAILURE() << "window not exposed";
    return w;
}

QAction* action(MainWindow* w, const char* name) {
    auto* a = w->findChild<QAction*>(name);
    EXPECT_NE(a, nullptr) << name;
    return a;
}

void selectAction(MainWindow* w, int motion, int act) {
    auto* library = w->findChild<QTreeWidget*>("library");
    QTreeWidgetItem* top = library->topLevelItem(motion);
    library->expandItem(top);
    QApplication::processEvents();
    QTreeWidgetItem* item = top->child(act);
    library->scrollToItem(item);
    QTest::mouseClick(library->viewport(), Qt::LeftButton, Qt::NoModifier, library->visualItemRect(item).center());
}

// Project > Segment on motion 0 (in the background) until its one undo step lands.
void segmentFirstMotion(MainWindow* w) {
    selectAction(w, 0, 0);
    const int before = w->document()->undoStack()->count();
    action(w, "actionSegment")->trigger();
    if (!QTest::qWaitFor([&] { return w->document()->undoStack()->count() == before + 1; }, 120000))
        ADD_FAILURE() << "segmentation did not land: " << w->statusBar()->currentMessage().toStdString();
}

// The first action of motion 0 with a proposal, and the proposal.
std::pair<int, std::string> actionWithProposal(const fray::prep::Project& p) {
    const auto& acts = p.motions[0].actions.actions;
    for (std::size_t a = 0; a < acts.size(); ++a)
        if (!acts[a].proposed.empty()) return {static_cast<int>(a), acts[a].proposed.front()};
    return {-1, {}};
}

class EditorEdits : public ::testing::Test {
protected:
    void SetUp() override {
        w = openWindow(demo.project, EditorOptions::Recovery::Discard);
        ASSERT_NE(w, nullptr);
        doc = w->document();
        ASSERT_NE(doc, nullptr);
        original = doc->serialized();
        timeline = w->findChild<fray::editor::TimelineView*>("timeline");
        ASSERT_NE(timeline, nullptr);
    }
    void TearDown() override { w.reset(); }
    DemoCopy demo{false};  // no cache: the analysis runs from the takes
    std::unique_ptr<MainWindow> w;
    fray::authoring::ProjectDocument* doc = nullptr;
    fray::editor::TimelineView* timeline = nullptr;
    std::string original;
};

TEST_F(EditorEdits, DraggingACutIsOneUndoStepAndTheMenuUndoesItExactly) {
    selectAction(w.get(), 0, 3);
    const auto cuts = doc->project().motions[0].actions.cuts;
    const int cut = cuts[3];
    timeline->showFrames(cuts[2], cuts[4]);
    const QPoint start(timeline->xOfFrame(cut), timeline->actionsY());
    QTest::mousePress(timeline, Qt::LeftButton, Qt::NoModifier, start);
    const int target = cut + (cuts[4] - cut) / 2;
    for (int f = cut; f <= target; f += 2) QTest::mouseMove(timeline, QPoint(timeline->xOfFrame(f), start.y()));
    QTest::mouseRelease(timeline, Qt::LeftButton, Qt::NoModifier, QPoint(timeline->xOfFrame(target), start.y()));
    EXPECT_EQ(doc->undoStack()->count(), 1) << "a drag is one undo step";
    const auto& moved = doc->project().motions[0].actions.cuts;
    EXPECT_NEAR(moved[3], target, 2);
    EXPECT_TRUE(w->isWindowModified());
    QAction* undo = action(w.get(), "actionUndo");
    EXPECT_TRUE(undo->text().contains("Undo")) << undo->text().toStdString();
    undo->trigger();
    EXPECT_EQ(doc->serialized(), original) << "undo gives back the exact project";
    EXPECT_FALSE(w->isWindowModified());
    action(w.get(), "actionRedo")->trigger();
    EXPECT_NEAR(doc->project().motions[0].actions.cuts[3], target, 2);
}

TEST_F(EditorEdits, SegmentingGivesProposalsToConfirmAndChipsInTheInspector) {
    segmentFirstMotion(w.get());
    EXPECT_TRUE(action(w.get(), "actionUndo")->text().contains("Segment")) << action(w.get(), "actionUndo")->text().toStdString();
    const auto [act, word] = actionWithProposal(doc->project());
    ASSERT_GE(act, 0) << "the demo project has proposals";
    selectAction(w.get(), 0, act);
    auto* accept = w->findChild<QToolButton*>(QString::fromStdString("accept:" + word));
    ASSERT_NE(accept, nullptr);
    // The inspector and timeline as the user sees them now (docs/EDITOR.md).
    QDir().mkpath(FRAY_EDITOR_SHOTS);
    QApplication::processEvents();
    w->findChild<QWidget*>("inspector")->grab().save(QString(FRAY_EDITOR_SHOTS) + "/inspector-proposals.png");
    timeline->grab().save(QString(FRAY_EDITOR_SHOTS) + "/timeline-segmented.png");
    QTest::mouseClick(accept, Qt::LeftButton);
    const auto& info = doc->project().motions[0].actions.actions[static_cast<std::size_t>(act)];
    EXPECT_NE(std::find(info.annotations.begin(), info.annotations.end(), word), info.annotations.end());
    EXPECT_EQ(std::find(info.proposed.begin(), info.proposed.end(), word), info.proposed.end());
    QApplication::processEvents();
    // The chip is there; clicking it removes the annotation.
    auto* chip = w->findChild<QToolButton*>(QString::fromStdString("chip:" + word));
    ASSERT_NE(chip, nullptr);
    QTest::mouseClick(chip, Qt::LeftButton);
    const auto& after = doc->project().motions[0].actions.actions[static_cast<std::size_t>(act)];
    EXPECT_EQ(std::find(after.annotations.begin(), after.annotations.end(), word), after.annotations.end());
    QApplication::processEvents();
    // A new word typed in becomes a vocabulary word and the action's annotation.
    auto* add = w->findChild<QComboBox*>("addAnnotation");
    ASSERT_NE(add, nullptr);
    add->setFocus();
    QTest::keyClicks(add->lineEdit(), "spinning");
    QTest::keyClick(add->lineEdit(), Qt::Key_Return);
    const auto& vocabulary = doc->project().vocabulary;
    EXPECT_NE(std::find(vocabulary.begin(), vocabulary.end(), "spinning"), vocabulary.end());
    const auto& last = doc->project().motions[0].actions.actions[static_cast<std::size_t>(act)];
    EXPECT_NE(std::find(last.annotations.begin(), last.annotations.end(), "spinning"), last.annotations.end());
    // Undo everything through the menu: the exact original.
    QAction* undo = action(w.get(), "actionUndo");
    while (doc->undoStack()->canUndo()) undo->trigger();
    EXPECT_EQ(doc->serialized(), original);
}

TEST_F(EditorEdits, LabellingContactsAndDeletingACutMergesTwoActions) {
    selectAction(w.get(), 0, 2);
    const int before = doc->project().motions[0].actions.actionCount();
    const auto cuts = doc->project().motions[0].actions.cuts;
    timeline->showFrames(cuts[0], cuts[6]);
    const int a = cuts[1] + 2, b = cuts[3] - 2;
    QTest::mousePress(timeline, Qt::LeftButton, Qt::NoModifier, QPoint(timeline->xOfFrame(a), timeline->footY(0)));
    QTest::mouseMove(timeline, QPoint(timeline->xOfFrame(b), timeline->footY(0)));
    QTest::mouseRelease(timeline, Qt::LeftButton, Qt::NoModifier, QPoint(timeline->xOfFrame(b), timeline->footY(0)));
    const auto& labels = doc->project().motions[0].contactLabels;
    ASSERT_FALSE(labels.empty());
    EXPECT_NEAR(labels.back().firstFrame, a, 3);
    EXPECT_NEAR(labels.back().lastFrame, b, 3);
    EXPECT_EQ(labels.back().left, std::optional<bool>(true));
    EXPECT_FALSE(labels.back().right.has_value());
    // Train: the analysis retrains the SVM on the labels as they are now and
    // the timeline's bands come from it.
    const std::size_t labelCount = labels.size();
    ASSERT_TRUE(QTest::qWaitFor([&] { return w->analysis() != nullptr; }, 240000)) << w->lastError().toStdString();
    action(w.get(), "actionAnalyse")->trigger();
    ASSERT_TRUE(QTest::qWaitFor([&] {
        return w->analysis() && w->analysis()->project.motions[0].contactLabels.size() == labelCount;
    }, 240000)) << w->lastError().toStdString();
    EXPECT_NE(w->analysis()->contactsSummary.find("SVM contacts, leave-one-out accuracy"), std::string::npos)
        << w->analysis()->contactsSummary;
    EXPECT_EQ(timeline->data().contactLeft, w->analysis()->motions[0].timeline.contactLeft);
    // The playhead on a cut, then Delete: the two actions around it merge.
    timeline->setFocus();
    timeline->setPlayhead(cuts[2]);
    QTest::keyClick(timeline, Qt::Key_Delete);
    EXPECT_EQ(doc->project().motions[0].actions.actionCount(), before - 1);
    EXPECT_EQ(doc->undoStack()->count(), 2);
}

TEST_F(EditorEdits, CombinationTableEditsAndSaveReopen) {
    auto* dock = w->findChild<QDockWidget*>("CombosDock");
    dock->show();
    dock->raise();
    auto* table = w->findChild<QTableView*>("combos");
    ASSERT_NE(table, nullptr);
    ASSERT_GT(table->model()->rowCount(), 0);
    // Type a new suitability into the first row's cell, as a user would.
    QApplication::processEvents();
    const QModelIndex cell = table->model()->index(0, 2);
    const std::string mine = table->model()->index(0, 0).data().toString().toStdString();
    const std::string theirs = table->model()->index(0, 1).data().toString().toStdString();
    table->setFocus();
    table->setCurrentIndex(cell);
    QTest::keyClick(table->viewport(), Qt::Key_F2);
    QApplication::processEvents();
    QWidget* editor = QApplication::focusWidget();
    ASSERT_NE(editor, nullptr);
    QTest::keyClick(editor, Qt::Key_A, Qt::ControlModifier);
    QTest::keyClicks(editor, "-2.5");
    QTest::keyClick(editor, Qt::Key_Return);
    QApplication::processEvents();
    EXPECT_EQ(doc->project().combos.find(mine, theirs), std::optional<double>(-2.5));
    EXPECT_EQ(doc->undoStack()->count(), 1);

    action(w.get(), "actionSave")->trigger();
    EXPECT_FALSE(w->isWindowModified());
    QFile saved(demo.project);
    ASSERT_TRUE(saved.open(QIODevice::ReadOnly));
    EXPECT_EQ(saved.readAll().toStdString(), doc->serialized());
    auto reopened = fray::authoring::ProjectDocument::open(demo.project.toStdString());
    ASSERT_TRUE(reopened) << reopened.error().message;
    EXPECT_EQ((*reopened)->serialized(), doc->serialized());
    EXPECT_EQ((*reopened)->project().combos.find(mine, theirs), std::optional<double>(-2.5));
}

TEST_F(EditorEdits, DroppingATakeImportsItAndTheGraphRebuildsWithANewThreshold) {
    // A take dropped on the window: one undo step, a new motion in the library.
    const QString take = demo.dir.filePath("walking.bvh");
    QMimeData mime;
    mime.setUrls({QUrl::fromLocalFile(take)});
    // As a drag from a file manager arrives: enter (Qt records the target), then drop.
    QDragEnterEvent enter(QPoint(200, 200), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(w.get(), &enter);
    EXPECT_TRUE(enter.isAccepted()) << "the window accepts motion files";
    QDropEvent drop(QPointF(200, 200), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(w.get(), &drop);
    ASSERT_EQ(doc->project().motions.size(), 7u) << w->lastError().toStdString();
    EXPECT_EQ(doc->project().motions.back().id, "walking_2");
    auto* library = w->findChild<QTreeWidget*>("library");
    EXPECT_EQ(library->topLevelItemCount(), 7);
    // A new clustering threshold typed in the graph panel: saved in the
    // project (undoable) and the graph rebuilt in the background.
    ASSERT_TRUE(QTest::qWaitFor([&] { return w->analysis() != nullptr; }, 240000)) << w->lastError().toStdString();
    const int nodesBefore = w->analysis()->graph.nodeCount;
    auto* dock = w->findChild<QDockWidget*>("GraphDock");
    dock->show();
    dock->raise();
    auto* threshold = w->findChild<QDoubleSpinBox*>("graphThreshold");
    ASSERT_NE(threshold, nullptr);
    threshold->setFocus();
    threshold->selectAll();
    QTest::keyClicks(threshold, "0.12");
    QTest::keyClick(threshold, Qt::Key_Return);
    EXPECT_EQ(doc->project().settings.graphThreshold, std::optional<double>(0.12));
    ASSERT_TRUE(QTest::qWaitFor([&] { return w->analysis() && w->analysis()->graphThreshold == 0.12; }, 240000))
        << w->lastError().toStdString();
    EXPECT_GT(w->analysis()->graph.nodeCount, nodesBefore) << "a lower threshold gives more nodes";
    EXPECT_EQ(w->analysis()->motions.size(), 7u) << "the imported take is analysed too";
}

TEST(EditorBadInput, CorruptProjectAndBrokenTakeGiveOneClearMessage) {
    DemoCopy demo{false};  // no cache: the analysis runs from the takes
    auto w = openWindow(demo.project, EditorOptions::Recovery::Discard);
    ASSERT_NE(w, nullptr);
    // A project with a bad field: refused, named by file and JSON path, untouched.
    const QString bad = demo.dir.filePath("bad.frayproj");
    {
        QFile in(demo.project);
        ASSERT_TRUE(in.open(QIODevice::ReadOnly));
        QByteArray text = in.readAll();
        const int at = text.indexOf("\"cuts\"");
        ASSERT_GT(at, 0);
        const int open = text.indexOf('[', at);
        text.insert(open + 1, "\"seven\", ");
        QFile out(bad);
        ASSERT_TRUE(out.open(QIODevice::WriteOnly));
        out.write(text);
    }
    QFile before(bad);
    ASSERT_TRUE(before.open(QIODevice::ReadOnly));
    const QByteArray badBytes = before.readAll();
    EXPECT_FALSE(w->openPath(bad));
    EXPECT_TRUE(w->lastError().contains("bad.frayproj")) << w->lastError().toStdString();
    EXPECT_TRUE(w->lastError().contains("/motions/0/cuts")) << w->lastError().toStdString();
    QFile after(bad);
    ASSERT_TRUE(after.open(QIODevice::ReadOnly));
    EXPECT_EQ(after.readAll(), badBytes);
    EXPECT_NE(w->document(), nullptr) << "the open project stays open";
    // A broken BVH dropped in: file:line, nothing imported.
    const QString broken = demo.dir.filePath("broken.bvh");
    {
        QFile in(demo.dir.filePath("walking.bvh"));
        ASSERT_TRUE(in.open(QIODevice::ReadOnly));
        QByteArray text = in.readAll();
        text.truncate(text.indexOf("MOTION") + 40);
        text += "\n0.0 zero.5 1.0\n";
        QFile out(broken);
        ASSERT_TRUE(out.open(QIODevice::WriteOnly));
        out.write(text);
    }
    const std::size_t motions = w->document()->project().motions.size();
    w->importMotionFiles({broken});
    EXPECT_EQ(w->document()->project().motions.size(), motions);
    EXPECT_TRUE(w->lastError().contains(QRegularExpression("broken\\.bvh:[0-9]+"))) << w->lastError().toStdString();
}

// The child side of the crash test, run by KilledEditorIsRecoveredExactly as
// this binary with FRAY_CRASH_PROJECT set (not a test of its own): edit,
// autosave, write what the autosave holds, then die by SIGKILL (no cleanup,
// no save). A failed step exits 2 with a message, which the parent reports.
#define CHILD_CHECK(cond)                                                  \
    do {                                                                   \
        if (!(cond)) {                                                     \
            std::fprintf(stderr, "crash child: failed: %s\n", #cond);      \
            return 2;                                                      \
        }                                                                  \
    } while (0)

int crashChild(const QString& project) {
    auto w = openWindow(project, EditorOptions::Recovery::Discard);
    CHILD_CHECK(w != nullptr);
    auto* doc = w->document();
    segmentFirstMotion(w.get());
    const auto [act, word] = actionWithProposal(doc->project());
    CHILD_CHECK(act >= 0);
    selectAction(w.get(), 0, act);
    auto* accept = w->findChild<QToolButton*>(QString::fromStdString("accept:" + word));
    CHILD_CHECK(accept != nullptr);
    QTest::mouseClick(accept, Qt::LeftButton);
    auto* name = w->findChild<QLineEdit*>("actionName");
    name->setFocus();
    name->selectAll();
    QTest::keyClicks(name, "crash_test_name");
    QTest::keyClick(name, Qt::Key_Return);
    CHILD_CHECK(doc->undoStack()->count() >= 2);
    CHILD_CHECK(w->autosaver()->autosaveNow());
    QFile expected(project + ".expected");
    CHILD_CHECK(expected.open(QIODevice::WriteOnly));
    expected.write(QByteArray::fromStdString(doc->serialized()));
    expected.close();
    // One more edit after the autosave: it is lost with the crash, as it would be.
    CHILD_CHECK(doc->setActionName(doc->project().motions[0].id, act, "after_autosave"));
    ::kill(::getpid(), SIGKILL);
    return 2;  // not reached
}

TEST(EditorCrash, KilledEditorIsRecoveredExactly) {
    DemoCopy demo{false};  // no cache: the analysis runs from the takes
    const QByteArray before = [&] {
        QFile f(demo.project);
        f.open(QIODevice::ReadOnly);
        return f.readAll();
    }();
    QProcess child;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert("FRAY_CRASH_PROJECT", demo.project);
    env.insert("QT_QPA_PLATFORM", "offscreen");
    child.setProcessEnvironment(env);
    child.start(QCoreApplication::applicationFilePath(), {});
    ASSERT_TRUE(child.waitForFinished(240000));
    EXPECT_EQ(child.exitStatus(), QProcess::CrashExit) << child.readAllStandardOutput().toStdString();
    QFile expected(demo.project + ".expected");
    ASSERT_TRUE(expected.open(QIODevice::ReadOnly)) << "the child did not reach its autosave: "
                                                    << child.readAllStandardOutput().toStdString();
    const std::string autosaved = expected.readAll().toStdString();
    // The project file itself was never touched.
    QFile project(demo.project);
    ASSERT_TRUE(project.open(QIODevice::ReadOnly));
    EXPECT_EQ(project.readAll(), before);
    ASSERT_TRUE(fray::authoring::findRecovery(demo.project.toStdString()).has_value());
    // Restart: the editor offers the autosave; recovering gives its exact state, unsaved.
    auto w = openWindow(demo.project, EditorOptions::Recovery::Recover);
    ASSERT_NE(w, nullptr);
    EXPECT_EQ(w->document()->serialized(), autosaved);
    EXPECT_TRUE(w->document()->isDirty());
    EXPECT_TRUE(w->isWindowModified());
}

}  // namespace

int main(int argc, char** argv) {
    // The crash-recovery test's child process: edits, then dies.
    return fray::test::runWindowTests(argc, argv, "offscreen", []() -> std::optional<int> {
        if (const QByteArray project = qgetenv("FRAY_CRASH_PROJECT"); !project.isEmpty()) return crashChild(QString::fromUtf8(project));
        return std::nullopt;
    });
}
