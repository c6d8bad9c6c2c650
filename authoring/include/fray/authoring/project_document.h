#pragma once
// The open project as an editable document (issue 22, EDITOR.md): it owns the
// prep::Project and a QUndoStack, every mutation is an undo command, and one
// typed signal (changed) tells views what moved. Qt Core/Gui only.
//
// Each edit function checks its input against the project and either pushes
// exactly one command or returns an error naming the motion, action or field
// and changes nothing. Setting a value to what it already is pushes nothing.
// Edits given the same DragId (from beginDrag) merge into one undo step, so a
// dragged cut marker or slider undoes in one go; DragId 0 never merges.
#include <QObject>
#include <QString>
#include <QUndoStack>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fray/authoring/change_event.h"
#include "fray/core/result.h"
#include "fray/prep/project.h"
#include "fray/setup/hand_made.h"
#include "fray/setup/paint.h"
#include "fray/setup/scene_setup.h"
#include "fray/sim/patterns.h"

namespace fray::authoring {

using DragId = int;

class ProjectDocument : public QObject {
    Q_OBJECT

public:
    // `file` is where Save writes; empty for an untitled project (Save As first).
    explicit ProjectDocument(prep::Project project, std::filesystem::path file = {}, QObject* parent = nullptr);
    ~ProjectDocument() override;

    // Loads a project file; the error names the file and the bad field.
    static Result<std::unique_ptr<ProjectDocument>> open(const std::filesystem::path& file);

    const prep::Project& project() const { return project_; }
    // The bytes Save would write now.
    std::string serialized() const;
    const std::filesystem::path& filePath() const { return file_; }
    QUndoStack* undoStack() { return &undoStack_; }
    const QUndoStack* undoStack() const { return &undoStack_; }
    // Unsaved changes: follows QUndoStack::isClean.
    bool isDirty() const { return !undoStack_.isClean(); }
    // Grows with every change (undo and redo included); the autosaver compares it.
    std::uint64_t revision() const { return revision_; }

    // Atomic writes (temporary file, flush, rename). On failure the old file is
    // untouched and the document stays dirty. Save As into another folder
    // re-expresses relative motion paths from the new folder.
    Status save();
    Status saveAs(const std::filesystem::path& file);
    // After a crash recovery: the contents differ from the file on disk.
    void markDirty();
    // Reads the project file as it is now as the state Save may replace
    // (Save refuses to overwrite a file another program changed since).
    void rememberDiskState();

    DragId beginDrag() { return ++lastDrag_; }

    // ---- project and settings
    Status setName(const std::string& name);
    Status setGraphPreset(const std::string& preset);
    Status setGraphThreshold(std::optional<double> threshold, DragId drag = 0);
    Status setSegmentThresholdFactor(std::optional<double> factor, DragId drag = 0);

    // ---- motions. Imported entries need id (made unique with _2, _3...),
    // path and actions (at least MotionActions::whole(frameCount)).
    Status importMotions(std::vector<prep::ProjectMotion> motions);
    Status removeMotion(const std::string& motionId);

    // ---- cuts (SPEC 1.1): actions follow their cuts (prep::CutEdit semantics).
    Status addCut(const std::string& motionId, int frame);
    Status removeCut(const std::string& motionId, int frame);
    Status moveCut(const std::string& motionId, int frame, int toFrame, DragId drag = 0);
    // Split `action` at `frame`, which must lie inside it (not on its first frame).
    Status splitAction(const std::string& motionId, int action, int frame);
    // Merge `action` with the next one.
    Status mergeActions(const std::string& motionId, int action);
    // Replaces every cut and action description of a motion at once (an
    // automatic segmentation with its proposals): one undo step named `text`.
    // The frame count must stay the motion's; every description is checked.
    Status setMotionActions(const std::string& motionId, prep::MotionActions actions, const QString& text);

