#pragma once
// The editor's main window. The Vulkan viewport with play / pause / scrub /
// speed controls is the central widget; dockable panels sit around it and
// their layout is kept between runs:
//  - Library: a project's motions and their actions (filter by annotation or
//    name), or the motion files opened, or a scene's characters.
//  - Timeline: the selected motion's acceleration profile, high-acceleration
//    bands, cuts, actions and foot contacts (thesis fig. 3.1), its playhead
//    synced with the viewport.
//  - Inspector: the selected action's name, annotations, proposals, joints,
//    direction, defended part and initial-condition ranges.
//  - Motion graph: nodes and edges, statistics; a node lists its actions.
//  - Combination table: sortable and filterable.
// A project's analysis (signals, contacts, segmentation profiles, the motion
// graph) runs in a worker thread with a progress bar and Cancel in the status
// bar; the window keeps drawing meanwhile.
#include <QMainWindow>
#include <QString>
#include <QTimer>
#include <atomic>
#include <cstdint>
#include <functional>
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include "fray/render/motion_stage.h"
#include "fray/pipeline/graph_setup.h"
#include "fray/setup/hand_made.h"
#include "fray/setup/scene_setup.h"
#include "fray/sim/patches.h"
#include "fray/sim/planner.h"
#include "floor_tools.h"
#include "project_analysis.h"
#include "scene_stage.h"
#include "takes.h"

class QDialog;
class QDockWidget;
class QMenu;
class QSettings;
class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QFormLayout;
class QGroupBox;
class QLabel;
class QLineEdit;
class QListWidget;
class QProgressBar;
class QPushButton;
class QSlider;
class QSortFilterProxyModel;
class QStandardItemModel;
class QTableView;
class QThread;
class QToolBar;
class QToolButton;
class QTreeWidget;
class QTreeWidgetItem;
class QUndoGroup;

namespace fray::authoring {
class Autosaver;
class ProjectDocument;
class RecentFiles;
struct ChangeEvent;
}  // namespace fray::authoring

namespace fray::editor {

// Item data of the library and graph lists: motion index and action index.
inline constexpr int kRoleMotion = Qt::UserRole + 1;
inline constexpr int kRoleAction = Qt::UserRole + 2;

class GanttView;
class PatchBrowser;
class PatternsPanel;
class InspectorPanel;
class Viewport;
struct PreparedPreview;
class GraphView;
class TimelineView;

struct EditorOptions {
    int quitAfter = 0;              // frames; 0: run until closed
    QString screenshot;             // the whole window, written before quitting
    QString viewportScreenshot;     // the viewport alone (the renderer's image)
    bool waitForAnalysis = false;   // with quitAfter: quit only once the project analysis has finished
    bool restoreLayout = true;      // restore the dock layout saved by the last run
    // An autosave newer than the project (a crash): ask, or recover / discard
    // without asking (tests, scripts).
    enum class Recovery { Ask, Recover, Discard } recovery = Recovery::Ask;
    int autosaveSeconds = -1;       // -1: the setting (default 2 minutes); 0: off
    bool noDialogs = false;         // errors go to the status bar and stderr only (tests)
    QString generateSpec;           // a scene spec generated once the window is up (--generate)
};

class MainWindow : public QMainWindow, public FloorToolHost {
    Q_OBJECT
public:
    // Plays `scene` when given, else the takes; `projectFile` (may be empty)
    // is the project the takes come from: its panels fill in once analysed.
    // `viewport` may be null (--describe-ui): a placeholder takes its place.
    MainWindow(Viewport* viewport, std::vector<app::LoadedTake> takes, std::unique_ptr<cli::SceneStage> scene,
               QString projectFile, QString title, EditorOptions options);
    ~MainWindow() override;

