// Cut edits (the document operations the editor undoes) and labels files.
#include <gtest/gtest.h>

#include "fray/prep/actions.h"
#include "fray/prep/labels.h"

using namespace fray::prep;

namespace {

MotionActions sample() {
    MotionActions doc = MotionActions::whole(100);
    doc.cuts = {20, 50};
    doc.actions.resize(3);
    doc.actions[0].name = "jab";
    doc.actions[0].annotations = {"punch"};
    doc.actions[1].name = "duck";
    doc.actions[1].annotations = {"avoid"};
    doc.actions[2].name = "step";
    return doc;
}

}  // namespace

TEST(CutEdits, EveryEditInvertsExactly) {
    const MotionActions start = sample();
    const std::vector<fray::Result<CutEdit>> edits = {makeAddCut(start, 35), makeRemoveCut(start, 20),
                                                      makeMoveCut(start, 50, 60), makeMergeActions(start, 1)};
    for (const auto& e : edits) {
        ASSERT_TRUE(e.ok()) << e.error().message;
        MotionActions doc = start;
        ASSERT_TRUE(apply(doc, *e).ok());
        EXPECT_FALSE(doc.validate().has_value()) << *doc.validate();
        EXPECT_NE(doc, start);
        ASSERT_TRUE(apply(doc, inverse(*e)).ok());
        EXPECT_EQ(doc, start);
    }
}

TEST(CutEdits, SplitCopiesAndMergeUnites) {
    MotionActions doc = sample();
    ASSERT_TRUE(apply(doc, *makeAddCut(doc, 35)).ok());
    ASSERT_EQ(doc.actionCount(), 4);
    EXPECT_EQ(doc.actions[1].name, "duck");
    EXPECT_EQ(doc.actions[2].name, "duck");
    EXPECT_EQ(doc.firstFrame(2), 35);
    EXPECT_EQ(doc.lastFrame(1), 34);
    ASSERT_TRUE(apply(doc, *makeRemoveCut(doc, 20)).ok());
    EXPECT_EQ(doc.actions[0].name, "jab");
    EXPECT_EQ(doc.actions[0].annotations, (std::vector<std::string>{"punch", "avoid"}));
    EXPECT_EQ(doc.lastFrame(0), 34);
}

TEST(CutEdits, RejectsImpossibleEditsWithReasons) {
    const MotionActions doc = sample();
    EXPECT_NE(makeAddCut(doc, 20).error().message.find("already a cut"), std::string::npos);
    EXPECT_NE(makeAddCut(doc, 0).error().message.find("1..99"), std::string::npos);
    EXPECT_NE(makeAddCut(doc, 100).error().message.find("1..99"), std::string::npos);
    EXPECT_NE(makeRemoveCut(doc, 21).error().message.find("not a cut"), std::string::npos);
    EXPECT_NE(makeMoveCut(doc, 20, 50).error().message.find("between frames 1 and 49"), std::string::npos);
    EXPECT_FALSE(makeMergeActions(doc, 2).ok());
}

TEST(CutEdits, RecutKeepsInfoOfActionsThatStillStartThere) {
    const MotionActions doc = sample();
    const MotionActions out = recut(doc, {21, 40, 70});
    ASSERT_EQ(out.actionCount(), 4);
    EXPECT_EQ(out.actions[0].name, "jab");   // frame 0 kept
    EXPECT_EQ(out.actions[1].name, "duck");  // 21 within 3 of 20
    EXPECT_EQ(out.actions[2].name, "");      // 40 is new
    EXPECT_EQ(out.actions[3].name, "");
    EXPECT_FALSE(out.validate().has_value());
}

TEST(Labels, ParsesAndRoundTrips) {
    const auto rows = parseLabelsCsv("# labels\nmotion,first_frame,last_frame,left,right\r\n"
                                     "walk, 10, 20, 1, 0\nwalk,30,40,-,1\n",
                                     "l.csv");
    ASSERT_TRUE(rows.ok()) << rows.error().message;
    ASSERT_EQ(rows->size(), 2u);
    EXPECT_EQ((*rows)[0].label.firstFrame, 10);
    EXPECT_EQ((*rows)[1].label.left, std::nullopt);
    const auto again = parseLabelsCsv(labelsToCsv(*rows), "again.csv");
    ASSERT_TRUE(again.ok());
    EXPECT_EQ((*again)[1].label, (*rows)[1].label);
}

TEST(Labels, ErrorsNameFileLineAndField) {
    const std::string h = "motion,first_frame,last_frame,left,right\n";
    struct Case {
        std::string text, expect;
    };
    const Case cases[] = {
        {"", "l.csv: empty labels file"},
        {"motion,first,last\n", "l.csv:1: header"},
        {h + "walk,10,x,1,0\n", "l.csv:2: last_frame: \"x\" is not a frame number"},
        {h + "walk,10,5,1,0\n", "l.csv:2: last_frame: 5 is before first_frame 10"},
        {h + "walk,-3,5,1,0\n", "l.csv:2: first_frame"},
        {h + "walk,1,5,2,0\n", "l.csv:2: left: \"2\" must be 1, 0 or -"},
        {h + "walk,1,5\n", "l.csv:2: row: expected 5"},
        {h + "walk,1,5,-,-\n", "labels neither foot"},
    };
    for (const auto& c : cases) {
        const auto r = parseLabelsCsv(c.text, "l.csv");
        ASSERT_FALSE(r.ok()) << c.text;
        EXPECT_NE(r.error().message.find(c.expect), std::string::npos) << r.error().message;
    }
}

TEST(Labels, ExpandRejectsOutOfRangeFrames) {
    const auto ok = expandLabels({{2, 4, true, std::nullopt}}, 10);
    ASSERT_TRUE(ok.ok());
    EXPECT_EQ(ok->left[3], 1);
    EXPECT_EQ(ok->right[3], -1);
    EXPECT_EQ(ok->left[5], -1);
    const auto bad = expandLabels({{2, 4, true, true}, {8, 12, false, false}}, 10);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("label 2 covers frames 8..12 but the motion has frames 0..9"),
              std::string::npos);
}
