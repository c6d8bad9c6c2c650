#pragma once
// The undo commands of a ProjectDocument. One generic ChangeValue<T> covers
// every edit that replaces one value (an action's description, the settings,
// a motion's contact labels, the combination table, the name); the specific
// commands cover edits that change the shape of the project (cuts, motions,
// vocabulary). ProjectDocument's edit functions build them; views never do.
#include <QUndoCommand>

#include <cassert>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fray/authoring/change_event.h"
#include "fray/authoring/project_document.h"
#include "fray/prep/actions.h"
#include "fray/prep/project.h"

namespace fray::authoring {

// QUndoCommand::id() values: only commands with the same id may merge.
enum CommandId : int {
    kChangeValueCommand = 1,
    kMoveCutCommand = 2,
    kSectionCommand = 3,
};

class DocumentCommand : public QUndoCommand {
protected:
    DocumentCommand(ProjectDocument* document, const QString& text) : QUndoCommand(text), document_(document) {}
    prep::Project& project() const { return document_->project_; }
    const std::filesystem::path& projectFile() const { return document_->file_; }
    void notify(const ChangeEvent& event) const { document_->notify(event); }

private:
    ProjectDocument* document_;
};

// Replaces the value `locate` finds with a new one. `key` names that value
// (e.g. "action/walk/3/name"); commands of the same key and the same non-zero
// drag merge, and a merge that lands back on the old value drops the step.
template <class T>
class ChangeValue : public DocumentCommand {
public:
    using Locate = std::function<T*(prep::Project&)>;

    ChangeValue(ProjectDocument* document, const QString& text, std::string key, Locate locate, T value,
                ChangeEvent event, DragId drag = 0)
        : DocumentCommand(document, text),
          key_(std::move(key)),
          locate_(std::move(locate)),
          newValue_(std::move(value)),
          event_(std::move(event)),
          drag_(drag) {
        const T* current = locate_(project());
        assert(current && "ChangeValue built for a value that does not exist");
        if (current) oldValue_ = *current;
    }

    void redo() override { set(newValue_); }
    void undo() override { set(oldValue_); }
    int id() const override { return drag_ != 0 ? kChangeValueCommand : -1; }
    bool mergeWith(const QUndoCommand* other) override {
        const auto* next = dynamic_cast<const ChangeValue<T>*>(other);
        if (!next || next->drag_ != drag_ || next->key_ != key_) return false;
        newValue_ = next->newValue_;
        setObsolete(newValue_ == oldValue_);
        return true;
    }

private:
    void set(const T& value) {
        T* target = locate_(project());
        assert(target && "the undo stack no longer matches the project");
        if (!target) return;
        *target = value;
        notify(event_);
    }

    std::string key_;
    Locate locate_;
    T oldValue_{};
    T newValue_;
    ChangeEvent event_;
    DragId drag_;
};

// One prep::CutEdit on one motion; consecutive moves of one cut in one drag merge.
class CutCommand : public DocumentCommand {
public:
    CutCommand(ProjectDocument* document, const QString& text, std::string motionId, prep::CutEdit edit, DragId drag);
    void redo() override;
    void undo() override;
    int id() const override;
    bool mergeWith(const QUndoCommand* other) override;

private:
    void apply(const prep::CutEdit& edit);
    std::string motionId_;
    prep::CutEdit edit_;
    DragId drag_;
};

// Appends motions. Paths are kept relative to the project file they were
// given for, and re-expressed if the project has moved since (Save As).
class ImportMotionsCommand : public DocumentCommand {
public:
    ImportMotionsCommand(ProjectDocument* document, std::vector<prep::ProjectMotion> motions);
    void redo() override;
    void undo() override;

private:
    std::vector<prep::ProjectMotion> motions_;
    std::filesystem::path givenFor_;
    int first_ = 0;
};

class RemoveMotionCommand : public DocumentCommand {
public:
    RemoveMotionCommand(ProjectDocument* document, int index);
    void redo() override;
    void undo() override;

private:
    prep::ProjectMotion motion_;
    std::filesystem::path givenFor_;
    int index_;
};

// A vocabulary edit: the words plus everything a rename or removal reaches
// (every action's annotations and proposals, the combination table).
class VocabularyCommand : public DocumentCommand {
public:
    VocabularyCommand(ProjectDocument* document, const QString& text, const prep::Project& after);
    void redo() override;
    void undo() override;

private:
    struct Words {
        std::vector<std::string> vocabulary;
        std::vector<std::vector<prep::ActionInfo>> actions;  // per motion, in project order
        prep::ComboTable combos;
    };
    static Words capture(const prep::Project& project);
    void restore(const Words& words);
    Words before_, after_;
};

// Replaces one of the project's later sections ("scene": the setups,
// "pattern_lists") with a new text, keeping the old one for undo, so undo
// gives back the very bytes (issue 23). `key` names the edited value (e.g.
// "setup/duel/start/red"): commands of the same key and the same non-zero
// drag merge, and a merge that lands back on the old text drops the step.
// Several events may be told (a rename is a removal and an addition to views
// that key on names).
class SectionCommand : public DocumentCommand {
public:
    SectionCommand(ProjectDocument* document, const QString& text, std::string section, std::optional<std::string> after,
                   std::string key, std::vector<ChangeEvent> events, DragId drag = 0);
    void redo() override;
    void undo() override;
    int id() const override { return drag_ != 0 ? kSectionCommand : -1; }
    bool mergeWith(const QUndoCommand* other) override;
    // The section before the first and after the last merged step (nullopt: absent).
    const std::optional<std::string>& before() const { return before_; }
    const std::optional<std::string>& after() const { return after_; }

private:
    void set(const std::optional<std::string>& value);
    std::string section_;
    std::optional<std::string> before_, after_;
    std::string key_;
    std::vector<ChangeEvent> events_;
    DragId drag_;
};

}  // namespace fray::authoring
