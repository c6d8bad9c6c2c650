#pragma once
// The editor's first window: the takes of the open project (or motion files)
// on the left, the Vulkan viewport with play / pause / scrub / speed controls
// on the right. Selecting takes shows them side by side, each labelled with
// its current action. With a scene (planned or composed) the list holds its
// characters instead: everyone present plays, labelled with the current
// action, and the selected character is highlighted and can be framed.
#include <QMainWindow>
#include <QString>
#include <QTimer>
#include <chrono>
#include <memory>
#include <vector>

#include "fray/render/motion_stage.h"
#include "scene_stage.h"
#include "takes.h"

class QComboBox;
class QLabel;
class QListWidget;
class QSlider;
class QToolButton;

namespace fray::editor {

class Viewport;

struct EditorOptions {
    int quitAfter = 0;              // frames; 0: run until closed
    QString screenshot;             // the whole window, written before quitting
    QString viewportScreenshot;     // the viewport alone (the renderer's image)
};

class MainWindow : public QMainWindow {
    Q_OBJECT
public:
    // Plays `scene` when given, else the takes.
    MainWindow(Viewport* viewport, std::vector<app::LoadedTake> takes, std::unique_ptr<cli::SceneStage> scene,
               QString title, EditorOptions options);

    // Exit code for main(): 0, or 1 after an error (already reported).
    int exitCode() const { return exitCode_; }

private Q_SLOTS:
    void tick();
    void takesChanged();
    void togglePlay();
    void scrubbed(int frame);

private:
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
    int selected_ = -1;  // scene character, -1: none
    EditorOptions options_;
    QListWidget* takeList_;
    QToolButton* playButton_;
    QSlider* scrub_;
    QComboBox* speed_;
    QLabel* timeLabel_;
    QLabel* statsLabel_;
    QTimer timer_;
    double time_ = 0.0;
    bool playing_ = true;
    bool lastDrawn_ = false;  // the previous tick put a frame on screen
    int ticks_ = 0;
    int exitCode_ = 0;
    std::chrono::steady_clock::time_point last_;
    double frameMsAverage_ = 0.0;
};

}  // namespace fray::editor
