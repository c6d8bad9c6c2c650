// ProjectDocument: every edit is one undo command whose undo gives back the
// byte-identical project file; random edit sequences undo and redo exactly;
// drags merge; dirty state follows the stack; saves are atomic.
#include <gtest/gtest.h>

#include <fstream>

#include <QUndoStack>

#include <functional>
#include <map>
#include <random>

#include "document_fixture.h"
#include "fray/authoring/project_document.h"
#include "fray/core/atomic_file.h"
#include "fray/prep/project.h"

using namespace fray;
using authoring::ChangeEvent;
using authoring::ChangeKind;
using authoring::ProjectDocument;
namespace fs = std::filesystem;

namespace {

// The cut frames of a motion, for building edits.
const prep::MotionActions& actionsOf(const ProjectDocument& doc, const std::string& id) {
    return doc.project().findMotion(id)->actions;
}

using test::expectOneUndoableStep;  // document_fixture.h

prep::ProjectMotion extraMotion(const std::string& id, int frames) {
    prep::ProjectMotion m;
    m.id = id;
    m.path = "takes/" + id + ".bvh";
    m.actions = prep::MotionActions::whole(frames);
    return m;
}

}  // namespace

TEST(Document, OpensTheDemoAndSerializesItsExactBytes) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    EXPECT_EQ(doc->serialized(), test::readFile(test::demoProject()));
    EXPECT_FALSE(doc->isDirty());
    EXPECT_EQ(doc->undoStack()->count(), 0);
}

