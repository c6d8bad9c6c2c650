// ProjectDocument's scene-setup and PatternList edits (issue 23): each edit is
// one undo step whose undo gives back the byte-identical project; bad input is
// refused with a message and changes nothing; drags merge; strokes undo bit
// for bit; save and reopen give the same bytes.
#include <gtest/gtest.h>

#include <QUndoStack>

#include <fstream>
#include <functional>

#include "document_fixture.h"
#include "fray/authoring/project_document.h"
#include "fray/setup/scene_setup.h"

using namespace fray;
using authoring::ChangeEvent;
using authoring::ChangeKind;
using authoring::ProjectDocument;
namespace fs = std::filesystem;

namespace {

// One undoable step (document_fixture.h) after which the project's setups still load.
void oneStep(ProjectDocument& doc, const std::string& what, const std::function<Status()>& edit) {
    test::expectOneUndoableStep(doc, what, edit, [](const prep::Project& reloaded) {
        auto setups = setup::projectSetups(reloaded, "after.frayproj");
        EXPECT_TRUE(setups.ok()) << setups.error().message;
    });
}

void refused(ProjectDocument& doc, const std::string& what, const std::string& message, const std::function<Status()>& edit) {
    SCOPED_TRACE(what);
    const std::string before = doc.serialized();
    const int count = doc.undoStack()->count();
    const Status st = edit();
    ASSERT_FALSE(st.ok()) << "accepted";
    EXPECT_NE(st.error().message.find(message), std::string::npos) << st.error().message;
    EXPECT_EQ(doc.undoStack()->count(), count);
    EXPECT_EQ(doc.serialized(), before);
}

// The demo project has the vocabulary word "punch" on some action; a word of
// the vocabulary that no action carries is found here.
std::string unusedWord(const ProjectDocument& doc) {
    for (const auto& w : doc.project().vocabulary) {
        bool used = false;
        for (const auto& m : doc.project().motions) {
            for (const auto& a : m.actions.actions) used = used || std::find(a.annotations.begin(), a.annotations.end(), w) != a.annotations.end();
        }
        if (!used) return w;
    }
    return {};
}

}  // namespace

