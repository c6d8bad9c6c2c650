#include "main_window.h"

#include <QApplication>
#include <QComboBox>
#include <QHBoxLayout>
#include <QImage>
#include <QLabel>
#include <QListWidget>
#include <QPixmap>
#include <QPainter>
#include <QSlider>
#include <QSplitter>
#include <QStatusBar>
#include <QStyle>
#include <QToolButton>
#include <QVBoxLayout>
#include <cmath>
#include <cstdio>

#include "fray/render/image.h"
#include "viewport.h"

namespace fray::editor {

MainWindow::MainWindow(Viewport* viewport, std::vector<app::LoadedTake> takes, std::unique_ptr<cli::SceneStage> scene,
                       QString title, EditorOptions options)
    : viewport_(viewport), takes_(std::move(takes)), scene_(std::move(scene)), options_(std::move(options)) {
    setWindowTitle(title + " - Fray");

    takeList_ = new QListWidget;
    if (scene_) {
        // One row per character, with its team colour.
        takeList_->setSelectionMode(QAbstractItemView::SingleSelection);
        takeList_->setToolTip("Select a character to highlight it; F frames it, F with none selected frames everyone");
        for (int c = 0; c < scene_->characterCount(); ++c) {
            const glm::vec3 tint = scene_->tint(c);
            QPixmap swatch(12, 12);
            swatch.fill(QColor::fromRgbF(tint.x, tint.y, tint.z));
            takeList_->addItem(new QListWidgetItem(
                QIcon(swatch), QString::fromStdString(scene_->scene().characters[static_cast<std::size_t>(c)].name)));
        }
    } else {
        takeList_->setSelectionMode(QAbstractItemView::ExtendedSelection);
        for (const app::LoadedTake& t : takes_) {
            const double seconds = t.motion->duration();
            takeList_->addItem(QString("%1  (%2 s)").arg(QString::fromStdString(t.name)).arg(seconds, 0, 'f', 1));
        }
    }

    viewportContainer_ = QWidget::createWindowContainer(viewport_);
    viewportContainer_->setMinimumSize(320, 200);
    viewportContainer_->setFocusPolicy(Qt::StrongFocus);

    playButton_ = new QToolButton;
    playButton_->setIcon(style()->standardIcon(QStyle::SP_MediaPause));
    playButton_->setToolTip("Play / pause (Space)");
    playButton_->setShortcut(Qt::Key_Space);
    scrub_ = new QSlider(Qt::Horizontal);
    scrub_->setToolTip("Scrub");
    speed_ = new QComboBox;
    for (const char* s : {"0.25x", "0.5x", "1x", "2x", "4x"}) speed_->addItem(s);
    speed_->setCurrentIndex(2);
    speed_->setToolTip("Playback speed");
    timeLabel_ = new QLabel;
    timeLabel_->setMinimumWidth(260);
    auto* transport = new QHBoxLayout;
    transport->addWidget(playButton_);
    transport->addWidget(scrub_, 1);
    transport->addWidget(speed_);
    transport->addWidget(timeLabel_);

    auto* right = new QWidget;
    auto* rightLayout = new QVBoxLayout(right);
    rightLayout->setContentsMargins(0, 0, 0, 0);
    rightLayout->addWidget(viewportContainer_, 1);
    rightLayout->addLayout(transport);

    auto* split = new QSplitter;
    split->addWidget(takeList_);
    split->addWidget(right);
    split->setStretchFactor(1, 1);
    split->setSizes({220, 1060});
    setCentralWidget(split);
    statsLabel_ = new QLabel;
    statusBar()->addPermanentWidget(statsLabel_);
    resize(1280, 760);

    connect(takeList_, &QListWidget::itemSelectionChanged, this, &MainWindow::takesChanged);
    connect(playButton_, &QToolButton::clicked, this, &MainWindow::togglePlay);
    connect(scrub_, &QSlider::valueChanged, this, &MainWindow::scrubbed);
    connect(viewport_, &Viewport::frameAllRequested, this, &MainWindow::frameAll);
    connect(&timer_, &QTimer::timeout, this, &MainWindow::tick);

    if (scene_) {
        scrub_->setRange(0, std::max(0, static_cast<int>(std::ceil(scene_->duration() * kSceneSteps))));
        frameAll();
    } else {
        if (!takes_.empty()) takeList_->setCurrentRow(0);
        takesChanged();
    }
    last_ = std::chrono::steady_clock::now();
    timer_.start(options_.quitAfter > 0 ? 0 : 15);
}

void MainWindow::takesChanged() {
    if (scene_) {
        // Selecting a character highlights it; the time keeps running.
        const auto rows = takeList_->selectedItems();
        selected_ = rows.empty() ? -1 : takeList_->row(rows.front());
        return;
    }
    shown_.clear();
    for (int i = 0; i < takeList_->count(); ++i)
        if (takeList_->item(i)->isSelected()) shown_.push_back(takes_[static_cast<std::size_t>(i)]);
    app::stageTakes(shown_, stage_);
    time_ = 0.0;
    stage_.pose(0.0);
    scrub_->blockSignals(true);
    scrub_->setRange(0, std::max(0, stage_.longestFrameCount() - 1));
    scrub_->setValue(0);
    scrub_->blockSignals(false);
    frameAll();
}

void MainWindow::frameAll() {
    render::Bounds b;
    if (scene_) {
        // The selected character as it is now, or everyone over the whole scene.
        const double now = time_;
        if (selected_ >= 0) {
            scene_->pose(now, cli::SceneStage::Labels::None);
            if (scene_->present(selected_)) {
                for (std::size_t k = 0; k < scene_->shown().size(); ++k)
                    if (scene_->shownCharacter(k) == selected_) b = render::characterBounds(scene_->shown().subspan(k, 1));
            }
        }
        if (b.empty()) b = scene_->bounds(0.0, scene_->duration());
        scene_->pose(now, cli::SceneStage::Labels::Auto, selected_);
    } else {
        b = stage_.bounds();
    }
    if (b.empty()) return;
    b.add(b.min - glm::vec3(0.4f));
    b.add(b.max + glm::vec3(0.4f));
    viewport_->frame().camera.frame(b, viewport_->aspect());
}

void MainWindow::togglePlay() {
    playing_ = !playing_;
    playButton_->setIcon(style()->standardIcon(playing_ ? QStyle::SP_MediaPause : QStyle::SP_MediaPlay));
}

void MainWindow::scrubbed(int frame) {
    if (scene_) {
        time_ = static_cast<double>(frame) / kSceneSteps;
    } else {
        if (shown_.empty()) return;
        time_ = frame / shown_.front().motion->fps();
    }
    if (playing_) togglePlay();
}

void MainWindow::tick() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    frameMsAverage_ = frameMsAverage_ == 0.0 ? ms : 0.9 * frameMsAverage_ + 0.1 * ms;
    // Fixed steps when counting frames, so test runs are reproducible: 1/60 s
    // per frame shown (not per tick: ticks also come before the window is exposed).
    const double dt = options_.quitAfter > 0 ? (lastDrawn_ ? 1.0 / 60.0 : 0.0) : ms / 1000.0;
    static constexpr double kSpeeds[] = {0.25, 0.5, 1.0, 2.0, 4.0};
    if (playing_) time_ += dt * kSpeeds[std::clamp(speed_->currentIndex(), 0, 4)];
    const double duration = scene_ ? scene_->duration() : stage_.duration();
    if (duration > 0.0 && time_ > duration) time_ = std::fmod(time_, duration);
    if (scene_) {
        scene_->pose(time_, cli::SceneStage::Labels::Auto, selected_);
        viewport_->frame().characters = scene_->shown();
        viewport_->frame().trajectories = scene_->trajectories();
        viewport_->frame().checkpoints = scene_->checkpoints();
        viewport_->frame().floorBitmap = scene_->floorBitmap();
    } else {
        stage_.pose(time_, true);
        viewport_->frame().characters = stage_.instances();
        viewport_->frame().floorBitmap = nullptr;
    }
    showTime();
    auto drawn = viewport_->renderNow();
    if (!drawn) return fail(QString::fromStdString(drawn.error().message));
    lastDrawn_ = *drawn;
    if (const render::Renderer* r = viewport_->renderer()) {
        statsLabel_->setText(QString("%1 ms  %2 characters  %3 triangles  %4")
                                 .arg(frameMsAverage_, 0, 'f', 1)
                                 .arg(r->stats().characters)
                                 .arg(static_cast<qulonglong>(r->stats().triangles))
                                 .arg(QString::fromStdString(r->device()->description())));
    }
    if (options_.quitAfter > 0 && viewport_->framesPresented() >= options_.quitAfter) finish();
    // Not exposed yet (or minimised): keep ticking; a run with --quit-after
    // that never gets a frame on screen is stopped by its caller's timeout.
    (void)ticks_++;
}

