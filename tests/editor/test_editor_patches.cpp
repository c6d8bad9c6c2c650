// The PatternList editor and the patch browser on a copy of the demo project,
// offscreen: rows added, moved and removed through the panel are undo steps;
// Generate patches runs in the background and says why paths were
// discarded; a composed setup uses patches, and once one of them is rejected in
// the browser the next composition does not use it; a PatternList with an
// annotation no action has is refused with a clear message.
#include <gtest/gtest.h>

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDialog>
#include <QDoubleSpinBox>
#include <QDir>
#include <QFile>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QStatusBar>
#include <QTableView>
#include <QTemporaryDir>
#include <QTest>
#include <QUndoStack>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "editor_fixture.h"
#include "fray/authoring/project_document.h"
#include "main_window.h"
#include "patch_browser.h"
#include "patterns_panel.h"
#include "scene_stage.h"

namespace {

using fray::test::child;

namespace fs = std::filesystem;
using fray::editor::MainWindow;
using fray::test::DemoCopy;

void waitIdle(MainWindow* w) {
    if (!QTest::qWaitFor([&] { return !w->busy(); }, 120000)) ADD_FAILURE() << "the background job did not finish";
}

// The patches of `lib` the scene plays: both characters' actions at the
// patch's relative times, in two of the scene's characters.
std::set<int> usedPatches(const fray::sim::Scene& scene, const fray::sim::PatchLibrary& lib) {
    std::set<int> used;
    const auto matches = [&](const std::vector<fray::sim::ActionInstance>& track, const std::vector<fray::sim::ActionInstance>& part,
                             double offset) {
        for (const auto& want : part) {
            bool found = false;
            for (const auto& have : track)
                found = found || (have.action == want.action && std::abs(have.start - (want.start + offset)) < 1e-6);
            if (!found) return false;
        }
        return true;
    };
    for (std::size_t p = 0; p < lib.patches().size(); ++p) {
        const auto& patch = lib.patches()[p];
        if (patch.tracks[0].empty() || patch.tracks[1].empty()) continue;
        for (std::size_t a = 0; a < scene.characters.size() && !used.count(static_cast<int>(p)); ++a) {
            for (const auto& inst : scene.characters[a].track) {
                if (inst.action != patch.tracks[0].front().action) continue;
                const double offset = inst.start - patch.tracks[0].front().start;
                if (!matches(scene.characters[a].track, patch.tracks[0], offset)) continue;
                for (std::size_t b = 0; b < scene.characters.size(); ++b)
                    if (b != a && matches(scene.characters[b].track, patch.tracks[1], offset)) used.insert(static_cast<int>(p));
            }
        }
    }
    return used;
}

TEST(EditorPatches, EditAPatternListGeneratePatchesRejectOneAndComposeWithoutIt) {
    DemoCopy demo;
    auto w = fray::test::openEditorWindow(demo.project);
    ASSERT_NE(w, nullptr);
    ASSERT_TRUE(QTest::qWaitFor([&] { return w->analysis() != nullptr; }, 120000));
    fray::authoring::ProjectDocument* doc = w->document();
    QUndoStack* undo = doc->undoStack();

    // A one-vs-many setup drawing on one PatternList, imported from a spec file.
    QFile spec(demo.dir.filePath("brawl.json"));
    ASSERT_TRUE(spec.open(QIODevice::WriteOnly));
    spec.write(R"({"kind": "one-vs-many", "duration": 25, "seed": 2, "enemies": 4, "entry_radius": 6,
                   "patterns": ["strike-fall"]})");
    spec.close();
    ASSERT_TRUE(w->selectSceneSource(spec.fileName()));
    ASSERT_TRUE(w->importSpecAsSetup("brawl")) << w->lastError().toStdString();
    EXPECT_EQ(w->currentSetup(), "brawl");