    // Exit code for main(): 0, or 1 after an error (already reported).
    int exitCode() const { return exitCode_; }
    // The docks, menus and actions as JSON (fray --describe-ui).
    QByteArray describeUi() const;
    // The analysis shown in the panels, once finished.
    const ProjectAnalysis* analysis() const { return analysis_ ? &*analysis_ : nullptr; }
    // The open project's document (null when playing files or a scene).
    authoring::ProjectDocument* document() const { return doc_.get(); }
    authoring::Autosaver* autosaver() const { return autosaver_; }
    // The project shown: the document's, else none.
    const prep::Project* project() const;
    // Opens a project, motion files or nothing; false (with a message) on error.
    bool openPath(const QString& path);
    // Imports motion files into the open project (one undo step).
    void importMotionFiles(const QStringList& files);
    // The last error shown to the user (dialog or status bar).
    const QString& lastError() const { return lastError_; }

    // ---- Generate and preview (window_scene.cpp)
    // The scene specs offered by the Scene panel (the demo specs, files opened).
    QStringList sceneSources() const;
    // Selects a spec file (adding it to the list when new); false when unreadable.
    bool selectSceneSource(const QString& specFile);
    // Selects one of the project's scene setups; false when there is none of that name.
    bool selectSetup(const QString& name);
    // The setup selected in the Scene panel ("" when a spec file is).
    QString currentSetup() const;
    // Imports the selected spec file as a new setup of the project (one undo step) and selects it.
    bool importSpecAsSetup(const QString& name);
    // A new setup of `kind` with its demo parameters (one undo step), selected
    // (window_graph_setup.cpp); the Scene panel's kind chooser and New setup.
    bool newSetup(const QString& name, setup::SetupKind kind);
    // "graph-duel", "graph-duel 2", ...: the first name of a kind not in use.
    QString newSetupName(setup::SetupKind kind) const;
    // The patch library generated in the PatternList panel (null: none yet).
    const sim::PatchLibrary* patchLibrary() const { return patchLibrary_.get(); }
    // The current setup's rejected patches.
    std::vector<int> rejectedPatches() const;
    // A hand-made patch (fray/setup/hand_made.h): played by the patch engine
    // (errors shown, the project unchanged), then stored in the project with
    // the patch kept in the current setup, one undo step. Needs generated patches.
    bool addHandMadePatch(const setup::HandMadePatch& recipe);
    // Plays a recipe through the engine without storing it (the dialog's Evaluate).
    Result<sim::Patch> evaluateHandMadePatch(const setup::HandMadePatch& recipe) const;
    // The Hand-made patch dialog (non-modal; null until first shown).
    void showHandMadeDialog();
    QDialog* handMadeDialog() const { return handMade_; }
    // The action library the patches were generated from (null: none yet).
    const sim::ActionLibrary* patchActions() const;
    // Plans or composes the selected spec in the background; the result plays.
    void generate();
    // The scene playing (null: none); whether it is a generated preview.
    const cli::SceneStage* scene() const { return scene_.get(); }
    bool busy() const { return jobThread_ != nullptr; }
    // Whether a live re-plan is waiting for its debounce or running.
    bool replanPending() const;
    static constexpr int kReplanDebounceMs = 250;
    // After the last live re-plan: the characters the edits could not affect
    // (fray::setup::affectedCharacters) and how many of them kept their tracks
    // byte for byte; -1 when not measured (an edit that affects everyone).
    int replanOthers() const { return replanOthers_; }
    int replanKept() const { return replanKept_; }
    // How the last generate of a duel or chase went with the planner's cache
    // (sim::PlanCache): decisions kept from the scene before and planned
    // again, where it resumed; empty for other kinds.
    const std::optional<sim::ReplanInfo>& lastReplan() const { return lastReplan_; }
    double playTime() const { return time_; }
    // Pauses the scene playing at t (s) and poses it there, as the viewport draws it
    // (scene()->jointPositions then reads that pose); the Gantt panel's seek.
    void seek(double t);
    int selectedCharacter() const { return selected_; }
    // Ends a generated preview: the viewport plays the library's motions again.
    void stopPreview();
    // ---- Posture mode (window_posture.cpp, docs/EDITOR.md): a view setting, not
    // a document edit (no undo command). Physics solves the scene playing with
    // the posture solver (docs/POSTURE.md) in the background (progress and
    // Cancel), then plays its poses; a scene generated while it is on is
    // solved again. Kinematic is immediate (the scene poser's poses).
    void setPostureMode(posture::Mode mode);
    posture::Mode postureMode() const { return postureMode_; }
    // Whether the scene playing shows the chosen mode's poses (false while solving).
    bool postureShown() const { return scene_ && scene_->postureMode() == postureMode_; }
    // ---- Edit a generated interaction (window_pins.cpp, docs/EDITOR.md)
    // The menu of a Gantt bar of the scene playing (the caller owns it):
    // "Replace with" the actions that fit there, "Pin", "Unpin". Items that
    // do not apply are disabled and say why.
    QMenu* ganttBarMenu(int row, int bar);
    // The action names that fit in place of a bar: those sharing an
    // annotation with it, and those the motion graph allows after the bar
    // before it, within the character's actions; empty with `why` when the
    // bar cannot be edited (a reaction, the start action, a compose scene).
    QStringList actionsFittingBar(int row, int bar, QString* why = nullptr) const;
    // Each one undo command on the setup of the scene playing (the live
    // re-plan follows): replace the bar's action by `action` and pin it,
    // pin the bar's action, remove the pin that chose the bar.
    bool replaceGanttBar(int row, int bar, const QString& action);
    bool pinGanttBar(int row, int bar);
    bool unpinGanttBar(int row, int bar);
    // ---- Floor tools (window_tools.cpp)
    // Activates a floor tool by name ("Brush", "Eraser", "Fill", "Text",
    // "Polyline", "Arc", "Circle", "Move"; "" : none, the mouse moves the camera).
    bool selectTool(const QString& name);
    FloorTool* tool(const QString& name) const;
    Viewport* viewport() const { return viewport_; }
    // The setup character trajectories are drawn for.
    bool selectToolCharacter(const QString& name);
    // Imports a PNG as the current setup's floor bitmap (one undo step); false with a message on bad input.
    bool importFloorPng(const QString& file);
    // FloorToolHost.
    authoring::ProjectDocument* toolDocument() override { return doc_.get(); }
    std::string toolSetup() override { return currentSetup().toStdString(); }
    std::string toolCharacter() override;
    void toolMessage(const QString& message, bool error) override;
    QWidget* toolDialogParent() override { return this; }
    void toolCheckpointSelected(const std::string& character, int index) override;
    // The checkpoint the Scene panel's checkpoint inspector edits (index -1: none).
    bool selectCheckpoint(const QString& character, int index);
    QString checkpointCharacter() const { return QString::fromStdString(cpCharacter_); }
    int checkpointIndex() const { return cpIndex_; }
    // Writes the scene playing in the background (the Export dialog's work):
    // optionally onto the user's rig (`rig`, retargeted as `fray-cli export
    // --rig`), with a root bone (`rootMotion` none|floor|in-place), and with
    // the posture solver's poses (`physics`, as `--posture physics`).
    struct ExportExtras {
        QString rig;
        QString rootMotion = "none";
        bool physics = false;
    };
    void exportScene(const QString& format, double fps, const QString& dir, const QString& name, const ExportExtras& extras);
    void exportScene(const QString& format, double fps, const QString& dir, const QString& name) {
        exportScene(format, fps, dir, name, ExportExtras{});
    }

protected:
    void closeEvent(QCloseEvent* event) override;
    void dragEnterEvent(QDragEnterEvent* event) override;
    void dropEvent(QDropEvent* event) override;
    bool event(QEvent* event) override;

private Q_SLOTS:
    void tick();
    void librarySelectionChanged();
    void togglePlay();
    void scrubbed(int frame);
    void timelinePlayhead(int frame);
    void graphNodeSelected(int node);
    void analysisProgress(double fraction, const QString& stage);
    void analysisFinished();
    void documentChanged(const fray::authoring::ChangeEvent& event);
    void editFailed(const QString& message);

private:
    void buildDocks();
    void buildMenus();
    void fillLibrary();
    void filterLibrary(const QString& text);
    void showMotion(int motion);
    void showAction(int motion, int action);
    void fillCombos();
    void startAnalysis();
    void cancelAnalysis();
    void openFile();
    void newProject();
    bool save();
    bool saveAs();
    // Asks to save unsaved changes: false when the user cancelled.
    bool maybeSave();
    void importMotionsDialog();
    void showError(const QString& title, const QString& message);
    // Automatic segmentation of the selected motion with proposals, in a
    // worker thread; the result is one undo command.
    void segmentCurrentMotion();
    void segmentFinished();
    bool openDocument(const QString& file);
    void updateTitle();
    void undoGroupChanged();
    void fillRecentMenu();
    void refreshAll();
    void refreshTimeline();
    void addComboRecord();
    void removeComboRecords();
    void importCombos();
    void exportCombos();
    QStringList jointNames(int motion) const;
    int motionIndex(const std::string& id) const;
    void resetLayout();
    void showShortcuts();
    void frameAll();
    void showTime();
    // Scrub steps per second of a scene.
    static constexpr int kSceneSteps = 30;
    void finish();
    void fail(const QString& message);