TEST(Document, EveryEditKindUndoesToTheSameBytes) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    ProjectDocument& d = *doc;
    const std::string start = d.serialized();
    const std::string box = "shadowbox_energetic";
    const auto& acts = [&]() -> const prep::MotionActions& { return actionsOf(d, box); };
    ASSERT_GT(acts().cuts.size(), 10u);

    expectOneUndoableStep(d, "project name", [&] { return d.setName("fight club"); });
    expectOneUndoableStep(d, "graph preset", [&] { return d.setGraphPreset("locomotion"); });
    expectOneUndoableStep(d, "graph threshold", [&] { return d.setGraphThreshold(3.5); });
    expectOneUndoableStep(d, "segmentation factor", [&] { return d.setSegmentThresholdFactor(9.0); });
    expectOneUndoableStep(d, "import", [&] { return d.importMotions({extraMotion("walking", 240)}); });
    EXPECT_TRUE(d.project().findMotion("walking_2")) << "an imported id that is taken gets a suffix";
    expectOneUndoableStep(d, "remove motion", [&] { return d.removeMotion("falls"); });
    const int c0 = acts().cuts[0], c1 = acts().cuts[1], c2 = acts().cuts[2];
    expectOneUndoableStep(d, "add cut", [&] { return d.addCut(box, (c0 + c1) / 2); });
    expectOneUndoableStep(d, "remove cut", [&] { return d.removeCut(box, c2); });
    expectOneUndoableStep(d, "move cut", [&] { return d.moveCut(box, acts().cuts[0], acts().cuts[0] + 1); });
    expectOneUndoableStep(d, "split", [&] { return d.splitAction(box, 4, acts().firstFrame(4) + 2); });
    expectOneUndoableStep(d, "merge", [&] { return d.mergeActions(box, 1); });
    {
        // A re-segmentation: every cut and description of the motion at once.
        const auto& c = acts().cuts;
        prep::MotionActions resegmented = prep::recut(acts(), {c[0], c[2], c[5], c[7], c[9], c[11]});
        resegmented.actions[1].proposed = {"kick"};
        prep::MotionActions wrong = resegmented;
        wrong.frameCount += 1;
        EXPECT_FALSE(d.setMotionActions(box, wrong, "Segment")) << "a frame count that is not the motion's";
        expectOneUndoableStep(d, "segment", [&] { return d.setMotionActions(box, resegmented, "Segment"); });
        EXPECT_EQ(acts().cuts.size(), 6u);
    }
    expectOneUndoableStep(d, "action name", [&] { return d.setActionName(box, 3, "spinning_backfist"); });
    expectOneUndoableStep(d, "add annotation", [&] { return d.addAnnotation(box, 3, "turn"); });
    expectOneUndoableStep(d, "remove annotation", [&] { return d.removeAnnotation(box, 3, "turn"); });
    prep::ActionInfo proposed = d.project().findMotion(box)->actions.actions[5];
    proposed.proposed = {"kick", "idle"};
    expectOneUndoableStep(d, "whole action info", [&] { return d.setActionInfo(box, 5, proposed); });
    expectOneUndoableStep(d, "confirm proposal", [&] { return d.confirmProposal(box, 5, "kick"); });
    EXPECT_TRUE(d.project().findMotion(box)->actions.actions[5].has("kick"));
    expectOneUndoableStep(d, "reject proposal", [&] { return d.rejectProposal(box, 5, "idle"); });
    EXPECT_TRUE(d.project().findMotion(box)->actions.actions[5].proposed.empty());
    expectOneUndoableStep(d, "joints", [&] { return d.setJoints(box, 3, {"LeftHand", "LeftForeArm"}); });
    expectOneUndoableStep(d, "attack direction", [&] { return d.setAttackDirection(box, 3, "hook-left"); });
    expectOneUndoableStep(d, "defended part", [&] { return d.setDefendedPart(box, 3, "body"); });
    expectOneUndoableStep(d, "initial conditions", [&] {
        return d.setInitialConditions(box, 3, prep::InitialConditions{0.4, 1.1, -0.5, 0.5, 2.9, 3.3, 0.0, 0.3});
    });
    expectOneUndoableStep(d, "vocabulary add", [&] { return d.addVocabularyWord("taunt"); });
    expectOneUndoableStep(d, "vocabulary rename", [&] { return d.renameVocabularyWord("punch", "strike"); });
    expectOneUndoableStep(d, "vocabulary remove", [&] { return d.removeVocabularyWord("block"); });
    expectOneUndoableStep(d, "contact label add", [&] { return d.addContactLabel(box, {100, 140, true, false}); });
    expectOneUndoableStep(d, "contact label change", [&] { return d.changeContactLabel(box, 0, {10, 20, false, true}); });
    expectOneUndoableStep(d, "contact label remove", [&] { return d.removeContactLabel(box, 1); });
    expectOneUndoableStep(d, "combo set", [&] { return d.setComboRecord({"spinning_backfist", "@kick", 0.75}); });
    const auto first = d.project().combos.records().front();
    expectOneUndoableStep(d, "combo replace", [&] { return d.setComboRecord({first.mine, first.theirs, -2.0}); });
    expectOneUndoableStep(d, "combo remove", [&] { return d.removeComboRecord(first.mine, first.theirs); });

    while (d.undoStack()->canUndo()) d.undoStack()->undo();
    EXPECT_EQ(d.serialized(), start);
}

TEST(Document, VocabularyRenameAndRemoveReachActionsAndCombos) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const std::string box = "shadowbox_energetic";
    auto count = [&](const std::string& w) {
        int n = 0;
        for (const auto& m : doc->project().motions)
            for (const auto& a : m.actions.actions) n += a.has(w);
        return n;
    };
    const int punches = count("punch");
    ASSERT_GT(punches, 10);
    ASSERT_TRUE(doc->setComboRecord({"@punch", "@block", 1.0}).ok());
    ASSERT_TRUE(doc->renameVocabularyWord("punch", "strike").ok());
    EXPECT_EQ(count("punch"), 0);
    EXPECT_EQ(count("strike"), punches);
    EXPECT_TRUE(doc->project().combos.find("@strike", "@block"));
    ASSERT_TRUE(doc->removeVocabularyWord("block").ok());
    EXPECT_EQ(count("block"), 0);
    EXPECT_FALSE(doc->project().combos.find("@strike", "@block"));
    doc->undoStack()->undo();
    doc->undoStack()->undo();
    EXPECT_EQ(count("punch"), punches);
    EXPECT_TRUE(doc->project().combos.find("@punch", "@block"));
}

