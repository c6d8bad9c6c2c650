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
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include "fray/render/motion_stage.h"
#include "project_analysis.h"
#include "scene_stage.h"
#include "takes.h"

class QDockWidget;
class QComboBox;
class QLabel;
class QLineEdit;
class QListWidget;
class QProgressBar;
class QPushButton;
class QSlider;
class QSortFilterProxyModel;
class QStandardItemModel;
class QTableView;
class QTextBrowser;
class QThread;
class QToolButton;
class QTreeWidget;
class QTreeWidgetItem;

namespace fray::editor {

class Viewport;
class GraphView;
class TimelineView;

struct EditorOptions {
    int quitAfter = 0;              // frames; 0: run until closed
    QString screenshot;             // the whole window, written before quitting
    QString viewportScreenshot;     // the viewport alone (the renderer's image)
    bool waitForAnalysis = false;   // with quitAfter: quit only once the project analysis has finished
    bool restoreLayout = true;      // restore the dock layout saved by the last run
};

class MainWindow : public QMainWindow {
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

protected:
    void closeEvent(QCloseEvent* event) override;

private Q_SLOTS:
    void tick();
    void librarySelectionChanged();
    void togglePlay();
    void scrubbed(int frame);
    void timelinePlayhead(int frame);
    void graphNodeSelected(int node);
    void analysisProgress(double fraction, const QString& stage);
    void analysisFinished();

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
    void resetLayout();
    void showShortcuts();
    void frameAll();
    void showTime();
    // Scrub steps per second of a scene.
    static constexpr int kSceneSteps = 30;
    void finish();
    void fail(const QString& message);

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
    QTextBrowser* inspector_ = nullptr;
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
    QProgressBar* progress_ = nullptr;
    QPushButton* cancelButton_ = nullptr;

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