    // Background jobs other than the analysis (generate, export, patches):
    // one at a time, with the status bar's progress and Cancel. `work` runs on
    // a worker thread; `done` on the UI thread after it.
    bool startJob(const QString& what, std::function<void(const ProgressFn&)> work, std::function<void()> done);
    void jobFinished();
    void updateBusy();
    void buildSceneDocks();
    void buildSceneMenu();
    void showGenerated(PreparedPreview generated);
    void ganttBarClicked(int row, int bar);
    void exportDialog();
    void buildPatchDocks();
    void fillPatterns();
    void fillSceneSources();
    void generatePatches(const QStringList& names);
    void previewPatch(int patch);
    void setPatchesRejected(const std::vector<int>& patches, bool reject);
    void reportStatus(const Status& s);
    void buildFloorTools();
    void refreshSetupOverlay();
    void fillToolCharacters();
    // A setup's parameters, placements, trajectories or floor changed: the
    // overlays follow, and the live re-plan starts its debounce.
    void setupEdited(const authoring::ChangeEvent& event);
    Viewport* viewport_;
    QWidget* viewportContainer_;
    std::vector<app::LoadedTake> takes_;
    std::vector<app::LoadedTake> shown_;
    render::MotionStage stage_;
    std::unique_ptr<cli::SceneStage> scene_;
    QString projectFile_;
    int selected_ = -1;  // scene character, -1: none
    int currentMotion_ = -1, currentAction_ = -1;
    EditorOptions options_;