TEST(Document, RefusedEditsNameTheProblemAndChangeNothing) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const std::string bytes = doc->serialized();
    const std::string box = "shadowbox_energetic";
    const int firstCut = actionsOf(*doc, box).cuts[0];
    struct Case {
        std::function<Status()> edit;
        std::string expect;
    };
    const Case cases[] = {
        {[&] { return doc->addCut("nope", 10); }, "no motion \"nope\""},
        {[&] { return doc->addCut(box, firstCut); }, "is already a cut"},
        {[&] { return doc->addCut(box, 0); }, "cannot cut at frame 0"},
        {[&] { return doc->removeCut(box, firstCut + 1); }, "is not a cut"},
        {[&] { return doc->moveCut(box, firstCut, 0); }, "it must stay between frames"},
        {[&] { return doc->splitAction(box, 0, 0); }, "action 0: cannot split at frame 0"},
        {[&] { return doc->mergeActions(box, 100000); }, "cannot merge action 100000"},
        {[&] { return doc->setActionName(box, -1, "x"); }, "action -1: no such action"},
        {[&] { return doc->addAnnotation(box, 0, "kik"); }, "annotation \"kik\" is not in the project vocabulary"},
        {[&] { return doc->setAnnotations(box, 0, {"kick", "kick"}); }, "annotation \"kick\" appears twice"},
        {[&] { return doc->confirmProposal(box, 0, "kick"); }, "\"kick\" is not a proposal"},
        {[&] { return doc->setInitialConditions(box, 0, prep::InitialConditions{2, 1, 0, 0, 0, 0, 0, 0}); },
         "initial-condition distance range"},
        {[&] { return doc->addVocabularyWord("Bad Word"); }, "\"Bad Word\" must be 1-32 lower-case"},
        {[&] { return doc->addVocabularyWord("punch"); }, "\"punch\" is already a word"},
        {[&] { return doc->renameVocabularyWord("punch", "kick"); }, "\"kick\" is already a word"},
        {[&] { return doc->removeVocabularyWord("zzz"); }, "\"zzz\" is not a word"},
        {[&] { return doc->addContactLabel(box, {10, 1000000, true, true}); }, "are outside the motion's"},
        {[&] { return doc->removeContactLabel(box, 99); }, "no contact label 99"},
        {[&] { return doc->setComboRecord({"a b", "jab", 1}); }, "\"a b\" is not an action name"},
        {[&] { return doc->setComboRecord({"@pnuch", "jab", 1}); }, "@pnuch is not in the project vocabulary"},
        {[&] { return doc->setComboRecord({"jabb", "@block", 1}); }, "no action of the project is named \"jabb\""},
        {[&] { return doc->removeComboRecord("x", "y"); }, "no record (x, y)"},
        {[&] { return doc->setGraphPreset("ballet"); }, "graph preset \"ballet\""},
        {[&] { return doc->setGraphThreshold(-1.0); }, "graph threshold must be positive"},
        {[&] { return doc->importMotions({}); }, "no motions given"},
        {[&] { return doc->importMotions({extraMotion("bad", 0)}); }, "import \"bad\": frame count 0"},
        {[&] { return doc->removeMotion("nope"); }, "no motion \"nope\""},
    };
    for (const auto& c : cases) {
        const Status st = c.edit();
        ASSERT_FALSE(st.ok()) << "expected: " << c.expect;
        EXPECT_NE(st.error().message.find(c.expect), std::string::npos) << st.error().message;
    }
    EXPECT_EQ(doc->undoStack()->count(), 0);
    EXPECT_EQ(doc->serialized(), bytes);
    // Setting what is already there pushes nothing.
    EXPECT_TRUE(doc->setName(doc->project().name).ok());
    EXPECT_TRUE(doc->moveCut(box, firstCut, firstCut).ok());
    EXPECT_EQ(doc->undoStack()->count(), 0);
}