void MainWindow::showTime() {
    auto text = [](const std::string& s) { return QString::fromStdString(s); };
    if (scene_) {
        scrub_->blockSignals(true);
        scrub_->setValue(static_cast<int>(std::lround(time_ * kSceneSteps)));
        scrub_->blockSignals(false);
        QString line = QString("%1 / %2 s  %3 characters")
                           .arg(time_, 0, 'f', 2)
                           .arg(scene_->duration(), 0, 'f', 1)
                           .arg(scene_->shown().size());
        if (selected_ >= 0) {
            const std::string& name = scene_->scene().characters[static_cast<std::size_t>(selected_)].name;
            line += "  " + text(name) + ": " +
                    (scene_->present(selected_) ? text(scene_->currentAction(selected_)) : QString("(not in the scene yet)"));
        }
        timeLabel_->setText(line);
        return;
    }
    if (!shown_.empty()) {
        const int f = stage_.frameOf(0);
        scrub_->blockSignals(true);
        scrub_->setValue(f);
        scrub_->blockSignals(false);
        const std::string_view action = stage_.actionOf(0);
        timeLabel_->setText(QString("frame %1 / %2  %3")
                                .arg(f)
                                .arg(shown_.front().motion->frameCount() - 1)
                                .arg(QString::fromUtf8(action.data(), static_cast<int>(action.size()))));
    } else {
        timeLabel_->setText("select a take");
    }
}

