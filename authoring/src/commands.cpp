#include "fray/authoring/commands.h"

#include <algorithm>

#include "fray/prep/project_edits.h"

namespace fray::authoring {

// ---- CutCommand -------------------------------------------------------------

CutCommand::CutCommand(ProjectDocument* document, const QString& text, std::string motionId, prep::CutEdit edit,
                       DragId drag)
    : DocumentCommand(document, text), motionId_(std::move(motionId)), edit_(std::move(edit)), drag_(drag) {}

void CutCommand::redo() { apply(edit_); }
void CutCommand::undo() { apply(prep::inverse(edit_)); }

int CutCommand::id() const {
    return edit_.kind == prep::CutEdit::Kind::Move && drag_ != 0 ? kMoveCutCommand : -1;
}

bool CutCommand::mergeWith(const QUndoCommand* other) {
    const auto* next = dynamic_cast<const CutCommand*>(other);
    if (!next || next->drag_ != drag_ || next->motionId_ != motionId_ || next->edit_.kind != prep::CutEdit::Kind::Move ||
        next->edit_.frame != edit_.toFrame) {
        return false;
    }
    // The neighbours of the cut did not change during the drag, so the
    // combined move is as valid as each step.
    edit_.toFrame = next->edit_.toFrame;
    setObsolete(edit_.toFrame == edit_.frame);
    return true;
}

void CutCommand::apply(const prep::CutEdit& edit) {
    prep::ProjectMotion* m = project().findMotion(motionId_);
    assert(m && "cut edit of a motion that is not in the project");
    if (!m) return;
    const Status st = prep::apply(m->actions, edit);
    assert(st.ok() && "the undo stack no longer matches the cuts");
    if (!st) return;
    const int frame = edit.kind == prep::CutEdit::Kind::Move ? std::min(edit.frame, edit.toFrame) : edit.frame;
    // The action ending just before the cut is the first one touched, before and after.
    notify({ChangeKind::Cuts, motionId_, m->actions.actionAt(frame - 1), 0});
}

// ---- motions ----------------------------------------------------------------

ImportMotionsCommand::ImportMotionsCommand(ProjectDocument* document, std::vector<prep::ProjectMotion> motions)
    : DocumentCommand(document, motions.size() == 1 ? QStringLiteral("Import %1").arg(QString::fromStdString(motions[0].id))
                                                    : QStringLiteral("Import %1 motions").arg(motions.size())),
      motions_(std::move(motions)),
      givenFor_(projectFile()) {}

void ImportMotionsCommand::redo() {
    auto& list = project().motions;
    first_ = static_cast<int>(list.size());
    for (prep::ProjectMotion m : motions_) {
        m.path = prep::rebaseMotionPath(givenFor_, projectFile(), m.path);
        list.push_back(std::move(m));
    }
    notify({ChangeKind::MotionsAdded, motions_.front().id, first_, static_cast<int>(motions_.size())});
}

void ImportMotionsCommand::undo() {
    auto& list = project().motions;
    assert(list.size() >= motions_.size());
    list.erase(list.begin() + first_, list.begin() + first_ + static_cast<std::ptrdiff_t>(motions_.size()));
    notify({ChangeKind::MotionsRemoved, motions_.front().id, first_, static_cast<int>(motions_.size())});
}

RemoveMotionCommand::RemoveMotionCommand(ProjectDocument* document, int index)
    : DocumentCommand(document, QString()),
      motion_(project().motions[static_cast<std::size_t>(index)]),
      givenFor_(projectFile()),
      index_(index) {
    setText(QStringLiteral("Remove %1").arg(QString::fromStdString(motion_.id)));
}

void RemoveMotionCommand::redo() {
    auto& list = project().motions;
    list.erase(list.begin() + index_);
    notify({ChangeKind::MotionsRemoved, motion_.id, index_, 1});
}

void RemoveMotionCommand::undo() {
    prep::ProjectMotion m = motion_;
    m.path = prep::rebaseMotionPath(givenFor_, projectFile(), m.path);
    auto& list = project().motions;
    list.insert(list.begin() + index_, std::move(m));
    notify({ChangeKind::MotionsAdded, motion_.id, index_, 1});
}

// ---- vocabulary -------------------------------------------------------------

VocabularyCommand::VocabularyCommand(ProjectDocument* document, const QString& text, const prep::Project& after)
    : DocumentCommand(document, text), before_(capture(project())), after_(capture(after)) {}

VocabularyCommand::Words VocabularyCommand::capture(const prep::Project& project) {
    Words w{project.vocabulary, {}, project.combos};
    w.actions.reserve(project.motions.size());
    for (const auto& m : project.motions) w.actions.push_back(m.actions.actions);
    return w;
}

void VocabularyCommand::restore(const Words& words) {
    prep::Project& p = project();
    assert(words.actions.size() == p.motions.size());
    p.vocabulary = words.vocabulary;
    p.combos = words.combos;
    for (std::size_t i = 0; i < p.motions.size() && i < words.actions.size(); ++i) {
        p.motions[i].actions.actions = words.actions[i];
    }
    notify({ChangeKind::Vocabulary, {}, -1, 0});
}

void VocabularyCommand::redo() { restore(after_); }
void VocabularyCommand::undo() { restore(before_); }

// ---- sections -----------------------------------------------------------------

SectionCommand::SectionCommand(ProjectDocument* document, const QString& text, std::string section,
                               std::optional<std::string> after, std::string key, std::vector<ChangeEvent> events,
                               DragId drag)
    : DocumentCommand(document, text),
      section_(std::move(section)),
      after_(std::move(after)),
      key_(std::move(key)),
      events_(std::move(events)),
      drag_(drag) {
    const auto& sections = project().laterSections;
    if (const auto it = sections.find(section_); it != sections.end()) before_ = it->second;
}

void SectionCommand::redo() { set(after_); }
void SectionCommand::undo() { set(before_); }

bool SectionCommand::mergeWith(const QUndoCommand* other) {
    const auto* next = dynamic_cast<const SectionCommand*>(other);
    if (!next || next->drag_ != drag_ || next->key_ != key_ || next->section_ != section_) return false;
    after_ = next->after_;
    // Views refresh what either step named.
    for (const auto& e : next->events_) {
        auto same = std::find_if(events_.begin(), events_.end(), [&](const ChangeEvent& x) {
            return x.kind == e.kind && x.setup == e.setup && x.character == e.character && x.index == e.index;
        });
        if (same == events_.end()) {
            events_.push_back(e);
        } else if (e.kind == ChangeKind::SetupFloor && !same->pixels.empty() && !e.pixels.empty()) {
            // One stroke dragged on: the union of the changed rectangles.
            const int x0 = std::min(same->pixels.x, e.pixels.x), y0 = std::min(same->pixels.y, e.pixels.y);
            const int x1 = std::max(same->pixels.x + same->pixels.width, e.pixels.x + e.pixels.width);
            const int y1 = std::max(same->pixels.y + same->pixels.height, e.pixels.y + e.pixels.height);
            same->pixels = {x0, y0, x1 - x0, y1 - y0};
        } else if (e.kind == ChangeKind::SetupFloor) {
            same->pixels = {};  // all of it
        }
    }
    setObsolete(after_ == before_);
    return true;
}

void SectionCommand::set(const std::optional<std::string>& value) {
    auto& sections = project().laterSections;
    if (value) sections[section_] = *value;
    else sections.erase(section_);
    for (const auto& e : events_) notify(e);
}

}  // namespace fray::authoring