TEST(Document, EmitsTypedChangeEvents) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    std::vector<ChangeEvent> events;
    QObject::connect(doc.get(), &ProjectDocument::changed, [&](const ChangeEvent& e) { events.push_back(e); });
    const std::string box = "shadowbox_energetic";
    ASSERT_TRUE(doc->setActionName(box, 7, "uppercut").ok());
    ASSERT_TRUE(doc->addCut(box, actionsOf(*doc, box).firstFrame(9) + 3).ok());
    ASSERT_TRUE(doc->setGraphThreshold(1.5).ok());
    doc->undoStack()->undo();
    const std::vector<ChangeEvent> expected = {{ChangeKind::Action, box, 7, 0},
                                               {ChangeKind::Cuts, box, 9, 0},
                                               {ChangeKind::Settings, {}, -1, 0},
                                               {ChangeKind::Settings, {}, -1, 0}};
    EXPECT_EQ(events, expected);
    EXPECT_EQ(doc->revision(), 4u);
}

TEST(Document, DragsMergeIntoOneUndoStep) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const std::string box = "shadowbox_energetic";
    const std::string start = doc->serialized();
    const int cut = actionsOf(*doc, box).cuts[3];
    auto* stack = doc->undoStack();

    // One drag: five moves of one cut, one undo step.
    const auto drag = doc->beginDrag();
    for (int step = 1; step <= 5; ++step) ASSERT_TRUE(doc->moveCut(box, cut + step - 1, cut + step, drag).ok());
    EXPECT_EQ(stack->count(), 1);
    EXPECT_EQ(actionsOf(*doc, box).cuts[3], cut + 5);
    stack->undo();
    EXPECT_EQ(doc->serialized(), start);
    stack->redo();
    EXPECT_EQ(actionsOf(*doc, box).cuts[3], cut + 5);

    // A second drag is a step of its own, and so are moves outside a drag.
    const auto drag2 = doc->beginDrag();
    ASSERT_TRUE(doc->moveCut(box, cut + 5, cut + 4, drag2).ok());
    ASSERT_TRUE(doc->moveCut(box, cut + 4, cut + 3, drag2).ok());
    EXPECT_EQ(stack->count(), 2);
    ASSERT_TRUE(doc->moveCut(box, cut + 3, cut + 2).ok());
    ASSERT_TRUE(doc->moveCut(box, cut + 2, cut + 1).ok());
    EXPECT_EQ(stack->count(), 4);

    // A drag that comes back where it started leaves no step at all.
    const auto drag3 = doc->beginDrag();
    const std::string beforeDrag3 = doc->serialized();
    ASSERT_TRUE(doc->moveCut(box, cut + 1, cut + 2, drag3).ok());
    ASSERT_TRUE(doc->moveCut(box, cut + 2, cut + 1, drag3).ok());
    EXPECT_EQ(stack->count(), 4);
    EXPECT_EQ(doc->serialized(), beforeDrag3);

    // Slider drags (ChangeValue) merge the same way.
    const auto slider = doc->beginDrag();
    for (double t : {1.0, 1.5, 2.0, 2.5}) ASSERT_TRUE(doc->setGraphThreshold(t, slider).ok());
    EXPECT_EQ(stack->count(), 5);
    EXPECT_EQ(doc->project().settings.graphThreshold, 2.5);
    // Another value in the same drag is a step of its own.
    ASSERT_TRUE(doc->setSegmentThresholdFactor(8.0, slider).ok());
    EXPECT_EQ(stack->count(), 6);
    stack->undo();
    EXPECT_EQ(doc->project().settings.graphThreshold, 2.5);
    stack->redo();
    while (stack->canUndo()) stack->undo();
    EXPECT_EQ(doc->serialized(), start);
}

TEST(Document, DirtyFollowsTheCleanState) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    std::vector<bool> signals_;
    QObject::connect(doc.get(), &ProjectDocument::dirtyChanged, [&](bool dirty) { signals_.push_back(dirty); });
    EXPECT_FALSE(doc->isDirty());
    ASSERT_TRUE(doc->setName("one").ok());
    EXPECT_TRUE(doc->isDirty());
    doc->undoStack()->undo();
    EXPECT_FALSE(doc->isDirty());
    doc->undoStack()->redo();
    ASSERT_TRUE(doc->save().ok());
    EXPECT_FALSE(doc->isDirty());
    doc->undoStack()->undo();  // before the saved state
    EXPECT_TRUE(doc->isDirty());
    doc->undoStack()->redo();
    EXPECT_FALSE(doc->isDirty());
    EXPECT_EQ(signals_, (std::vector<bool>{true, false, true, false, true, false}));
    doc->markDirty();
    EXPECT_TRUE(doc->isDirty());
}

