// 1,000 random edits (seeded) of the demo project through ProjectDocument:
// each undoes to the bytes from before it and redoes to the bytes after it;
// undo-all gives back the start and redo-all the end.
#include <gtest/gtest.h>

#include <QUndoStack>

#include <functional>
#include <map>
#include <random>

#include "document_fixture.h"
#include "fray/authoring/project_document.h"
#include "fray/prep/project.h"

using namespace fray;
using authoring::ProjectDocument;

namespace {

struct Edits {
    ProjectDocument& doc;
    std::mt19937& rng;
    int serial = 0;

    int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
    template <class T>
    const T& pick(const std::vector<T>& v) { return v[static_cast<std::size_t>(uniform(0, static_cast<int>(v.size()) - 1))]; }
    const prep::ProjectMotion& motion() { return pick(doc.project().motions); }
    int action(const prep::ProjectMotion& m) { return uniform(0, m.actions.actionCount() - 1); }
    std::string word() { return pick(doc.project().vocabulary); }

    // Each returns the edit's status; a refused edit (e.g. a frame that is
    // already a cut) is simply drawn again.
    using Edit = std::function<Status()>;
    std::vector<std::pair<const char*, Edit>> all() {
        return {
            {"add cut", [&] { const auto& m = motion(); return doc.addCut(m.id, uniform(1, m.actions.frameCount - 1)); }},
            {"remove cut", [&] {
                 const auto& m = motion();
                 if (m.actions.cuts.empty()) return Status(makeError("no cuts"));
                 return doc.removeCut(m.id, pick(m.actions.cuts));
             }},
            {"move cut", [&] {
                 const auto& m = motion();
                 if (m.actions.cuts.empty()) return Status(makeError("no cuts"));
                 const int c = pick(m.actions.cuts);
                 return doc.moveCut(m.id, c, c + uniform(-6, 6));
             }},
            {"drag cut", [&] {
                 const auto& m = motion();
                 if (m.actions.cuts.empty()) return Status(makeError("no cuts"));
                 const std::string id = m.id;
                 int c = pick(m.actions.cuts);
                 const auto drag = doc.beginDrag();
                 for (int i = 0, n = uniform(2, 5); i < n; ++i) {
                     const int to = c + uniform(-2, 2);
                     if (Status st = doc.moveCut(id, c, to, drag); !st) return i == 0 ? st : Status();
                     c = to;
                 }
                 return Status();
             }},
            {"split", [&] {
                 const auto& m = motion();
                 const int a = action(m);
                 return doc.splitAction(m.id, a, uniform(m.actions.firstFrame(a), m.actions.lastFrame(a)));
             }},
            {"merge", [&] { const auto& m = motion(); return doc.mergeActions(m.id, action(m)); }},
            {"name", [&] {
                 static const std::vector<std::string> names = {"jab", "hook", "duck", "step", "", "fall"};
                 const auto& m = motion();
                 return doc.setActionName(m.id, action(m), pick(names));
             }},
            {"annotate", [&] { const auto& m = motion(); return doc.addAnnotation(m.id, action(m), word()); }},
            {"unannotate", [&] {
                 const auto& m = motion();
                 const int a = action(m);
                 const auto& ann = m.actions.actions[static_cast<std::size_t>(a)].annotations;
                 if (ann.empty()) return Status(makeError("none"));
                 return doc.removeAnnotation(m.id, a, pick(ann));
             }},
            {"propose", [&] {
                 const auto& m = motion();
                 const int a = action(m);
                 prep::ActionInfo info = m.actions.actions[static_cast<std::size_t>(a)];
                 const std::string w = word();
                 if (info.has(w) || std::find(info.proposed.begin(), info.proposed.end(), w) != info.proposed.end())
                     return Status(makeError("taken"));
                 info.proposed.push_back(w);
                 return doc.setActionInfo(m.id, a, info);
             }},
            {"confirm or reject", [&] {
                 for (int tries = 0; tries < 20; ++tries) {
                     const auto& m = motion();
                     const int a = action(m);
                     const auto& p = m.actions.actions[static_cast<std::size_t>(a)].proposed;
                     if (p.empty()) continue;
                     const std::string w = pick(p);
                     return uniform(0, 1) ? doc.confirmProposal(m.id, a, w) : doc.rejectProposal(m.id, a, w);
                 }
                 return Status(makeError("no proposals"));
             }},
            {"joints", [&] {
                 const auto& m = motion();
                 return doc.setJoints(m.id, action(m), uniform(0, 1) ? std::vector<std::string>{"LeftHand"}
                                                                      : std::vector<std::string>{"RightFoot", "RightLeg"});
             }},
            {"attack direction", [&] {
                 const auto& m = motion();
                 return doc.setAttackDirection(m.id, action(m), uniform(0, 2) ? std::optional<std::string>("straight")
                                                                              : std::nullopt);
             }},
            {"defended part", [&] {
                 const auto& m = motion();
                 return doc.setDefendedPart(m.id, action(m), uniform(0, 2) ? std::optional<std::string>("head")
                                                                          : std::nullopt);
             }},
            {"initial conditions", [&] {
                 const auto& m = motion();
                 const double d = uniform(3, 12) / 10.0;
                 return doc.setInitialConditions(m.id, action(m),
                                                 prep::InitialConditions{d, d + 0.4, -0.3, 0.3, 2.8, 3.4, 0.0, 0.2});
             }},
            {"vocabulary add", [&] { return doc.addVocabularyWord("word" + std::to_string(++serial)); }},
            {"vocabulary rename", [&] { return doc.renameVocabularyWord(word(), "renamed" + std::to_string(++serial)); }},
            {"vocabulary remove", [&] {
                 if (doc.project().vocabulary.size() < 8) return Status(makeError("keep some words"));
                 return doc.removeVocabularyWord(word());
             }},
            {"contact label add", [&] {
                 const auto& m = motion();
                 const int f = uniform(0, m.actions.frameCount - 1);
                 return doc.addContactLabel(m.id, {f, std::min(f + uniform(0, 60), m.actions.frameCount - 1),
                                                   uniform(0, 1) == 1, std::nullopt});
             }},
            {"contact label remove", [&] {
                 const auto& m = motion();
                 if (m.contactLabels.empty()) return Status(makeError("none"));
                 return doc.removeContactLabel(m.id, uniform(0, static_cast<int>(m.contactLabels.size()) - 1));
             }},
            {"combo set", [&] {
                 return doc.setComboRecord({"@" + word(), uniform(0, 1) ? "jab" : "@" + word(), uniform(-4, 4) / 2.0});
             }},
            {"combo remove", [&] {
                 const auto& r = doc.project().combos.records();
                 if (r.empty()) return Status(makeError("none"));
                 const auto rec = pick(r);
                 return doc.removeComboRecord(rec.mine, rec.theirs);
             }},
            {"settings", [&] {
                 switch (uniform(0, 2)) {
                     case 0: return doc.setGraphPreset(uniform(0, 1) ? "fighting" : "locomotion");
                     case 1: return doc.setGraphThreshold(uniform(0, 3) ? std::optional<double>(uniform(1, 40) / 10.0)
                                                                        : std::nullopt);
                     default: return doc.setSegmentThresholdFactor(uniform(4, 20) * 1.0);
                 }
             }},
            {"import", [&] {
                 prep::ProjectMotion m;
                 m.id = "extra";
                 m.path = "extra/take.bvh";
                 m.actions = prep::MotionActions::whole(uniform(120, 900));
                 return doc.importMotions({m});
             }},
            {"remove motion", [&] {
                 if (doc.project().motions.size() < 4) return Status(makeError("keep some motions"));
                 const std::string id = motion().id;
                 return doc.removeMotion(id);
             }},
        };
    }
};

}  // namespace

