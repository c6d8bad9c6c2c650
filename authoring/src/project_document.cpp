#include "fray/authoring/project_document.h"

#include <QSignalBlocker>

#include <algorithm>
#include <cmath>
#include <functional>

#include "fray/authoring/commands.h"
#include "fray/core/atomic_file.h"
#include "fray/prep/project_edits.h"

namespace fray::authoring {
namespace {

namespace fs = std::filesystem;

std::string inQuotes(const std::string& s) { return "\"" + s + "\""; }
std::string where(const std::string& motionId, int action) {
    return "motion " + inQuotes(motionId) + ", action " + std::to_string(action);
}
QString q(const std::string& s) { return QString::fromStdString(s); }

}  // namespace

ProjectDocument::ProjectDocument(prep::Project project, fs::path file, QObject* parent)
    : QObject(parent), project_(std::move(project)), file_(std::move(file)) {
    connect(&undoStack_, &QUndoStack::cleanChanged, this, [this](bool clean) { Q_EMIT dirtyChanged(!clean); });
}

ProjectDocument::~ProjectDocument() {
    // Commands reach the project through this document: drop them first,
    // without telling listeners (clearing changes the clean state).
    const QSignalBlocker quiet(&undoStack_);
    undoStack_.clear();
}

Result<std::unique_ptr<ProjectDocument>> ProjectDocument::open(const fs::path& file) {
    auto text = readWholeFile(file, "the project file");
    if (!text) return text.error();
    auto project = prep::projectFromJson(*text, file.string());
    if (!project) return project.error();
    auto doc = std::make_unique<ProjectDocument>(std::move(*project), file);
    doc->onDisk_ = std::move(*text);
    return doc;
}

void ProjectDocument::rememberDiskState() {
    onDisk_.reset();
    if (file_.empty()) return;
    std::error_code ec;
    if (!fs::exists(file_, ec)) return;
    if (auto text = readWholeFile(file_, "the project")) onDisk_ = std::move(*text);
}

Status ProjectDocument::writeLocked(const fs::path& file, const std::string& bytes, bool checkUnchanged) {
    // Under the project's lock (the CLI's edits take it too), and only over
    // the file this document last read or wrote: an edit saved meanwhile by
    // another program is never overwritten silently.
    auto lock = FileLock::acquire(file, std::chrono::seconds(5));
    if (!lock) return lock.error();
    if (checkUnchanged && onDisk_) {
        std::error_code ec;
        if (fs::exists(file, ec)) {
            auto now = readWholeFile(file, "the project");
            if (!now) return now.error();
            if (*now != *onDisk_)
                return makeError(file.string() +
                                 ": changed on disk since it was opened here (another program saved it); nothing was "
                                 "written: Save As to keep both versions, or reopen the project to take the other one");
        }
    }
    if (auto st = writeFileAtomically(file, bytes); !st) return st;
    onDisk_ = bytes;
    return {};
}

std::string ProjectDocument::serialized() const { return prep::projectToJson(project_); }

void ProjectDocument::notify(const ChangeEvent& event) {
    ++revision_;
    Q_EMIT changed(event);
}

Status ProjectDocument::save() {
    if (file_.empty()) return makeError(project_.name + ": the project has no file yet (use Save As)");
    if (auto st = writeLocked(file_, serialized(), true); !st) return st;
    undoStack_.setClean();
    Q_EMIT saved(QString::fromStdString(file_.string()));
    return {};
}

Status ProjectDocument::saveAs(const fs::path& file) {
    if (file.empty()) return makeError("Save As: no file name given");
    // Write a copy whose relative motion paths resolve from the new folder,
    // and adopt it only once it is on disk.
    prep::Project moved = project_;
    bool pathsMoved = false;
    for (auto& m : moved.motions) {
        std::string p = prep::rebaseMotionPath(file_, file, m.path);
        pathsMoved = pathsMoved || p != m.path;
        m.path = std::move(p);
    }
    // Save As to the file itself is a Save; to another file, the user chose to replace it.
    if (auto st = writeLocked(file, prep::projectToJson(moved), file == file_); !st) return st;
    project_ = std::move(moved);
    const bool renamed = file != file_;
    file_ = file;
    if (pathsMoved) notify({ChangeKind::MotionPaths, {}, -1, 0});
    undoStack_.setClean();
    if (renamed) Q_EMIT fileChanged(QString::fromStdString(file_.string()));
    Q_EMIT saved(QString::fromStdString(file_.string()));
    return {};
}

void ProjectDocument::markDirty() { undoStack_.resetClean(); }

// ---- lookup -----------------------------------------------------------------

Result<prep::ProjectMotion*> ProjectDocument::motion(const std::string& motionId) {
    prep::ProjectMotion* m = project_.findMotion(motionId);
    if (!m) return makeError("the project has no motion " + inQuotes(motionId));
    return m;
}

Result<prep::ActionInfo*> ProjectDocument::action(const std::string& motionId, int action) {
    auto m = motion(motionId);
    if (!m) return m.error();
    const int count = (*m)->actions.actionCount();
    if (action < 0 || action >= count) {
        return makeError(where(motionId, action) + ": no such action (the motion has " + std::to_string(count) + ")");
    }
    return &(*m)->actions.actions[static_cast<std::size_t>(action)];
}

// ---- settings ---------------------------------------------------------------

Status ProjectDocument::setName(const std::string& name) {
    if (name == project_.name) return {};
    undoStack_.push(new ChangeValue<std::string>(
        this, QStringLiteral("Rename project"), "name", [](prep::Project& p) { return &p.name; }, name,
        {ChangeKind::Name, {}, -1, 0}));
    return {};
}

Status ProjectDocument::pushSettings(prep::ProjectSettings settings, const char* field, const QString& text,
                                     DragId drag) {
    if (auto why = prep::checkSettings(settings)) return makeError("settings: " + *why);
    if (settings == project_.settings) return {};
    undoStack_.push(new ChangeValue<prep::ProjectSettings>(
        this, text, std::string("settings/") + field, [](prep::Project& p) { return &p.settings; }, std::move(settings),
        {ChangeKind::Settings, {}, -1, 0}, drag));
    return {};
}

Status ProjectDocument::setGraphPreset(const std::string& preset) {
    prep::ProjectSettings s = project_.settings;
    s.graphPreset = preset;
    return pushSettings(std::move(s), "graph_preset", QStringLiteral("Set graph preset"), 0);
}

Status ProjectDocument::setGraphThreshold(std::optional<double> threshold, DragId drag) {
    prep::ProjectSettings s = project_.settings;
    s.graphThreshold = threshold;
    return pushSettings(std::move(s), "graph_threshold", QStringLiteral("Set graph threshold"), drag);
}

Status ProjectDocument::setSegmentThresholdFactor(std::optional<double> factor, DragId drag) {
    prep::ProjectSettings s = project_.settings;
    s.segmentThresholdFactor = factor;
    return pushSettings(std::move(s), "segment_threshold_factor", QStringLiteral("Set segmentation threshold"), drag);
}

// ---- motions ----------------------------------------------------------------

Status ProjectDocument::importMotions(std::vector<prep::ProjectMotion> motions) {
    if (motions.empty()) return makeError("import: no motions given");
    prep::Project check = project_;  // ids are unique against the project and each other
    for (auto& m : motions) {
        if (m.id.empty()) return makeError("import: a motion has no id");
        if (m.path.empty()) return makeError("import " + inQuotes(m.id) + ": no file path");
        if (auto why = m.actions.validate()) return makeError("import " + inQuotes(m.id) + ": " + *why);
        for (int a = 0; a < m.actions.actionCount(); ++a) {
            if (auto why = prep::checkActionInfo(project_, m.actions.actions[static_cast<std::size_t>(a)],
                                                 "import " + where(m.id, a))) {
                return makeError(*why);
            }
        }
        for (const auto& label : m.contactLabels) {
            if (auto why = prep::checkContactLabel(m, label)) return makeError("import: " + *why);
        }
        const std::string stem = m.id;
        for (int n = 2; check.findMotion(m.id); ++n) m.id = stem + "_" + std::to_string(n);
        check.motions.push_back(m);
    }
    undoStack_.push(new ImportMotionsCommand(this, std::move(motions)));
    return {};
}

Status ProjectDocument::removeMotion(const std::string& motionId) {
    auto m = motion(motionId);
    if (!m) return m.error();
    undoStack_.push(new RemoveMotionCommand(this, static_cast<int>(*m - project_.motions.data())));
    return {};
}

// ---- cuts -------------------------------------------------------------------

Status ProjectDocument::pushCutEdit(const std::string& motionId, Result<prep::CutEdit> edit, const QString& text,
                                    DragId drag) {
    if (!edit) return makeError("motion " + inQuotes(motionId) + ": " + edit.error().message);
    if (edit->kind == prep::CutEdit::Kind::Move && edit->frame == edit->toFrame) return {};
    undoStack_.push(new CutCommand(this, text, motionId, std::move(*edit), drag));
    return {};
}

Status ProjectDocument::addCut(const std::string& motionId, int frame) {
    auto m = motion(motionId);
    if (!m) return m.error();
    return pushCutEdit(motionId, prep::makeAddCut((*m)->actions, frame), QStringLiteral("Add cut"), 0);
}

Status ProjectDocument::removeCut(const std::string& motionId, int frame) {
    auto m = motion(motionId);
    if (!m) return m.error();
    return pushCutEdit(motionId, prep::makeRemoveCut((*m)->actions, frame), QStringLiteral("Remove cut"), 0);
}

Status ProjectDocument::moveCut(const std::string& motionId, int frame, int toFrame, DragId drag) {
    auto m = motion(motionId);
    if (!m) return m.error();
    if (frame == toFrame) return {};
    return pushCutEdit(motionId, prep::makeMoveCut((*m)->actions, frame, toFrame), QStringLiteral("Move cut"), drag);
}

Status ProjectDocument::splitAction(const std::string& motionId, int actionIndex, int frame) {
    auto a = action(motionId, actionIndex);
    if (!a) return a.error();
    const prep::MotionActions& doc = project_.findMotion(motionId)->actions;
    if (frame <= doc.firstFrame(actionIndex) || frame > doc.lastFrame(actionIndex)) {
        return makeError(where(motionId, actionIndex) + ": cannot split at frame " + std::to_string(frame) +
                         ": the action spans frames " + std::to_string(doc.firstFrame(actionIndex)) + ".." +
                         std::to_string(doc.lastFrame(actionIndex)) + " and a split needs a frame after its first");
    }
    return pushCutEdit(motionId, prep::makeAddCut(doc, frame), QStringLiteral("Split action"), 0);
}

Status ProjectDocument::mergeActions(const std::string& motionId, int actionIndex) {
    auto m = motion(motionId);
    if (!m) return m.error();
    return pushCutEdit(motionId, prep::makeMergeActions((*m)->actions, actionIndex), QStringLiteral("Merge actions"),
                       0);
}

Status ProjectDocument::setMotionActions(const std::string& motionId, prep::MotionActions actions, const QString& text) {
    auto m = motion(motionId);
    if (!m) return m.error();
    if (actions.frameCount != (*m)->actions.frameCount)
        return makeError("motion " + inQuotes(motionId) + ": the new actions cover " + std::to_string(actions.frameCount) +
                         " frames but the motion has " + std::to_string((*m)->actions.frameCount));
    if (auto why = actions.validate()) return makeError("motion " + inQuotes(motionId) + ": " + *why);
    for (int a = 0; a < actions.actionCount(); ++a)
        if (auto why = prep::checkActionInfo(project_, actions.actions[static_cast<std::size_t>(a)], where(motionId, a)))
            return makeError(*why);
    if (actions == (*m)->actions) return {};
    const std::string id = motionId;
    undoStack_.push(new ChangeValue<prep::MotionActions>(
        this, text, "motion/" + id + "/actions",
        [id](prep::Project& p) -> prep::MotionActions* {
            prep::ProjectMotion* pm = p.findMotion(id);
            return pm ? &pm->actions : nullptr;
        },
        std::move(actions), {ChangeKind::Cuts, id, 0, 0}, 0));
    return {};
}

// ---- action descriptions ----------------------------------------------------

Status ProjectDocument::pushActionInfo(const std::string& motionId, int actionIndex, prep::ActionInfo info,
                                       const char* field, const QString& text, DragId drag) {
    auto current = action(motionId, actionIndex);
    if (!current) return current.error();
    if (auto why = prep::checkActionInfo(project_, info, where(motionId, actionIndex))) return makeError(*why);
    if (info == **current) return {};
    const std::size_t index = static_cast<std::size_t>(actionIndex);
    undoStack_.push(new ChangeValue<prep::ActionInfo>(
        this, text, "action/" + motionId + "/" + std::to_string(actionIndex) + "/" + field,
        [motionId, index](prep::Project& p) -> prep::ActionInfo* {
            prep::ProjectMotion* m = p.findMotion(motionId);
            return m && index < m->actions.actions.size() ? &m->actions.actions[index] : nullptr;
        },
        std::move(info), {ChangeKind::Action, motionId, actionIndex, 0}, drag));
    return {};
}

Status ProjectDocument::editAction(const std::string& motionId, int actionIndex, const char* field,
                                   const QString& text, DragId drag,
                                   const std::function<Status(prep::ActionInfo&)>& change) {
    auto a = action(motionId, actionIndex);
    if (!a) return a.error();
    prep::ActionInfo info = **a;
    if (auto st = change(info); !st) return makeError(where(motionId, actionIndex) + ": " + st.error().message);
    return pushActionInfo(motionId, actionIndex, std::move(info), field, text, drag);
}

Status ProjectDocument::setActionInfo(const std::string& motionId, int actionIndex, prep::ActionInfo info,
                                      DragId drag) {
    return pushActionInfo(motionId, actionIndex, std::move(info), "info", QStringLiteral("Edit action"), drag);
}

Status ProjectDocument::setActionName(const std::string& motionId, int actionIndex, const std::string& name) {
    return editAction(motionId, actionIndex, "name", QStringLiteral("Name action"), 0, [&](prep::ActionInfo& info) {
        info.name = name;
        return Status();
    });
}

Status ProjectDocument::setAnnotations(const std::string& motionId, int actionIndex,
                                       std::vector<std::string> annotations) {
    return editAction(motionId, actionIndex, "annotations", QStringLiteral("Annotate action"), 0,
                      [&](prep::ActionInfo& info) {
                          info.annotations = std::move(annotations);
                          // A confirmed word is no longer a proposal.
                          std::erase_if(info.proposed, [&](const std::string& w) { return info.has(w); });
                          return Status();
                      });
}

Status ProjectDocument::addAnnotation(const std::string& motionId, int actionIndex, const std::string& word) {
    return editAction(motionId, actionIndex, "annotations", QStringLiteral("Annotate action"), 0,
                      [&](prep::ActionInfo& info) {
                          if (info.has(word)) return Status(makeError("already annotated " + inQuotes(word)));
                          info.annotations.push_back(word);
                          std::erase(info.proposed, word);
                          return Status();
                      });
}

Status ProjectDocument::removeAnnotation(const std::string& motionId, int actionIndex, const std::string& word) {
    return editAction(motionId, actionIndex, "annotations", QStringLiteral("Remove annotation"), 0,
                      [&](prep::ActionInfo& info) {
                          if (std::erase(info.annotations, word) == 0) {
                              return Status(makeError("not annotated " + inQuotes(word)));
                          }
                          return Status();
                      });
}

Status ProjectDocument::confirmProposal(const std::string& motionId, int actionIndex, const std::string& word) {
    return editAction(motionId, actionIndex, "confirm", QStringLiteral("Confirm %1").arg(q(word)), 0,
                      [&](prep::ActionInfo& info) {
                          if (std::erase(info.proposed, word) == 0) {
                              return Status(makeError(inQuotes(word) + " is not a proposal"));
                          }
                          if (!info.has(word)) info.annotations.push_back(word);
                          return Status();
                      });
}

Status ProjectDocument::rejectProposal(const std::string& motionId, int actionIndex, const std::string& word) {
    return editAction(motionId, actionIndex, "reject", QStringLiteral("Reject %1").arg(q(word)), 0,
                      [&](prep::ActionInfo& info) {
                          if (std::erase(info.proposed, word) == 0) {
                              return Status(makeError(inQuotes(word) + " is not a proposal"));
                          }
                          return Status();
                      });
}

Status ProjectDocument::setJoints(const std::string& motionId, int actionIndex, std::vector<std::string> joints) {
    return editAction(motionId, actionIndex, "joints", QStringLiteral("Set joints used"), 0,
                      [&](prep::ActionInfo& info) {
                          info.joints = std::move(joints);
                          return Status();
                      });
}

Status ProjectDocument::setAttackDirection(const std::string& motionId, int actionIndex,
                                           std::optional<std::string> direction) {
    if (direction && direction->empty()) direction.reset();
    return editAction(motionId, actionIndex, "attack_direction", QStringLiteral("Set attack direction"), 0,
                      [&](prep::ActionInfo& info) {
                          info.attackDirection = std::move(direction);
                          return Status();
                      });
}

Status ProjectDocument::setDefendedPart(const std::string& motionId, int actionIndex, std::optional<std::string> part) {
    if (part && part->empty()) part.reset();
    return editAction(motionId, actionIndex, "defended_part", QStringLiteral("Set defended part"), 0,
                      [&](prep::ActionInfo& info) {
                          info.defendedPart = std::move(part);
                          return Status();
                      });
}

Status ProjectDocument::setInitialConditions(const std::string& motionId, int actionIndex,
                                             std::optional<prep::InitialConditions> conditions, DragId drag) {
    return editAction(motionId, actionIndex, "initial_conditions", QStringLiteral("Set initial conditions"), drag,
                      [&](prep::ActionInfo& info) {
                          info.initialConditions = conditions;
                          return Status();
                      });
}

// ---- vocabulary -------------------------------------------------------------

Status ProjectDocument::pushVocabulary(const prep::Project& after, const QString& text) {
    undoStack_.push(new VocabularyCommand(this, text, after));
    return {};
}

Status ProjectDocument::addVocabularyWord(const std::string& word) {
    prep::Project after = project_;
    if (auto st = prep::addVocabularyWord(after, word); !st) return st;
    return pushVocabulary(after, QStringLiteral("Add word %1").arg(q(word)));
}

Status ProjectDocument::renameVocabularyWord(const std::string& from, const std::string& to) {
    if (from == to) return {};
    prep::Project after = project_;
    if (auto st = prep::renameVocabularyWord(after, from, to); !st) return st;
    return pushVocabulary(after, QStringLiteral("Rename word %1 to %2").arg(q(from), q(to)));
}

Status ProjectDocument::removeVocabularyWord(const std::string& word) {
    prep::Project after = project_;
    if (auto st = prep::removeVocabularyWord(after, word); !st) return st;
    return pushVocabulary(after, QStringLiteral("Remove word %1").arg(q(word)));
}

// ---- contact labels ---------------------------------------------------------

Status ProjectDocument::pushContactLabels(const std::string& motionId, std::vector<prep::ContactLabel> labels,
                                          const QString& text, const std::string& key, DragId drag) {
    auto m = motion(motionId);
    if (!m) return m.error();
    for (const auto& label : labels) {
        if (auto why = prep::checkContactLabel(**m, label)) return makeError(*why);
    }
    if (labels == (*m)->contactLabels) return {};
    undoStack_.push(new ChangeValue<std::vector<prep::ContactLabel>>(
        this, text, "labels/" + motionId + "/" + key,
        [motionId](prep::Project& p) -> std::vector<prep::ContactLabel>* {
            prep::ProjectMotion* pm = p.findMotion(motionId);
            return pm ? &pm->contactLabels : nullptr;
        },
        std::move(labels), {ChangeKind::ContactLabels, motionId, -1, 0}, drag));
    return {};
}

Status ProjectDocument::addContactLabel(const std::string& motionId, const prep::ContactLabel& label) {
    auto m = motion(motionId);
    if (!m) return m.error();
    auto labels = (*m)->contactLabels;
    labels.push_back(label);
    return pushContactLabels(motionId, std::move(labels), QStringLiteral("Add contact label"), "add", 0);
}

Result<std::vector<prep::ContactLabel>> ProjectDocument::contactLabels(const std::string& motionId, int index) {
    auto m = motion(motionId);
    if (!m) return m.error();
    const auto& labels = (*m)->contactLabels;
    if (index < 0 || index >= static_cast<int>(labels.size())) {
        return makeError("motion " + inQuotes(motionId) + ": no contact label " + std::to_string(index) + " (it has " +
                         std::to_string(labels.size()) + ")");
    }
    return labels;
}

Status ProjectDocument::changeContactLabel(const std::string& motionId, int index, const prep::ContactLabel& label,
                                           DragId drag) {
    auto labels = contactLabels(motionId, index);
    if (!labels) return labels.error();
    (*labels)[static_cast<std::size_t>(index)] = label;
    return pushContactLabels(motionId, std::move(*labels), QStringLiteral("Change contact label"),
                             "change/" + std::to_string(index), drag);
}

Status ProjectDocument::removeContactLabel(const std::string& motionId, int index) {
    auto labels = contactLabels(motionId, index);
    if (!labels) return labels.error();
    labels->erase(labels->begin() + index);
    return pushContactLabels(motionId, std::move(*labels), QStringLiteral("Remove contact label"), "remove", 0);
}

// ---- combination table ------------------------------------------------------

Status ProjectDocument::setComboRecord(const prep::ComboRecord& record, DragId drag) {
    for (const std::string& key : {record.mine, record.theirs}) {
        if (!prep::ComboTable::validKey(key)) {
            return makeError("combination table: " + inQuotes(key) + " is not an action name or @annotation");
        }
    }
    if (!std::isfinite(record.suitability)) {
        return makeError("combination table: (" + record.mine + ", " + record.theirs + "): suitability must be a number");
    }
    // Annotations from the vocabulary, action names of the project's actions.
    if (auto st = prep::ComboTable::checkRecord(record, project_.vocabulary); !st)
        return makeError("combination table: " + st.error().message);
    for (const std::string& key : {record.mine, record.theirs}) {
        if (key.front() == '@') continue;
        bool named = false;
        for (const auto& m : project_.motions)
            for (const auto& a : m.actions.actions) named = named || a.name == key;
        if (!named) return makeError("combination table: no action of the project is named " + inQuotes(key));
    }
    prep::ComboTable table = project_.combos;
    table.set(record);
    if (table == project_.combos) return {};
    undoStack_.push(new ChangeValue<prep::ComboTable>(
        this, QStringLiteral("Set combination %1 / %2").arg(q(record.mine), q(record.theirs)),
        "combos/" + record.mine + "/" + record.theirs, [](prep::Project& p) { return &p.combos; }, std::move(table),
        {ChangeKind::Combos, {}, -1, 0}, drag));
    return {};
}

Status ProjectDocument::removeComboRecord(const std::string& mine, const std::string& theirs) {
    prep::ComboTable table = project_.combos;
    if (!table.remove(mine, theirs)) {
        return makeError("combination table: no record (" + mine + ", " + theirs + ")");
    }
    undoStack_.push(new ChangeValue<prep::ComboTable>(
        this, QStringLiteral("Remove combination %1 / %2").arg(q(mine), q(theirs)), "combos/remove",
        [](prep::Project& p) { return &p.combos; }, std::move(table), {ChangeKind::Combos, {}, -1, 0}));
    return {};
}

}  // namespace fray::authoring