TEST(SetupEdits, EveryEditIsOneExactUndoStep) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    std::vector<ChangeEvent> events;
    QObject::connect(doc.get(), &ProjectDocument::changed, [&](const ChangeEvent& e) { events.push_back(e); });
    oneStep(*doc, "add duel", [&] { return doc->addSetup("duel", setup::SetupKind::Duel); });
    EXPECT_EQ(events.back().kind, ChangeKind::SetupAdded);
    EXPECT_EQ(events.back().setup, "duel");
    oneStep(*doc, "add domino", [&] { return doc->addSetup("domino", setup::SetupKind::Domino); });
    oneStep(*doc, "add rat", [&] { return doc->addSetup("rat", setup::SetupKind::Rat); });
    oneStep(*doc, "add one-vs-many", [&] { return doc->addSetup("ovm", setup::SetupKind::OneVsMany); });
    oneStep(*doc, "add football", [&] { return doc->addSetup("football", setup::SetupKind::Football); });
    oneStep(*doc, "duplicate", [&] { return doc->duplicateSetup("duel", "duel 2"); });
    oneStep(*doc, "rename", [&] { return doc->renameSetup("duel 2", "sparring"); });
    EXPECT_EQ(events.back().kind, ChangeKind::SetupRenamed);
    EXPECT_EQ(events.back().previousName, "duel 2");
    oneStep(*doc, "remove", [&] { return doc->removeSetup("sparring"); });
    oneStep(*doc, "parameter", [&] { return doc->setSetupParameter("duel", "/duration", "12.5"); });
    oneStep(*doc, "depth", [&] { return doc->setSetupParameter("duel", "/characters/0/depth", "4"); });
    oneStep(*doc, "start", [&] { return doc->setCharacterStart("duel", "blue", {1.4, 0.2, -80}); });
    EXPECT_EQ(events.back().kind, ChangeKind::SetupPlacement);
    EXPECT_EQ(events.back().character, "blue");
    oneStep(*doc, "team", [&] { return doc->moveTeam("duel", 0, 0.5, 0); });
    setup::Trajectory t{"red", setup::TrajectoryShape::Polyline, {{0, 0}, {3, 0}}, false, false, {}};
    oneStep(*doc, "trajectory", [&] { return doc->addTrajectory("duel", t); });
    oneStep(*doc, "point", [&] { return doc->addTrajectoryPoint("duel", "red", 2, {3, 3}); });
    oneStep(*doc, "move point", [&] { return doc->moveTrajectoryPoint("duel", "red", 2, {4, 3}); });
    oneStep(*doc, "remove point", [&] { return doc->removeTrajectoryPoint("duel", "red", 1); });
    Result<int> at = 0;
    oneStep(*doc, "checkpoint", [&] {
        at = doc->addCheckpoint("duel", "red", {{2, 1.5}, 4.0, ""});
        return at ? Status{} : Status(at.error());
    });
    EXPECT_EQ(*at, 0);
    oneStep(*doc, "checkpoint before", [&] {
        at = doc->addCheckpoint("duel", "red", {{0.5, 0.5}, std::nullopt, ""});
        return at ? Status{} : Status(at.error());
    });
    EXPECT_EQ(*at, 0);  // it comes first along the trajectory
    oneStep(*doc, "checkpoint time", [&] { return doc->setCheckpointTime("duel", "red", 0, 2.0); });
    oneStep(*doc, "checkpoint action", [&] { return doc->setCheckpointAction("duel", "red", 0, "@punch"); });
    oneStep(*doc, "move checkpoint", [&] { return doc->moveCheckpoint("duel", "red", 1, {2.2, 1.6}); });
    oneStep(*doc, "remove checkpoint", [&] { return doc->removeCheckpoint("duel", "red", 1); });
    oneStep(*doc, "pin", [&] { return doc->addPin("duel", {"red", 3.0, "jab"}); });
    oneStep(*doc, "unpin", [&] { return doc->removePin("duel", 0); });
    oneStep(*doc, "remove trajectory", [&] { return doc->removeTrajectory("duel", "red"); });
    oneStep(*doc, "reject", [&] { return doc->setPatchVerdict("ovm", 3, ProjectDocument::Verdict::Reject); });
    oneStep(*doc, "keep", [&] { return doc->setPatchVerdict("ovm", 3, ProjectDocument::Verdict::Keep); });
    oneStep(*doc, "commands", [&] { return doc->setTimedCommands("ovm", {{0, "move", setup::Point{2, 1}}, {4, "kick"}}); });
    oneStep(*doc, "rat path", [&] { return doc->setRatPath("rat", {{-5, 0}, {0, 2}, {5, 0}}); });
    oneStep(*doc, "directions", [&] { return doc->setRunDirections("football", {{0, 0}, {5, 30}}); });
    oneStep(*doc, "domino starts", [&] { return doc->setDominoStarts("domino", {{0.5, {1, 1}}}); });
    setup::FloorStroke brush;
    brush.points = {{-1, 0}, {1, 0}};
    oneStep(*doc, "brush", [&] { return doc->paintFloor("domino", brush).ok() ? Status{} : makeError("stroke"); });
    EXPECT_EQ(events.back().kind, ChangeKind::SetupFloor);
    EXPECT_FALSE(events.back().pixels.empty());
    setup::FloorStroke text;
    text.tool = setup::FloorStroke::Tool::Text;
    text.text = "FRAY";
    text.points = {{-8, 2}};
    text.startTime = 1.0;
    oneStep(*doc, "text", [&] { return doc->paintFloor("domino", text).ok() ? Status{} : makeError("text"); });
    EXPECT_EQ(setup::dominoStarts(*doc->sceneSetup("domino")).size(), 5u);  // one per letter, and the first
    setup::FloorStroke eraser = brush;
    eraser.tool = setup::FloorStroke::Tool::Eraser;
    oneStep(*doc, "eraser", [&] { return doc->paintFloor("domino", eraser).ok() ? Status{} : makeError("eraser"); });

    // PatternLists.
    sim::PatternList p;
    p.name = "punch-avoid";
    p.entries = {{0, "attack"}, {1, "defence"}};
    oneStep(*doc, "pattern", [&] { return doc->addPattern(p); });
    oneStep(*doc, "row", [&] { return doc->addPatternRow("punch-avoid", 2, {0, "punch"}); });
    oneStep(*doc, "move row", [&] { return doc->movePatternRow("punch-avoid", 2, 0); });
    oneStep(*doc, "remove row", [&] { return doc->removePatternRow("punch-avoid", 0); });
    oneStep(*doc, "weights", [&] { return doc->setPatternWeights("punch-avoid", {2, 1, 0.5}); });
    oneStep(*doc, "threshold", [&] { return doc->setPatternThreshold("punch-avoid", 0.7); });
    oneStep(*doc, "range", [&] { return doc->setInitialRange("punch", sim::InitialRange{0.5, 1.0, -30, 30, 0, 0.2}); });
    oneStep(*doc, "rename pattern", [&] { return doc->renamePattern("punch-avoid", "pa"); });
    EXPECT_EQ(events.back().kind, ChangeKind::PatternLists);
    oneStep(*doc, "remove pattern", [&] { return doc->removePattern("pa"); });

    // Undo everything: the file as it was opened.
    while (doc->undoStack()->canUndo()) doc->undoStack()->undo();
    EXPECT_EQ(doc->serialized(), test::readFile(dir / "demo.frayproj"));
}