void MainWindow::fail(const QString& message) {
    std::fprintf(stderr, "fray: %s\n", message.toUtf8().constData());
    exitCode_ = 1;
    timer_.stop();
    QApplication::exit(1);
}

// Screenshots use the renderer's own readback: the viewport is a native
// Vulkan window that QWidget::grab() cannot see (and QVulkanWindow::grab()
// swaps red and blue on Qt 6.4 with lavapipe).
void MainWindow::finish() {
    timer_.stop();
    render::Image view;
    if (Status s = viewport_->renderer()->readback(view); !s) return fail(QString::fromStdString(s.error().message));
    if (!options_.viewportScreenshot.isEmpty()) {
        if (Status s = render::writePng(options_.viewportScreenshot.toStdString(), view); !s)
            return fail(QString::fromStdString(s.error().message));
    }
    if (!options_.screenshot.isEmpty()) {
        QImage shot = grab().toImage().convertToFormat(QImage::Format_RGBA8888);
        const QImage viewImage(view.rgba.data(), view.width, view.height, view.width * 4, QImage::Format_RGBA8888);
        QPainter painter(&shot);
        painter.drawImage(QRect(viewportContainer_->mapTo(this, QPoint(0, 0)), viewportContainer_->size()), viewImage);
        painter.end();
        if (!shot.save(options_.screenshot, "PNG")) return fail(options_.screenshot + ": cannot write the screenshot");
    }
    // The time of the last frame shown: the window tests check that playback moves.
    std::printf("fray: drew %d frames, at %.3f s\n", viewport_->framesPresented(), time_);
    QApplication::exit(exitCode_);
}

}  // namespace fray::editor