    // ---- action descriptions (SPEC 1.4)
    Status setActionInfo(const std::string& motionId, int action, prep::ActionInfo info, DragId drag = 0);
    Status setActionName(const std::string& motionId, int action, const std::string& name);
    Status setAnnotations(const std::string& motionId, int action, std::vector<std::string> annotations);
    Status addAnnotation(const std::string& motionId, int action, const std::string& word);
    Status removeAnnotation(const std::string& motionId, int action, const std::string& word);
    Status confirmProposal(const std::string& motionId, int action, const std::string& word);
    Status rejectProposal(const std::string& motionId, int action, const std::string& word);
    Status setJoints(const std::string& motionId, int action, std::vector<std::string> joints);
    Status setAttackDirection(const std::string& motionId, int action, std::optional<std::string> direction);
    Status setDefendedPart(const std::string& motionId, int action, std::optional<std::string> part);
    Status setInitialConditions(const std::string& motionId, int action,
                                std::optional<prep::InitialConditions> conditions, DragId drag = 0);

    // ---- vocabulary (renames and removals reach actions and combination keys)
    Status addVocabularyWord(const std::string& word);
    Status renameVocabularyWord(const std::string& from, const std::string& to);
    Status removeVocabularyWord(const std::string& word);

    // ---- foot-contact labels (SVM training data, SPEC 1.3)
    Status addContactLabel(const std::string& motionId, const prep::ContactLabel& label);
    Status changeContactLabel(const std::string& motionId, int index, const prep::ContactLabel& label,
                              DragId drag = 0);
    Status removeContactLabel(const std::string& motionId, int index);

    // ---- combination table (SPEC 1.6)
    Status setComboRecord(const prep::ComboRecord& record, DragId drag = 0);
    Status removeComboRecord(const std::string& mine, const std::string& theirs);