TEST(SetupEdits, BadInputChangesNothing) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    ASSERT_TRUE(doc->addSetup("duel", setup::SetupKind::Duel).ok());
    ASSERT_TRUE(doc->addSetup("domino", setup::SetupKind::Domino).ok());
    refused(*doc, "same name", "already exists", [&] { return doc->addSetup("duel", setup::SetupKind::Chase); });
    refused(*doc, "empty name", "must not be empty", [&] { return doc->addSetup("", setup::SetupKind::Chase); });
    // A duel's parameters are read as simulate reads them: what it could not read is refused, naming the field.
    refused(*doc, "unknown preset", "/characters/0/preset: unknown preset 'boxer'",
            [&] { return doc->setSetupParameter("duel", "/characters/0/preset", "\"boxer\""); });
    refused(*doc, "negative weight", "/characters/1/weights/w_r: must be between 0 and 1e6",
            [&] { return doc->setSetupParameter("duel", "/characters/1/weights/w_r", "-1"); });
    refused(*doc, "annotation not in the takes", "no action has annotation 'carry' in the selected motions",
            [&] { return doc->setSetupParameter("duel", "/characters/1/actions", R"(["@carry"])"); });
    refused(*doc, "no setup", "no setup 'x'", [&] { return doc->removeSetup("x"); });
    refused(*doc, "empty trajectory", "is empty", [&] {
        return doc->addTrajectory("duel", {"red", setup::TrajectoryShape::Polyline, {}, false, false, {}});
    });
    refused(*doc, "flat arc", "on a line", [&] {
        return doc->addTrajectory("duel", {"red", setup::TrajectoryShape::Arc, {{0, 0}, {1, 0}, {2, 0}}, false, false, {}});
    });
    refused(*doc, "nobody", "no character named 'green'", [&] {
        return doc->addTrajectory("duel", {"green", setup::TrajectoryShape::Polyline, {{0, 0}}, false, false, {}});
    });
    refused(*doc, "not finite", "finite", [&] { return doc->setCharacterStart("duel", "red", {std::nan(""), 0, 0}); });
    refused(*doc, "kind parameter", "kind", [&] { return doc->setSetupParameter("duel", "/kind", "\"rat\""); });
    refused(*doc, "bad json", "not valid JSON", [&] { return doc->setSetupParameter("duel", "/duration", "{"); });
    // An imported bitmap that is not an image.
    { std::ofstream(dir / "notes.png") << "these are my notes, not a picture"; }
    refused(*doc, "not an image", "notes.png: not an image", [&] { return doc->importFloorImage("domino", dir / "notes.png", 0.1, {0, 0}); });
    refused(*doc, "no file", "no such file", [&] { return doc->importFloorImage("domino", dir / "none.png", 0.1, {0, 0}); });
    setup::FloorStroke letters;
    letters.tool = setup::FloorStroke::Tool::Text;
    letters.text = "a%";
    letters.points = {{0, 0}};
    refused(*doc, "bad letter", "no letter '%'", [&] { return doc->paintFloor("domino", letters).ok() ? Status{} : Status(doc->paintFloor("domino", letters).error()); });
    // PatternLists: an annotation no action has, or one outside the vocabulary.
    sim::PatternList p;
    p.name = "x";
    p.entries = {{0, "kik"}, {1, "defence"}};
    refused(*doc, "unknown annotation", "'kik' is not in the project vocabulary", [&] { return doc->addPattern(p); });
    const std::string unused = unusedWord(*doc);
    if (!unused.empty()) {
        p.entries[0].annotation = unused;
        refused(*doc, "annotation no action has", "no action of the project has annotation '" + unused + "'", [&] { return doc->addPattern(p); });
    }
    p.entries = {{0, "attack"}};
    refused(*doc, "one character", "both characters", [&] { return doc->addPattern(p); });
    p.entries = {{0, "attack"}, {1, "defence"}};
    ASSERT_TRUE(doc->addPattern(p).ok());
    refused(*doc, "last row", "both characters", [&] { return doc->removePatternRow("x", 1); });
    refused(*doc, "threshold", "[0, 1]", [&] { return doc->setPatternThreshold("x", 2); });
    refused(*doc, "range", "max is below its min", [&] { return doc->setInitialRange("punch", sim::InitialRange{1, 0.5, 0, 0, 0, 0}); });
}