    // The PatternList: a new list with its first row, then rows added with the panel's row controls.
    fray::sim::PatternList list;
    list.name = "strike-fall";
    list.entries = {{0, "attack"}, {1, "falling"}};
    const fray::Status added = doc->addPattern(list);
    ASSERT_TRUE(added) << added.error().message;
    auto* panel = child<fray::editor::PatternsPanel>(w.get(), "patternsPanel");
    auto* lists = child<QComboBox>(w.get(), "patternLists");
    ASSERT_EQ(lists->count(), 1);
    EXPECT_EQ(lists->currentText(), "strike-fall");
    auto* character = child<QComboBox>(w.get(), "patternRowCharacter");
    auto* annotation = child<QComboBox>(w.get(), "patternRowAnnotation");
    auto* addRow = child<QPushButton>(w.get(), "patternAddRow");
    auto* rows = child<QListWidget>(w.get(), "patternRows");
    const auto texts = [&] {
        QStringList out;
        for (int i = 0; i < rows->count(); ++i) out << rows->item(i)->text();
        return out.join(", ");
    };
    ASSERT_EQ(texts(), "1: attack, 2: falling");
    const auto addRowUi = [&](int who, const char* word) {
        character->setCurrentIndex(who);
        annotation->setCurrentText(word);
        rows->setCurrentRow(rows->count() - 1);
        QTest::mouseClick(addRow, Qt::LeftButton);
    };
    const int before = undo->count();
    addRowUi(1, "block");
    EXPECT_EQ(texts(), "1: attack, 2: falling, 2: block");
    // Reorder (what a drop in the list does to its model): the block before the fall.
    rows->model()->moveRow(QModelIndex(), 2, QModelIndex(), 1);
    ASSERT_TRUE(QTest::qWaitFor([&] { return undo->count() == before + 2; }, 5000));
    EXPECT_EQ(texts(), "1: attack, 2: block, 2: falling");
    auto set = doc->patternSet();
    ASSERT_TRUE(set);
    ASSERT_EQ(set->patterns[0].entries.size(), 3u);
    EXPECT_EQ(set->patterns[0].entries[1].annotation, "block");
    // Remove the block row (selected, Remove row).
    rows->setCurrentRow(1);
    QTest::mouseClick(child<QPushButton>(w.get(), "patternRemoveRow"), Qt::LeftButton);
    EXPECT_EQ(texts(), "1: attack, 2: falling");
    EXPECT_EQ(undo->count(), before + 3);
    // Undo and redo: the panel follows the document.
    undo->undo();
    EXPECT_EQ(texts(), "1: attack, 2: block, 2: falling");
    undo->redo();
    EXPECT_EQ(texts(), "1: attack, 2: falling");
    // An annotation no action has: refused with a message, the project unchanged.
    const std::string beforeBad = doc->serialized();
    addRowUi(1, "cartwheel");
    EXPECT_EQ(doc->serialized(), beforeBad);
    EXPECT_TRUE(w->lastError().contains("cartwheel")) << w->lastError().toStdString();
    EXPECT_EQ(texts(), "1: attack, 2: falling");
    panel->grab().save(QString(FRAY_EDITOR_SHOTS) + "/PatternsDock.png");

    // Generate patches in the background: the report says why paths were discarded.
    QTest::mouseClick(child<QPushButton>(w.get(), "patternGenerate"), Qt::LeftButton);
    EXPECT_TRUE(w->busy());
    waitIdle(w.get());
    ASSERT_NE(w->patchLibrary(), nullptr) << w->lastError().toStdString();
    const fray::sim::PatchLibrary& lib = *w->patchLibrary();
    ASSERT_GT(lib.patches().size(), 3u);
    const QString report = child<QLabel>(w.get(), "patternReport")->text();
    EXPECT_TRUE(report.contains("discarded")) << report.toStdString();
    EXPECT_TRUE(report.contains("strike-fall")) << report.toStdString();
    EXPECT_TRUE(fs::exists(demo.project.toStdString() + ".patches"));
    auto* browser = child<fray::editor::PatchBrowser>(w.get(), "patchBrowser");
    EXPECT_EQ(browser->table()->model()->rowCount(), static_cast<int>(lib.patches().size()));

    // Compose the setup: some patches are used.
    QTest::mouseClick(child<QPushButton>(w.get(), "sceneGenerate"), Qt::LeftButton);
    waitIdle(w.get());
    ASSERT_NE(w->scene(), nullptr) << w->lastError().toStdString();
    const std::set<int> first = usedPatches(w->scene()->scene(), lib);
    ASSERT_FALSE(first.empty()) << "no patch of the library found in the composed scene";
    const int victim = *first.begin();
    std::printf("editor: the composition used %zu of %zu patches; rejecting patch %d\n", first.size(), lib.patches().size(), victim);