    // Docks and panels.
    QDockWidget* libraryDock_ = nullptr;
    QDockWidget* timelineDock_ = nullptr;
    QDockWidget* inspectorDock_ = nullptr;
    QDockWidget* graphDock_ = nullptr;
    QDockWidget* combosDock_ = nullptr;
    QLineEdit* libraryFilter_ = nullptr;
    QTreeWidget* library_ = nullptr;
    TimelineView* timeline_ = nullptr;
    InspectorPanel* inspector_ = nullptr;
    QDockWidget* historyDock_ = nullptr;
    QMenu* recentMenu_ = nullptr;
    QAction* saveAction_ = nullptr;
    QAction* saveAsAction_ = nullptr;
    QAction* importAction_ = nullptr;
    QAction* analyseAction_ = nullptr;
    std::unique_ptr<QSettings> settings_;
    std::unique_ptr<authoring::ProjectDocument> doc_;
    authoring::Autosaver* autosaver_ = nullptr;
    authoring::RecentFiles* recent_ = nullptr;
    int cutDrag_ = 0;                 // the DragId of the cut being dragged
    int draggedCutAt_ = 0;            // where that cut is now
    QUndoGroup* undoGroup_ = nullptr;
    std::uint64_t analysisRevision_ = 0;  // the document revision the analysis saw
    bool graphStale_ = false;
    bool fillingCombos_ = false;
    bool fillingGraphControls_ = false;
    QString lastError_;
    GraphView* graph_ = nullptr;
    QListWidget* nodeActions_ = nullptr;
    QTableView* combos_ = nullptr;
    QStandardItemModel* combosModel_ = nullptr;
    QSortFilterProxyModel* combosProxy_ = nullptr;
    QLineEdit* combosFilter_ = nullptr;
    QByteArray defaultLayout_;