TEST(SetupEdits, DragsMergeAndStrokesUndoBitForBit) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    ASSERT_TRUE(doc->addSetup("duel", setup::SetupKind::Duel).ok());
    ASSERT_TRUE(doc->addSetup("domino", setup::SetupKind::Domino).ok());
    const int steps = doc->undoStack()->count();
    const authoring::DragId drag = doc->beginDrag();
    for (int i = 1; i <= 10; ++i) ASSERT_TRUE(doc->setCharacterStart("duel", "blue", {1.1 + 0.1 * i, 0, -90}, drag).ok());
    EXPECT_EQ(doc->undoStack()->count(), steps + 1);
    // Back where it started: the merged step disappears.
    ASSERT_TRUE(doc->setCharacterStart("duel", "blue", {1.1, 0, -90}, drag).ok());
    EXPECT_EQ(doc->undoStack()->count(), steps);

    const setup::FloorPaint blank = *doc->sceneSetup("domino")->floor;
    const authoring::DragId stroke = doc->beginDrag();
    setup::FloorStroke brush;
    brush.radius = 0.4;
    for (int i = 0; i < 8; ++i) {
        brush.points = {{-4.0 + i, -1.0 + 0.25 * i}, {-3.0 + i, -1.0 + 0.25 * (i + 1)}};
        ASSERT_TRUE(doc->paintFloor("domino", brush, stroke).ok());
    }
    EXPECT_EQ(doc->undoStack()->count(), steps + 1);
    const setup::FloorPaint painted = *doc->sceneSetup("domino")->floor;
    EXPECT_NE(painted, blank);
    doc->undoStack()->undo();
    EXPECT_EQ(*doc->sceneSetup("domino")->floor, blank);
    doc->undoStack()->redo();
    EXPECT_EQ(*doc->sceneSetup("domino")->floor, painted);
}

TEST(SetupEdits, SaveAndReopenGiveTheSameBytes) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    ASSERT_TRUE(doc->addSetup("domino", setup::SetupKind::Domino).ok());
    setup::FloorStroke brush;
    brush.points = {{-3, 0}, {3, 1}};
    ASSERT_TRUE(doc->paintFloor("domino", brush).ok());
    ASSERT_TRUE(doc->addSetup("duel", setup::SetupKind::Duel).ok());
    ASSERT_TRUE(doc->addTrajectory("duel", {"red", setup::TrajectoryShape::Circle, {{0, 0}, {2, 0}}, false, true,
                                            {{{0, 2}, 3.0, "@punch"}}}).ok());
    sim::PatternList p;
    p.name = "x";
    p.entries = {{0, "attack"}, {1, "defence"}};
    ASSERT_TRUE(doc->addPattern(p).ok());
    ASSERT_TRUE(doc->save().ok());
    const std::string saved = test::readFile(dir / "demo.frayproj");
    EXPECT_EQ(saved, doc->serialized());
    auto again = ProjectDocument::open(dir / "demo.frayproj");
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_EQ((*again)->serialized(), saved);
    EXPECT_EQ(*(*again)->setups(), *doc->setups());
}

TEST(SetupEdits, ImportASpecFileWithItsBitmap) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const fs::path demo = FRAY_DEMO_SPECS;
    oneStep(*doc, "import domino", [&] { return doc->importSetupFromSpec("crowd", demo / "domino.json"); });
    auto s = doc->sceneSetup("crowd");
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s->kind, setup::SetupKind::Domino);
    ASSERT_TRUE(s->floor);
    EXPECT_EQ(s->floor->width, 200);
    EXPECT_EQ(s->floor->height, 120);
    EXPECT_EQ(std::count(s->floor->painted.begin(), s->floor->painted.end(), 1), 8213);  // as fray-cli setup list counts it
    oneStep(*doc, "import duel", [&] { return doc->importSetupFromSpec("duel", demo / "duel.json"); });
    EXPECT_EQ(doc->sceneSetup("duel")->kind, setup::SetupKind::Duel);
    // A spec whose bitmap is not an image: refused, naming it.
    fs::create_directories(dir / "specs");
    fs::copy_file(demo / "domino.json", dir / "specs" / "domino.json");
    { std::ofstream(dir / "specs" / "domino_floor.png") << "not a picture"; }
    refused(*doc, "bitmap not an image", "domino_floor.png: not an image", [&] { return doc->importSetupFromSpec("bad", dir / "specs" / "domino.json"); });
    refused(*doc, "name taken", "already exists", [&] { return doc->importSetupFromSpec("duel", demo / "duel.json"); });
}