TEST(RandomEdits, ThousandSeededEditsUndoAndRedoExactly) {
    test::TempDir dir;
    auto opened = test::openDemoCopy(dir);
    ASSERT_TRUE(opened);
    ProjectDocument& doc = *opened;
    QUndoStack& stack = *doc.undoStack();
    stack.setUndoLimit(0);  // unlimited: undo-all must reach the start
    std::mt19937 rng(20261126);
    Edits edits{doc, rng};
    const auto kinds = edits.all();
    std::map<std::string, int> done;

    const std::string start = doc.serialized();
    int steps = 0, attempts = 0;
    while (steps < 1000 && attempts < 20000) {
        ++attempts;
        const auto& [name, edit] = kinds[static_cast<std::size_t>(edits.uniform(0, static_cast<int>(kinds.size()) - 1))];
        const std::string before = doc.serialized();
        const int index = stack.index();
        const Status st = edit();
        if (!st.ok() || stack.index() == index) {
            // Refused (or a no-op) edits must leave the document as it was.
            ASSERT_EQ(doc.serialized(), before) << name << ": " << (st.ok() ? "no-op" : st.error().message);
            continue;
        }
        ASSERT_EQ(stack.index(), index + 1) << name << " pushed more than one step";
        const std::string after = doc.serialized();
        stack.undo();
        ASSERT_EQ(doc.serialized(), before) << "undo of edit " << steps << " (" << name << ")";
        stack.redo();
        ASSERT_EQ(doc.serialized(), after) << "redo of edit " << steps << " (" << name << ")";
        for (const auto& m : doc.project().motions) {
            ASSERT_FALSE(m.actions.validate().has_value()) << name << ": " << m.id << ": " << *m.actions.validate();
        }
        ++done[name];
        ++steps;
    }
    ASSERT_EQ(steps, 1000) << "too many refused edits";
    for (const auto& [name, edit] : kinds) EXPECT_GE(done[name], 10) << name << " was hardly exercised";

    const std::string end = doc.serialized();
    const auto reloaded = prep::projectFromJson(end, "end.frayproj");
    ASSERT_TRUE(reloaded.ok()) << reloaded.error().message;
    EXPECT_EQ(prep::projectToJson(*reloaded), end);

    ASSERT_EQ(stack.count(), 1000);
    while (stack.canUndo()) stack.undo();
    EXPECT_EQ(doc.serialized(), start);
    while (stack.canRedo()) stack.redo();
    EXPECT_EQ(doc.serialized(), end);
}