    // The background analysis.
    QThread* analysisThread_ = nullptr;
    std::atomic<bool> cancelRequested_{false};
    std::atomic<double> lastPosted_{-1.0};
    std::optional<Result<ProjectAnalysis>> analysisResult_;  // written by the worker, read after it finished
    std::optional<ProjectAnalysis> analysis_;
    QThread* segmentThread_ = nullptr;
    std::string segmentMotion_;
    std::optional<Result<prep::MotionActions>> segmentResult_;
    QAction* segmentAction_ = nullptr;
    QComboBox* graphPreset_ = nullptr;
    QDoubleSpinBox* graphThreshold_ = nullptr;
    QProgressBar* progress_ = nullptr;
    QPushButton* cancelButton_ = nullptr;

    // Generate and preview.
    QThread* jobThread_ = nullptr;
    QString jobName_;
    std::function<void()> jobDone_;
    std::atomic<bool> jobCancel_{false};
    bool sceneIsPreview_ = false;     // scene_ was generated here (the library still lists motions)
    QDockWidget* sceneDock_ = nullptr;
    QDockWidget* ganttDock_ = nullptr;
    QDockWidget* metricsDock_ = nullptr;
    QComboBox* sceneSource_ = nullptr;
    QPushButton* generateButton_ = nullptr;
    QLabel* sceneInfo_ = nullptr;
    GanttView* gantt_ = nullptr;
    QLabel* metricsSummary_ = nullptr;
    QTableView* metrics_ = nullptr;
    QStandardItemModel* metricsModel_ = nullptr;
    QAction* generateAction_ = nullptr;
    QAction* exportAction_ = nullptr;
    QAction* stopPreviewAction_ = nullptr;
    QDockWidget* patternsDock_ = nullptr;
    QDockWidget* patchesDock_ = nullptr;
    PatternsPanel* patterns_ = nullptr;
    PatchBrowser* patchBrowser_ = nullptr;
    std::shared_ptr<const sim::PatchLibrary> patchLibrary_;      // generated here and the hand-made ones, also written to PROJECT.patches
    std::shared_ptr<const sim::PatchLibrary> patchGenerated_;    // the generated part alone
    std::string handMadeApplied_;                                // the hand-made section patchLibrary_ was built with
    void rebuildPatchLibrary();
    QDialog* handMade_ = nullptr;
    std::shared_ptr<const pipeline::SimSession> patchSession_;   // the action library it was made from
    int previewedPatch_ = -1;
    std::shared_ptr<pipeline::SimSession> generateSession_;  // the last generate's session (read by the next job only)
    std::shared_ptr<sim::PlanCache> planCache_;  // the last tree-expansion run (used by one job at a time)
    std::optional<sim::ReplanInfo> lastReplan_;
    QToolBar* toolBar_ = nullptr;
    QToolBar* toolOptions_ = nullptr;
    QComboBox* toolCharacter_ = nullptr;
    std::vector<FloorTool*> tools_;    // children of the window
    // The current setup drawn on the floor: its bitmap, trajectories, checkpoints and starts.
    std::vector<std::uint8_t> overlayPixels_;
    render::FloorBitmap overlayFloor_;
    std::vector<std::vector<glm::vec3>> overlayLinePoints_;
    std::vector<render::Polyline> overlayLines_;
    std::vector<render::Checkpoint> overlayMarks_;
    std::vector<std::string> overlayLabels_;  // the marks' labels (the marks hold views of them)
    // The checkpoint inspector (Scene panel) and the checkpoint it edits.
    QWidget* makeCheckpointInspector();
    void refreshCheckpointInspector();
    // The Scene panel's Setup box: kind chooser, New setup, the Interaction
    // Graph kinds' parameters (window_graph_setup.cpp).
    QWidget* makeSetupParameters();
    void refreshSetupParameters();
    void setGraphParameter(const std::string& key, const std::string& json);
    QComboBox* newKind_ = nullptr;
    QFormLayout* paramsForm_ = nullptr;
    std::vector<QWidget*> paramWidgets_;
    QLabel* paramsInfo_ = nullptr;
    bool fillingParams_ = false;
    // A duel's or chase's characters in the Setup box: preset, a weight,
    // takes and actions of the character picked (window_plan_setup.cpp).
    void makePlanCharacterRows();
    void refreshPlanCharacterRows(const setup::SceneSetup* s);
    void setPlanWeight();
    void setPlanList(QListWidget* list, const char* field);
    QComboBox* planCharacter_ = nullptr;
    QComboBox* planPreset_ = nullptr;
    QComboBox* planWeightKey_ = nullptr;
    QLineEdit* planWeight_ = nullptr;
    QLabel* planWeightFrom_ = nullptr;
    QListWidget* planMotions_ = nullptr;
    QListWidget* planActions_ = nullptr;
    QListWidget* planReactions_ = nullptr;
    std::vector<QWidget*> planRows_;
    // A domino setup's painted floor scale (metres per pixel; ProjectDocument::setFloorScale).
    QDoubleSpinBox* floorScale_ = nullptr;
    // Interaction graphs built in memory by earlier generates (graph setups), reused.
    std::shared_ptr<pipeline::GraphCache> graphCache_;
    QGroupBox* cpBox_ = nullptr;
    QLabel* cpLabel_ = nullptr;
    QDoubleSpinBox* cpTime_ = nullptr;
    QComboBox* cpAction_ = nullptr;
    QPushButton* cpRemove_ = nullptr;
    std::string cpCharacter_;
    int cpIndex_ = -1;
    std::uint64_t overlayRevision_ = 0;
    // The posture mode (a view setting): the Scene panel's choice and the View menu's.
    posture::Mode postureMode_ = posture::Mode::Kinematic;
    QComboBox* posture_ = nullptr;
    QAction* postureKinematic_ = nullptr;
    QAction* posturePhysics_ = nullptr;
    bool solvingPosture_ = false;
    bool postureDropped_ = false;  // the running solve was cancelled by a switch to Kinematic
    // Starts the physics solve of the scene playing when physics is chosen and it lacks it.
    void solvePosture();
    void syncPostureControls();
    void buildPostureMenu(QMenu* view);
    QCheckBox* live_ = nullptr;        // re-plan after each edit of the current setup
    QTimer* replanTimer_ = nullptr;    // the live re-plan's debounce
    bool generatingReplan_ = false;    // the running generate is a live re-plan
    // Since the scene playing was generated from setup previewSetup_: the
    // characters the edits can affect (fray::setup::affectedCharacters) and
    // their tracks then, to report after the re-plan who kept theirs.
    QString previewSetup_;
    std::vector<setup::Pin> previewPins_;  // the pins the scene playing was planned with
    std::vector<int> replanAffected_;
    std::vector<std::pair<std::string, std::vector<sim::ActionInstance>>> replanBase_;  // name and track, before the edits
    bool replanOther_ = false;         // an edit that affects everyone
    int replanOthers_ = -1, replanKept_ = -1;
    double lastGenerateSeconds_ = 0;
    int sceneShownAtFrame_ = 0;       // viewport frames presented when the generated scene began playing  // wall clock of the last generate, request to result shown

    QToolButton* playButton_;
    QSlider* scrub_;
    QComboBox* speed_;
    QLabel* timeLabel_;
    QLabel* statsLabel_;
    QTimer timer_;
    double time_ = 0.0;
    bool playing_ = true;
    bool lastDrawn_ = false;  // the previous tick put a frame on screen
    int exitCode_ = 0;
    std::chrono::steady_clock::time_point last_;
    double frameMsAverage_ = 0.0;
};

}  // namespace fray::editor
