// Project-wide edits shared by the editor's commands and the CLI: vocabulary
// renames and removals, checks of authored fields, motion paths on Save As.
#include <gtest/gtest.h>

#include "fray/prep/project_edits.h"

using namespace fray::prep;
namespace fs = std::filesystem;

namespace {

Project sample() {
    Project p = makeProject("edits");
    ProjectMotion m;
    m.id = "box";
    m.path = "takes/box.bvh";
    m.actions = MotionActions::whole(300);
    m.actions.cuts = {100, 200};
    m.actions.actions.resize(3);
    m.actions.actions[0].annotations = {"punch", "step"};
    m.actions.actions[1].proposed = {"punch"};
    m.actions.actions[2].annotations = {"block"};
    p.motions.push_back(m);
    p.combos.set({"@punch", "@block", 1.0});
    p.combos.set({"jab", "@punch", -1.0});
    p.combos.set({"@kick", "jab", 0.5});
    return p;
}

}  // namespace

TEST(ProjectEdits, RenameReachesAnnotationsProposalsAndCombos) {
    Project p = sample();
    ASSERT_TRUE(renameVocabularyWord(p, "punch", "strike").ok());
    const auto& a = p.motions[0].actions.actions;
    EXPECT_EQ(a[0].annotations, (std::vector<std::string>{"strike", "step"}));
    EXPECT_EQ(a[1].proposed, (std::vector<std::string>{"strike"}));
    EXPECT_EQ(p.vocabulary[0], "strike");
    ASSERT_EQ(p.combos.records().size(), 3u);
    EXPECT_EQ(p.combos.records()[0], (ComboRecord{"@strike", "@block", 1.0}));  // order kept
    EXPECT_EQ(p.combos.records()[1], (ComboRecord{"jab", "@strike", -1.0}));
    EXPECT_EQ(vocabularyWordUses(p, "strike"), 4);
    EXPECT_EQ(vocabularyWordUses(p, "punch"), 0);
    // The result is a loadable project.
    EXPECT_TRUE(projectFromJson(projectToJson(p), "p").ok());
}

TEST(ProjectEdits, RefusedRenamesChangeNothing) {
    Project p = sample();
    p.combos.set({"@strike", "@block", 2.0});
    const Project before = p;
    auto st = renameVocabularyWord(p, "punch", "strike");  // "@strike,@block" would appear twice
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().message.find("would hold (@strike, @block) twice"), std::string::npos) << st.error().message;
    st = renameVocabularyWord(p, "punch", "kick");
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().message.find("\"kick\" is already a word"), std::string::npos);
    st = renameVocabularyWord(p, "nope", "x");
    ASSERT_FALSE(st.ok());
    st = renameVocabularyWord(p, "punch", "Punch!");
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(p, before);
}

TEST(ProjectEdits, RemoveDropsTheWordEverywhere) {
    Project p = sample();
    ASSERT_TRUE(removeVocabularyWord(p, "punch").ok());
    EXPECT_EQ(p.motions[0].actions.actions[0].annotations, (std::vector<std::string>{"step"}));
    EXPECT_TRUE(p.motions[0].actions.actions[1].proposed.empty());
    EXPECT_EQ(p.combos.records(), (std::vector<ComboRecord>{{"@kick", "jab", 0.5}}));
    EXPECT_FALSE(removeVocabularyWord(p, "punch").ok());
    ASSERT_TRUE(addVocabularyWord(p, "punch").ok());
    EXPECT_EQ(p.vocabulary.back(), "punch");
    EXPECT_FALSE(addVocabularyWord(p, "punch").ok());
    EXPECT_TRUE(projectFromJson(projectToJson(p), "p").ok());
}

TEST(ProjectEdits, ChecksNameTheFieldAndTheProblem) {
    const Project p = sample();
    ActionInfo a;
    a.annotations = {"punch", "kik"};
    EXPECT_EQ(checkActionInfo(p, a, "motion \"box\", action 1"),
              "motion \"box\", action 1: annotation \"kik\" is not in the project vocabulary");
    a.annotations = {"punch"};
    a.proposed = {"kick", "kick"};
    EXPECT_EQ(checkActionInfo(p, a, "here"), "here: proposal \"kick\" appears twice");
    a.proposed.clear();
    a.initialConditions = InitialConditions{0, 1, 0, 0, 0, 0, 0.5, 0.1};
    EXPECT_NE(checkActionInfo(p, a, "here")->find("initial-condition timing range"), std::string::npos);
    a.initialConditions->maxTiming = 0.6;
    EXPECT_FALSE(checkActionInfo(p, a, "here").has_value());

    EXPECT_NE(checkContactLabel(p.motions[0], {250, 300, true, true})->find("outside the motion's 0..299"),
              std::string::npos);
    EXPECT_FALSE(checkContactLabel(p.motions[0], {250, 299, true, std::nullopt}).has_value());

    ProjectSettings s;
    EXPECT_FALSE(checkSettings(s).has_value());
    s.graphPreset = "ballet";
    EXPECT_TRUE(checkSettings(s).has_value());
    s.graphPreset = "locomotion";
    s.graphThreshold = 0.0;
    EXPECT_EQ(checkSettings(s), "graph threshold must be positive");
}

TEST(ProjectEdits, RebasedMotionPathsResolveToTheSameFile) {
    const fs::path root = fs::temp_directory_path() / "fray_rebase";
    const fs::path from = root / "a" / "p.frayproj", to = root / "b" / "c" / "q.frayproj";
    EXPECT_EQ(rebaseMotionPath(from, root / "a" / "other.frayproj", "takes/../takes/x.bvh"), "takes/../takes/x.bvh");
    EXPECT_EQ(rebaseMotionPath(from, to, "/abs/x.bvh"), "/abs/x.bvh");
    const std::string moved = rebaseMotionPath(from, to, "takes/x.bvh");
    EXPECT_EQ(moved, "../../a/takes/x.bvh");
    ProjectMotion m;
    m.path = moved;
    EXPECT_EQ(resolveMotionPath(to, m).lexically_normal(), (root / "a" / "takes" / "x.bvh").lexically_normal());
}