TEST(Document, SaveAndSaveAsAreAtomicAndAFailureKeepsTheOldFile) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const fs::path file = dir / "demo.frayproj";
    const std::string original = test::readFile(file);
    ASSERT_TRUE(doc->setName("edited").ok());

    // Another program saved the project meanwhile: Save refuses to overwrite
    // it, leaves its bytes, and the document stays dirty.
    const std::string theirs = original + "\n";
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out << theirs;
    }
    const Status failed = doc->save();
    ASSERT_FALSE(failed.ok());
    EXPECT_NE(failed.error().message.find("demo.frayproj: changed on disk"), std::string::npos) << failed.error().message;
    EXPECT_EQ(test::readFile(file), theirs);
    EXPECT_TRUE(doc->isDirty());
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out << original;
    }
    // The project's lock held by another program: the save waits, then fails, the old file stays.
    {
        auto held = FileLock::acquire(file, std::chrono::seconds(1));
        ASSERT_TRUE(held.ok());
        const Status locked = doc->save();
        ASSERT_FALSE(locked.ok());
        EXPECT_NE(locked.error().message.find("another program is still editing it"), std::string::npos)
            << locked.error().message;
        EXPECT_EQ(test::readFile(file), original);
        EXPECT_TRUE(doc->isDirty());
    }

    // Save As onto a folder fails the same way and keeps the document's file.
    fs::create_directories(dir / "taken.frayproj" / "x");
    EXPECT_FALSE(doc->saveAs(dir / "taken.frayproj").ok());
    EXPECT_EQ(doc->filePath(), file);
    EXPECT_TRUE(doc->isDirty());

    ASSERT_TRUE(doc->save().ok());
    EXPECT_FALSE(doc->isDirty());
    EXPECT_EQ(test::readFile(file), doc->serialized());
    const auto reloaded = prep::loadProject(file);
    ASSERT_TRUE(reloaded.ok()) << reloaded.error().message;
    EXPECT_EQ(*reloaded, doc->project());
    for (const auto& entry : fs::directory_iterator(dir.path()))
        EXPECT_EQ(entry.path().extension() == ".tmp", false) << "a temporary file was left: " << entry.path();
}

TEST(Document, SaveAsIntoAnotherFolderKeepsMotionPathsPointingAtTheSameFiles) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const fs::path oldFile = doc->filePath();
    std::map<std::string, fs::path> before;
    for (const auto& m : doc->project().motions) before[m.id] = prep::resolveMotionPath(oldFile, m).lexically_normal();
    ASSERT_TRUE(doc->removeMotion("walking").ok());

    const fs::path newFile = dir / "sub" / "deeper" / "moved.frayproj";
    fs::create_directories(newFile.parent_path());
    ASSERT_TRUE(doc->saveAs(newFile).ok());
    EXPECT_EQ(doc->filePath(), newFile);
    EXPECT_FALSE(doc->isDirty());
    for (const auto& m : doc->project().motions) {
        EXPECT_EQ(fs::weakly_canonical(prep::resolveMotionPath(newFile, m)), fs::weakly_canonical(before[m.id])) << m.id;
    }
    // Undoing the removal after the move brings the motion back with a path
    // that resolves from the new folder.
    doc->undoStack()->undo();
    const prep::ProjectMotion* walking = doc->project().findMotion("walking");
    ASSERT_TRUE(walking);
    EXPECT_EQ(fs::weakly_canonical(prep::resolveMotionPath(newFile, *walking)), fs::weakly_canonical(before["walking"]));
    EXPECT_EQ(test::readFile(newFile), prep::projectToJson([&] {
                  auto p = doc->project();
                  p.motions.erase(p.motions.begin() + 5);
                  return p;
              }()));
}

TEST(Document, UntitledDocumentNeedsSaveAs) {
    ProjectDocument doc(prep::makeProject("untitled"));
    const Status st = doc.save();
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().message.find("use Save As"), std::string::npos);
}