    // Select it in the browser (a real click on its row): it plays, looping.
    browser->table()->sortByColumn(2, Qt::DescendingOrder);  // by score: the row moves, the patch stays
    const int row = browser->rowOfPatch(victim);
    ASSERT_GE(row, 0);
    QTest::mouseClick(browser->table()->viewport(), Qt::LeftButton, Qt::NoModifier,
                      browser->table()->visualRect(browser->table()->model()->index(row, 1)).center());
    EXPECT_EQ(browser->selectedPatch(), victim);
    ASSERT_NE(w->scene(), nullptr);
    EXPECT_EQ(w->scene()->scene().characters.size(), 2u);
    EXPECT_DOUBLE_EQ(w->scene()->duration(), lib.patches()[static_cast<std::size_t>(victim)].duration);
    // Reject it: stored in the setup, one undo step.
    const int steps = undo->count();
    QTest::mouseClick(child<QPushButton>(w.get(), "patchReject"), Qt::LeftButton);
    EXPECT_EQ(undo->count(), steps + 1);
    EXPECT_EQ(w->rejectedPatches(), std::vector<int>{victim});
    EXPECT_EQ(browser->table()->model()->index(row, 6).data().toString(), "rejected");
    browser->grab().save(QString(FRAY_EDITOR_SHOTS) + "/PatchesDock.png");

    // Compose again: the rejected patch is not used.
    ASSERT_TRUE(w->selectSetup("brawl"));
    QTest::mouseClick(child<QPushButton>(w.get(), "sceneGenerate"), Qt::LeftButton);
    waitIdle(w.get());
    ASSERT_NE(w->scene(), nullptr) << w->lastError().toStdString();
    const std::set<int> second = usedPatches(w->scene()->scene(), lib);
    EXPECT_FALSE(second.empty());
    EXPECT_EQ(second.count(victim), 0u) << "the rejected patch was composed";
    // Saved and reopened, the verdict stays.
    ASSERT_TRUE(doc->save());
    w.reset();
    auto again = fray::test::openEditorWindow(demo.project);
    ASSERT_NE(again, nullptr);
    ASSERT_TRUE(again->selectSetup("brawl"));
    EXPECT_EQ(again->rejectedPatches(), std::vector<int>{victim});
}

