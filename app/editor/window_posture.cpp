// MainWindow: the posture mode (issue 25 item 5, docs/EDITOR.md). Posture:
// Kinematic | Physics (Scene panel, View menu, `fray --posture`) picks the poses
// the viewport plays. Physics runs posture::ScenePoses::make over the scene
// playing as a background job (progress and Cancel); Kinematic drops those
// poses at once. A view setting: no document edit, no undo command.
#include <QAction>
#include <QActionGroup>
#include <QComboBox>
#include <QElapsedTimer>
#include <QMenu>
#include <QSignalBlocker>
#include <QStatusBar>
#include <QTimer>
#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <utility>

#include "fray/posture/posture.h"
#include "gantt_view.h"
#include "main_window.h"

namespace fray::editor {

namespace {
QString qs(const std::string& s) { return QString::fromStdString(s); }
}  // namespace

// ---- posture mode

void MainWindow::seek(double t) {
    if (!scene_) return;
    time_ = std::clamp(t, 0.0, scene_->duration());
    gantt_->setTime(time_);
    if (playing_) togglePlay();
    scene_->pose(time_, cli::SceneStage::Labels::Auto, selected_);
    showTime();
}

void MainWindow::buildPostureMenu(QMenu* view) {
    // View > Posture: Kinematic | Physics (listed by --describe-ui with the View menu's actions).
    view->addSeparator();
    auto* group = new QActionGroup(this);
    postureKinematic_ = view->addAction("Posture: &Kinematic", this, [this] { setPostureMode(posture::Mode::Kinematic); });
    postureKinematic_->setObjectName("actionPostureKinematic");
    postureKinematic_->setStatusTip("Play the captured clips' poses (immediate)");
    posturePhysics_ = view->addAction("Posture: &Physics", this, [this] { setPostureMode(posture::Mode::Physics); });
    posturePhysics_->setObjectName("actionPosturePhysics");
    posturePhysics_->setStatusTip("Play the posture solver's poses (solved in the background; docs/POSTURE.md)");
    for (QAction* a : {postureKinematic_, posturePhysics_}) {
        a->setCheckable(true);
        group->addAction(a);
    }
    syncPostureControls();
}

void MainWindow::syncPostureControls() {
    const bool physics = postureMode_ == posture::Mode::Physics;
    if (posture_) {
        const QSignalBlocker block(posture_);
        posture_->setCurrentIndex(physics ? 1 : 0);
    }
    if (postureKinematic_) postureKinematic_->setChecked(!physics);
    if (posturePhysics_) posturePhysics_->setChecked(physics);
}

void MainWindow::setPostureMode(posture::Mode mode) {
    if (mode == postureMode_) {
        syncPostureControls();
        return;
    }
    postureMode_ = mode;
    syncPostureControls();
    if (mode == posture::Mode::Kinematic) {
        if (solvingPosture_ && jobThread_) {
            jobCancel_ = true;  // its result is dropped
            postureDropped_ = true;
        }
        if (scene_) {
            if (Status st = scene_->setPosture(posture::Mode::Kinematic); !st) showError("Posture", qs(st.error().message));
        }
        statusBar()->showMessage("Posture: kinematic (the captured clips)", 8000);
        if (scene_) scene_->pose(time_, cli::SceneStage::Labels::Auto, selected_);
        showTime();
        return;
    }
    if (!scene_) statusBar()->showMessage("Posture: physics (the next scene generated is solved)", 8000);
    solvePosture();
}

void MainWindow::solvePosture() {
    if (postureMode_ != posture::Mode::Physics || !scene_ || scene_->postureMode() == posture::Mode::Physics ||
        solvingPosture_)
        return;
    if (replanTimer_ && replanTimer_->isActive()) return;  // the re-planned scene is solved instead
    if (jobThread_) {
        // One job at a time: jobFinished starts the solve after it.
        statusBar()->showMessage("Physics posture: waits for " + jobName_, 8000);
        return;
    }
    const cli::SceneStage* stage = scene_.get();
    auto made = std::make_shared<std::optional<Result<posture::ScenePoses>>>();
    auto clock = std::make_shared<QElapsedTimer>();
    clock->start();
    solvingPosture_ = true;
    startJob(
        "solving physics posture",
        [stage, made](const ProgressFn& progress) {
            // The stage stays while the job runs: no generate, stop or library pick replaces it (one job at a time).
            made->emplace(posture::ScenePoses::make(posture::Mode::Physics, stage->scene(), stage->library(), {}, progress));
        },
        [this, stage, made, clock] {
            solvingPosture_ = false;
            const bool dropped = std::exchange(postureDropped_, false);
            const bool current = scene_.get() == stage && postureMode_ == posture::Mode::Physics;
            if (!*made || !**made) {
                const bool cancelled = *made && (*made)->error().isCancelled();
                if (!current) return;  // switched back to kinematic, or the scene changed
                if (replanTimer_ && replanTimer_->isActive()) return;  // cancelled for a re-plan: solved after it
                if (dropped) return;  // Kinematic then Physics again while it stopped: jobFinished solves again
                // Cancelled or failed: the viewport keeps the kinematic poses, and says so.
                postureMode_ = posture::Mode::Kinematic;
                syncPostureControls();
                if (cancelled) statusBar()->showMessage("Physics posture cancelled: playing kinematic poses", 8000);
                else showError("Posture", *made ? qs((*made)->error().message) : QString("no result"));
                return;
            }
            if (!current) return;
            const std::size_t notes = (**made)->report().notes.size();
            scene_->setPosture(std::move(***made));
            const double seconds = static_cast<double>(clock->elapsed()) / 1000.0;
            const QString msg = QString("Posture: physics (solved in %1 s, %2 solver notes)").arg(seconds, 0, 'f', 2).arg(notes);
            statusBar()->showMessage(msg, 15000);
            std::printf("fray: %s\n", msg.toUtf8().constData());
            std::fflush(stdout);
            scene_->pose(time_, cli::SceneStage::Labels::Auto, selected_);
            showTime();
        });
}

}  // namespace fray::editor