    // ---- scene setups (issue 23; the model is fray/setup/scene_setup.h, stored
    // in the project's "scene" section). Errors name the setup, the character
    // or the index and change nothing; drags (DragId) merge into one step.
    // The setups as stored now (an error when the section is damaged: it
    // names the file and the JSON path).
    Result<std::vector<setup::SceneSetup>> setups() const;
    Result<setup::SceneSetup> sceneSetup(const std::string& name) const;
    Status addSetup(setup::SceneSetup setup);                       // appended; the name must be new
    Status addSetup(const std::string& name, setup::SetupKind kind);  // setup::makeSetup (duel: defaultDuelActionSet)
    Status removeSetup(const std::string& name);
    Status renameSetup(const std::string& from, const std::string& to);
    Status duplicateSetup(const std::string& name, const std::string& copyName);
    // A setup made from a --spec file (and the PNG its domino floor names,
    // beside the spec), as `fray-cli setup P import` makes it. Errors name the
    // file and the JSON path, or the bitmap that is not a two-colour image.
    Status importSetupFromSpec(const std::string& name, const std::filesystem::path& specFile);
    // Any parameter by JSON pointer into the --spec form ("/duration",
    // "/characters/1/preset", "/characters/0/weights/r_d"); `json` is the
    // value as JSON text, "null" removes it. setup::setParameter's rules; duel, chase: setup::checkPlanSetup.
    Status setSetupParameter(const std::string& setup, const std::string& pointer, const std::string& json, DragId drag = 0);
    // A whole setup replaced at once (an import, a reset to defaults): one step named `text`.
    Status replaceSetup(const std::string& name, setup::SceneSetup setup, const QString& text);
    // Placements.
    Status setCharacterStart(const std::string& setup, const std::string& character, const setup::Placement& start,
                             DragId drag = 0);
    // Moves every character of `side` by (dx, dz) from where they are now (a drag passes each move's delta).
    Status moveTeam(const std::string& setup, int side, double dx, double dz, DragId drag = 0);
    Status setDominoStarts(const std::string& setup, std::vector<setup::DominoStartPoint> starts, DragId drag = 0);
    // Paths of compose kinds.
    Status setRatPath(const std::string& setup, std::vector<setup::Point> path, DragId drag = 0);
    Status setRunDirections(const std::string& setup, std::vector<setup::RunDirection> directions, DragId drag = 0);
    Status setTimedCommands(const std::string& setup, std::vector<setup::TimedCommand> commands);
    // Trajectories (duel and chase; one per character).
    Status addTrajectory(const std::string& setup, setup::Trajectory trajectory);
    Status removeTrajectory(const std::string& setup, const std::string& character);
    Status addTrajectoryPoint(const std::string& setup, const std::string& character, int index, setup::Point point);
    Status removeTrajectoryPoint(const std::string& setup, const std::string& character, int index);
    Status moveTrajectoryPoint(const std::string& setup, const std::string& character, int index, setup::Point point,
                               DragId drag = 0);
    // Checkpoints stay in the order they are passed along the trajectory: an
    // added one goes where it lies along it; returns its index.
    Result<int> addCheckpoint(const std::string& setup, const std::string& character, setup::SetupCheckpoint checkpoint);
    Status removeCheckpoint(const std::string& setup, const std::string& character, int index);
    Status moveCheckpoint(const std::string& setup, const std::string& character, int index, setup::Point point,
                          DragId drag = 0);
    Status setCheckpointTime(const std::string& setup, const std::string& character, int index, std::optional<double> time,
                             DragId drag = 0);
    // "" clears it; otherwise "@annotation" (a word of the vocabulary) or an action name of the project.
    Status setCheckpointAction(const std::string& setup, const std::string& character, int index, const std::string& action);
    // The floor bitmap: one stroke is one undo step holding the pixels it
    // changed (strokes passed the same drag merge); undo restores the bitmap
    // bit for bit. A stroke's start time also adds a domino chain start.
    Result<std::vector<setup::PixelChange>> paintFloor(const std::string& setup, const setup::FloorStroke& stroke,
                                                       DragId drag = 0);
    // A floor bitmap read from an image file (dark pixels painted); a file
    // that is not a two-colour image is refused, naming the file.
    Status importFloorImage(const std::string& setup, const std::filesystem::path& file, double metresPerPixel,
                            setup::Point origin);
    Status setFloor(const std::string& setup, std::optional<setup::FloorPaint> floor, const QString& text);
    // The painted floor's scale (metres per pixel, setup::setFloorScale),
    // checked as compose reads it: one undo step.
    Status setFloorScale(const std::string& setup, double metresPerPixel, DragId drag = 0);
    // Pins of edited generated interactions.
    Status addPin(const std::string& setup, const setup::Pin& pin);
    Status removePin(const std::string& setup, int index);
    // One undo step: the pin of `pin.character` at `pin.time` plays
    // `pin.action` from now on (added when there is none at that time);
    // "Replace with ..." of the Gantt track.
    Status setPin(const std::string& setup, const setup::Pin& pin);
    // Patch verdicts (indices of the project's patch library).
    enum class Verdict { None, Keep, Reject };
    Status setPatchVerdict(const std::string& setup, int patch, Verdict verdict);
    // Hand-made patches (fray/setup/hand_made.h), stored as recipes in the
    // project's "hand_made_patches" section. Adding one appends its recipe
    // and, when `setup` is given, marks the patch it becomes (index `patch`
    // of the library the caller built it into) kept there: one undo step.
    // The caller has played the recipe through the patch engine first.
    Result<std::vector<setup::HandMadePatch>> handMadePatches() const;
    Status addHandMadePatch(setup::HandMadePatch recipe, const std::string& setup, int patch);
    Status removeHandMadePatch(int index);