// A hand-made patch: character 1's action picked from the library in the
// Hand-made dialog, played by the patch engine, added as kept (one undo
// step), stored in the project; a wrong action is refused, nothing changed.
TEST(EditorPatches, AHandMadePatchBuiltActionByActionIsKeptAndStored) {
    DemoCopy demo;
    auto w = fray::test::openEditorWindow(demo.project);
    ASSERT_NE(w, nullptr);
    ASSERT_TRUE(QTest::qWaitFor([&] { return w->analysis() != nullptr; }, 120000));
    fray::authoring::ProjectDocument* doc = w->document();
    QUndoStack* undo = doc->undoStack();
    ASSERT_TRUE(doc->addSetup("ovm", fray::setup::SetupKind::OneVsMany));
    w->findChild<QCheckBox*>("sceneLive")->setChecked(false);
    ASSERT_TRUE(w->selectSetup("ovm"));
    for (const auto& p : fray::sim::defaultPatterns())
        if (p.name == "attack-fall") {
            ASSERT_TRUE(doc->addPattern(p));
        }
    QTest::mouseClick(child<QPushButton>(w.get(), "patternGenerate"), Qt::LeftButton);
    waitIdle(w.get());
    ASSERT_NE(w->patchLibrary(), nullptr) << w->lastError().toStdString();
    const std::size_t generated = w->patchLibrary()->patches().size();
    ASSERT_GT(generated, 0u);
    // Before generating there is nothing to add to; with patches, the dialog.
    QTest::mouseClick(child<QPushButton>(w.get(), "patchHandMade"), Qt::LeftButton);
    QDialog* dialog = w->handMadeDialog();
    ASSERT_NE(dialog, nullptr);
    auto* pattern = child<QComboBox>(dialog, "handMadePattern");
    auto* action = child<QComboBox>(dialog, "handMadeAction");
    auto* result = child<QLabel>(dialog, "handMadeResult");
    pattern->setCurrentText("attack-fall");
    const fray::sim::ActionLibrary* actions = w->patchActions();
    ASSERT_NE(actions, nullptr);
    const auto labelOf = [&](int a) { return QString::fromStdString(actions->actions()[static_cast<std::size_t>(a)].label()); };
    const fray::sim::Patch src = w->patchLibrary()->patches().front();
    const auto setConfig = [&](const fray::sim::PatchConfig& c) {
        child<QDoubleSpinBox>(dialog, "handMadeR")->setValue(c.r);
        child<QDoubleSpinBox>(dialog, "handMadeTheta1")->setValue(c.theta1 * 180.0 / 3.14159265358979323846);
        child<QDoubleSpinBox>(dialog, "handMadeTheta2")->setValue(c.theta2 * 180.0 / 3.14159265358979323846);
        child<QDoubleSpinBox>(dialog, "handMadeDelay")->setValue(c.delay);
    };
    setConfig(src.initial);
    // A block where the pattern wants an attack: Evaluate says why, Add changes nothing.
    int block = -1;
    for (int i = 0; i < actions->size() && block < 0; ++i)
        if (actions->actions()[static_cast<std::size_t>(i)].is(fray::sim::kBlock)) block = i;
    ASSERT_GE(block, 0);
    const std::string before = doc->serialized();
    action->setCurrentText(labelOf(block));
    QTest::mouseClick(child<QPushButton>(dialog, "handMadeAdd1"), Qt::LeftButton);
    QTest::mouseClick(child<QPushButton>(dialog, "handMadeEvaluate"), Qt::LeftButton);
    EXPECT_TRUE(result->text().contains("is not 'attack'")) << result->text().toStdString();
    const int steps = undo->count();
    QTest::mouseClick(child<QPushButton>(dialog, "handMadeKeep"), Qt::LeftButton);
    EXPECT_EQ(doc->serialized(), before);
    EXPECT_EQ(undo->count(), steps);
    EXPECT_EQ(w->patchLibrary()->patches().size(), generated);
    QTest::mouseClick(child<QPushButton>(dialog, "handMadeClear"), Qt::LeftButton);
    // The generated patch's attack by character 1, from its configuration: it plays and is added as kept.
    action->setCurrentText(labelOf(src.tracks[0].front().action));
    QTest::mouseClick(child<QPushButton>(dialog, "handMadeAdd1"), Qt::LeftButton);
    EXPECT_EQ(child<QListWidget>(dialog, "handMadeActions1")->count(), 1);
    QTest::mouseClick(child<QPushButton>(dialog, "handMadeEvaluate"), Qt::LeftButton);
    EXPECT_TRUE(result->text().contains("score")) << result->text().toStdString();
    dialog->grab().save(QString(FRAY_EDITOR_SHOTS) + "/handmade-dialog.png");
    QTest::mouseClick(child<QPushButton>(dialog, "handMadeKeep"), Qt::LeftButton);
    EXPECT_EQ(undo->count(), steps + 1) << w->lastError().toStdString();
    ASSERT_EQ(w->patchLibrary()->patches().size(), generated + 1);
    const fray::sim::Patch& made = w->patchLibrary()->patches().back();
    EXPECT_TRUE(made.handMade);
    EXPECT_EQ(made.hits.size(), src.hits.size());
    EXPECT_EQ(made.tracks[0].front().action, src.tracks[0].front().action);
    auto s = doc->sceneSetup("ovm");
    EXPECT_EQ(s->patches.kept, std::vector<int>{static_cast<int>(generated)});
    ASSERT_EQ(doc->handMadePatches()->size(), 1u);
    EXPECT_EQ((*doc->handMadePatches())[0].pattern, "attack-fall");
    // Undo removes it from the project and the library; redo puts it back.
    undo->undo();
    EXPECT_EQ(doc->serialized(), before);
    EXPECT_EQ(w->patchLibrary()->patches().size(), generated);
    undo->redo();
    EXPECT_EQ(w->patchLibrary()->patches().size(), generated + 1);
    // Stored in the project: saved and reopened, the recipe is there. (The
    // label is taken first: `actions` belongs to the window closed below.)
    const std::string attackLabel = labelOf(src.tracks[0].front().action).toStdString();
    ASSERT_TRUE(doc->save());
    w.reset();
    auto again = fray::test::openEditorWindow(demo.project);
    ASSERT_NE(again, nullptr);
    auto stored = again->document()->handMadePatches();
    ASSERT_TRUE(stored);
    ASSERT_EQ(stored->size(), 1u);
    EXPECT_EQ((*stored)[0].actions[0], std::vector<std::string>{attackLabel});
}

}  // namespace

int main(int argc, char** argv) { return fray::test::runWindowTests(argc, argv, "offscreen"); }