    // ---- PatternLists (SPEC 4.1; the project's "pattern_lists" section)
    Result<sim::PatternSet> patternSet() const;
    Status addPattern(sim::PatternList pattern);
    Status removePattern(const std::string& name);
    Status renamePattern(const std::string& from, const std::string& to);
    // Rows: (character 0|1, annotation). The annotation must be carried by
    // an action of the project (or be a group: attack, defence, fall, any).
    Status addPatternRow(const std::string& pattern, int index, sim::PatternEntry row);
    Status removePatternRow(const std::string& pattern, int index);
    Status movePatternRow(const std::string& pattern, int from, int to);
    Status setPatternRow(const std::string& pattern, int index, sim::PatternEntry row);
    Status setPatternWeights(const std::string& pattern, sim::PatternWeights weights, DragId drag = 0);
    Status setPatternThreshold(const std::string& pattern, double threshold, DragId drag = 0);
    // The initial-condition ranges of an annotation (nullopt: back to the default).
    Status setInitialRange(const std::string& annotation, std::optional<sim::InitialRange> range, DragId drag = 0);

Q_SIGNALS:
    void changed(const fray::authoring::ChangeEvent& event);
    void dirtyChanged(bool dirty);
    void fileChanged(const QString& file);
    // A successful Save or Save As wrote this file.
    void saved(const QString& file);

private:
    friend class DocumentCommand;
    void notify(const ChangeEvent& event);
    Result<prep::ProjectMotion*> motion(const std::string& motionId);
    Result<prep::ActionInfo*> action(const std::string& motionId, int action);
    // Copies the action's description, lets `change` edit it (or refuse), pushes the result.
    Status editAction(const std::string& motionId, int action, const char* field, const QString& text, DragId drag,
                      const std::function<Status(prep::ActionInfo&)>& change);
    Result<std::vector<prep::ContactLabel>> contactLabels(const std::string& motionId, int index);
    Status pushActionInfo(const std::string& motionId, int action, prep::ActionInfo info, const char* field,
                          const QString& text, DragId drag);
    Status pushSettings(prep::ProjectSettings settings, const char* field, const QString& text, DragId drag);
    Status pushContactLabels(const std::string& motionId, std::vector<prep::ContactLabel> labels, const QString& text,
                             const std::string& key, DragId drag);
    Status pushCutEdit(const std::string& motionId, Result<prep::CutEdit> edit, const QString& text, DragId drag);
    Status pushVocabulary(const prep::Project& after, const QString& text);

    using SetupChange = std::function<Status(std::vector<setup::SceneSetup>&, std::vector<ChangeEvent>&)>;
    // Reads the setups, lets `change` edit them (or refuse; it may fill in the
    // events), checks what changed and pushes one SectionCommand when anything did.
    Status editSetups(const QString& text, const std::string& key, DragId drag, std::vector<ChangeEvent> events,
                      const SetupChange& change);
    Status editSetup(const std::string& name, const QString& text, const std::string& key, DragId drag, ChangeEvent event,
                     const std::function<Status(setup::SceneSetup&)>& change);
    Status editTrajectory(const std::string& name, const std::string& character, const QString& text, const std::string& key,
                          DragId drag, const std::function<Status(setup::Trajectory&)>& change);
    Status editPatterns(const QString& text, const std::string& key, DragId drag, const std::string& pattern,
                        const std::function<Status(sim::PatternSet&)>& change);
    Status checkPatternAnnotation(const std::string& annotation, const std::string& where) const;
    // A setup parameter edit read as simulate (duel, chase) or compose (the
    // patch kinds) reads it: refused when it brings a problem `was` did not
    // have (the message names the setup and the field).
    Status checkSetupEdit(const setup::SceneSetup& was, const setup::SceneSetup& now) const;

    Status writeLocked(const std::filesystem::path& file, const std::string& bytes, bool checkUnchanged);

    prep::Project project_;
    std::filesystem::path file_;
    std::optional<std::string> onDisk_;  // the file's bytes as this document last read or wrote them
    QUndoStack undoStack_;
    std::uint64_t revision_ = 0;
    DragId lastDrag_ = 0;
};

}  // namespace fray::authoring
