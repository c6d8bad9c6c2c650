// MainWindow: generate and preview (issue 23). The Scene panel picks a scene
// spec and generates it in the background (progress and Cancel in the status
// bar); the result plays in the viewport, its action track shows in the Gantt
// panel below it and its `fray-cli metrics` figures in the Metrics panel.
// File > Export scene writes the scene playing, in the background too.
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QInputDialog>
#include <QSignalBlocker>
#include <QTimer>
#include <QCoreApplication>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDir>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QMenu>
#include <QMenuBar>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QSlider>
#include <QStandardItemModel>
#include <QStatusBar>
#include <QTableView>
#include <QThread>
#include <QToolButton>
#include <QTreeWidget>
#include <QVBoxLayout>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include "fray/authoring/project_document.h"
#include "fray/export/export.h"
#include "fray/io/rig_import.h"
#include "fray/posture/posture.h"
#include "fray/setup/affected.h"
#include "fray/setup/convert.h"
#include "gantt_view.h"
#include "main_window.h"
#include "scene_generation.h"
#include "viewport.h"

namespace fray::editor {

namespace {
// A share [from, to] of a job's progress.
ProgressFn partOf(const ProgressFn& progress, double from, double to) {
    if (!progress) return {};
    return [=](double f, std::string_view name) { return progress(from + (to - from) * f, name); };
}
}  // namespace


namespace {

QString qs(const std::string& s) { return QString::fromStdString(s); }

// Where the demo scene specs are: the source tree's resources/demo (a build
// runs from the tree), else beside the executable.
QString demoSpecDir() {
#ifdef FRAY_DEMO_SPEC_DIR
    if (QFileInfo(FRAY_DEMO_SPEC_DIR).isDir()) return FRAY_DEMO_SPEC_DIR;
#endif
    const QString beside = QCoreApplication::applicationDirPath() + "/../../resources/demo";
    return QFileInfo(beside).isDir() ? QFileInfo(beside).canonicalFilePath() : QString();
}

constexpr const char* kSetupPrefix = "setup:";

}  // namespace

void MainWindow::buildSceneDocks() {
    // Scene: which spec to generate.
    auto* panel = new QWidget;
    panel->setObjectName("scenePanel");
    auto* layout = new QVBoxLayout(panel);
    layout->setContentsMargins(2, 2, 2, 2);
    sceneSource_ = new QComboBox;
    sceneSource_->setObjectName("sceneSource");
    sceneSource_->setToolTip("The scene to generate: a demo spec (resources/demo) or a spec file you opened");
    const QString dir = demoSpecDir();
    if (!dir.isEmpty()) {
        const QStringList specs = QDir(dir).entryList({"*.json"}, QDir::Files, QDir::Name);
        for (const QString& f : specs) {
            const QString path = QDir(dir).filePath(f);
            sceneSource_->addItem("demo: " + QFileInfo(f).completeBaseName(), path);
        }
    }
    auto* open = new QPushButton("Open spec...");
    open->setObjectName("sceneOpenSpec");
    connect(open, &QPushButton::clicked, this, [this] {
        const QString f = QFileDialog::getOpenFileName(this, "Scene spec", demoSpecDir(), "Scene specs (*.json)");
        if (!f.isEmpty()) selectSceneSource(f);
    });
    generateButton_ = new QPushButton("Generate");
    generateButton_->setObjectName("sceneGenerate");
    generateButton_->setToolTip("Plan (tree expansion) or compose (Interaction Patches) the scene in the background and play it (F5)");
    connect(generateButton_, &QPushButton::clicked, this, &MainWindow::generate);
    auto* row = new QHBoxLayout;
    row->addWidget(sceneSource_, 1);
    row->addWidget(open);
    layout->addLayout(row);
    layout->addWidget(makeSetupParameters());
    auto* importSpec = new QPushButton("Import as setup...");
    importSpec->setObjectName("sceneImportSpec");
    importSpec->setToolTip("Store the selected spec file (and its floor bitmap) in the project as a scene setup");
    connect(importSpec, &QPushButton::clicked, this, [this] {
        const QString file = sceneSource_->currentData().toString();
        if (file.startsWith(kSetupPrefix)) return;
        bool ok = false;
        const QString name = QInputDialog::getText(this, "Import as setup", "Setup name", QLineEdit::Normal,
                                                   QFileInfo(file).completeBaseName(), &ok);
        if (ok && !name.trimmed().isEmpty()) importSpecAsSetup(name.trimmed());
    });
    auto* row2 = new QHBoxLayout;
    row2->addWidget(generateButton_);
    row2->addWidget(importSpec);
    auto* stop = new QPushButton("Stop preview");
    stop->setObjectName("sceneStopPreview");
    connect(stop, &QPushButton::clicked, this, &MainWindow::stopPreview);
    row2->addWidget(stop);
    row2->addStretch(1);
    layout->addLayout(row2);
    live_ = new QCheckBox("Re-plan after each edit");
    live_->setObjectName("sceneLive");
    live_->setChecked(true);
    live_->setToolTip("After an edit of the selected setup (a stroke, a moved checkpoint, a changed weight) the scene "
                      "regenerates by itself once you pause for a moment");
    layout->addWidget(live_);
    auto* postureRow = new QHBoxLayout;
    postureRow->addWidget(new QLabel("Posture:"));
    posture_ = new QComboBox;
    posture_->setObjectName("scenePosture");
    posture_->addItem("Kinematic", "kinematic");
    posture_->addItem("Physics", "physics");
    posture_->setToolTip("The poses the viewport plays (a view setting, not an edit): kinematic (the captured clips) or "
                         "physics (the posture solver, solved in the background; docs/POSTURE.md)");
    connect(posture_, &QComboBox::currentIndexChanged, this, [this](int i) {
        setPostureMode(i == 1 ? posture::Mode::Physics : posture::Mode::Kinematic);
    });
    postureRow->addWidget(posture_, 1);
    layout->addLayout(postureRow);
    replanTimer_ = new QTimer(this);
    replanTimer_->setSingleShot(true);
    replanTimer_->setInterval(kReplanDebounceMs);
    connect(replanTimer_, &QTimer::timeout, this, [this] {
        if (jobThread_) {
            // A re-plan that is out of date already: cancel it and start again.
            if (generatingReplan_ || solvingPosture_) jobCancel_ = true;
            replanTimer_->start(50);
            return;
        }
        generatingReplan_ = true;
        generate();
    });
    layout->addWidget(makeCheckpointInspector());
    sceneInfo_ = new QLabel("Pick a scene and Generate: it plays in the viewport, its action track below it.");
    sceneInfo_->setObjectName("sceneInfo");
    sceneInfo_->setWordWrap(true);
    sceneInfo_->setMinimumHeight(sceneInfo_->fontMetrics().lineSpacing() * 3);
    sceneInfo_->setAlignment(Qt::AlignTop | Qt::AlignLeft);
    layout->addWidget(sceneInfo_);
    layout->addStretch(1);
    sceneDock_ = new QDockWidget("Scene", this);
    sceneDock_->setObjectName("SceneDock");
    // Scrolled: with a graph setup's parameters the panel is taller than a small screen leaves it.
    auto* scroll = new QScrollArea;
    scroll->setObjectName("scenePanelScroll");
    scroll->setWidgetResizable(true);
    scroll->setFrameShape(QFrame::NoFrame);
    scroll->setWidget(panel);
    sceneDock_->setWidget(scroll);
    addDockWidget(Qt::LeftDockWidgetArea, sceneDock_);
    splitDockWidget(libraryDock_, sceneDock_, Qt::Vertical);

    // Gantt (made in buildDocks, above the timeline): the action track of the scene playing.
    connect(gantt_, &GanttView::barClicked, this, &MainWindow::ganttBarClicked);
    connect(gantt_, &GanttView::barMenuRequested, this, [this](int r, int b, QPoint global) {
        std::unique_ptr<QMenu> menu(ganttBarMenu(r, b));
        if (menu) menu->exec(global);
    });
    connect(gantt_, &GanttView::seekRequested, this, &MainWindow::seek);

    // Metrics of the scene playing (`fray-cli metrics`).
    auto* metricsPanel = new QWidget;
    metricsPanel->setObjectName("metricsPanel");
    auto* ml = new QVBoxLayout(metricsPanel);
    ml->setContentsMargins(2, 2, 2, 2);
    metricsSummary_ = new QLabel("No scene generated yet.");
    metricsSummary_->setObjectName("metricsSummary");
    metricsSummary_->setWordWrap(true);
    metricsSummary_->setMinimumHeight(metricsSummary_->fontMetrics().lineSpacing() * 2 + 4);
    metricsModel_ = new QStandardItemModel(0, 0, this);
    metrics_ = new QTableView;
    metrics_->setObjectName("metrics");
    metrics_->setModel(metricsModel_);
    metrics_->setSortingEnabled(true);
    metrics_->verticalHeader()->hide();
    metrics_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    metrics_->setSelectionBehavior(QAbstractItemView::SelectRows);
    ml->addWidget(metricsSummary_);
    ml->addWidget(metrics_, 1);
    metricsDock_ = new QDockWidget("Metrics", this);
    metricsDock_->setObjectName("MetricsDock");
    metricsDock_->setWidget(metricsPanel);
    addDockWidget(Qt::RightDockWidgetArea, metricsDock_);
    tabifyDockWidget(historyDock_, metricsDock_);
    inspectorDock_->raise();
    resizeDocks({ganttDock_, timelineDock_}, {130, 200}, Qt::Vertical);
    resizeDocks({libraryDock_, sceneDock_}, {440, 210}, Qt::Vertical);
}

void MainWindow::buildSceneMenu() {
    QMenu* menu = menuBar()->addMenu("&Scene");
    menu->setObjectName("SceneMenu");
    generateAction_ = menu->addAction("&Generate", this, &MainWindow::generate);
    generateAction_->setObjectName("actionGenerate");
    generateAction_->setShortcut(Qt::Key_F5);
    QAction* open = menu->addAction("&Open scene spec...", this, [this] {
        const QString f = QFileDialog::getOpenFileName(this, "Scene spec", demoSpecDir(), "Scene specs (*.json)");
        if (!f.isEmpty()) selectSceneSource(f);
    });
    open->setObjectName("actionOpenSpec");
    stopPreviewAction_ = menu->addAction("&Stop preview", this, &MainWindow::stopPreview);
    stopPreviewAction_->setObjectName("actionStopPreview");
    menu->addSeparator();
    exportAction_ = menu->addAction("&Export scene...", this, &MainWindow::exportDialog);
    exportAction_->setObjectName("actionExportScene");
    exportAction_->setShortcut(QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_E));
}

void MainWindow::fillSceneSources() {
    if (!sceneSource_) return;
    const QString selected = sceneSource_->currentData().toString();
    const QSignalBlocker quiet(sceneSource_);
    for (int i = sceneSource_->count() - 1; i >= 0; --i)
        if (sceneSource_->itemData(i).toString().startsWith(kSetupPrefix)) sceneSource_->removeItem(i);
    if (doc_) {
        auto setups = doc_->setups();
        if (setups) {
            int at = 0;
            for (const setup::SceneSetup& st : *setups)
                sceneSource_->insertItem(at++, QString("setup: %1 (%2)").arg(qs(st.name)).arg(setup::setupKindName(st.kind)),
                                         QString(kSetupPrefix) + qs(st.name));
        } else {
            sceneInfo_->setText("The project's setups cannot be read: " + qs(setups.error().message));
        }
    }
    const int again = sceneSource_->findData(selected);
    sceneSource_->setCurrentIndex(again >= 0 ? again : 0);
    fillToolCharacters();
    refreshCheckpointInspector();
    refreshSetupOverlay();
    refreshSetupParameters();
}

bool MainWindow::selectSetup(const QString& name) {
    const int i = sceneSource_->findData(QString(kSetupPrefix) + name);
    if (i < 0) return false;
    sceneSource_->setCurrentIndex(i);
    return true;
}

QString MainWindow::currentSetup() const {
    const QString d = sceneSource_ ? sceneSource_->currentData().toString() : QString();
    return d.startsWith(kSetupPrefix) ? d.mid(static_cast<int>(std::strlen(kSetupPrefix))) : QString();
}

bool MainWindow::importSpecAsSetup(const QString& name) {
    const QString file = sceneSource_->currentData().toString();
    if (!doc_ || file.isEmpty() || file.startsWith(kSetupPrefix)) return false;
    std::ifstream in(file.toStdString(), std::ios::binary);
    if (!in) {
        showError("Import as setup", file + ": cannot read the file");
        return false;
    }
    std::stringstream text;
    text << in.rdbuf();
    auto imported = setup::importSpec(name.toStdString(), text.str(), file.toStdString(), loadFloorBitmapPng);
    if (!imported) {
        showError("Import as setup", qs(imported.error().message));
        return false;
    }
    if (Status st = doc_->addSetup(std::move(*imported)); !st) {
        showError("Import as setup", qs(st.error().message));
        return false;
    }
    fillSceneSources();
    return selectSetup(name);
}

bool MainWindow::replanPending() const { return (replanTimer_ && replanTimer_->isActive()) || (jobThread_ && generatingReplan_); }

void MainWindow::setupEdited(const authoring::ChangeEvent& event) {
    if (qs(event.setup) == currentSetup()) {
        refreshCheckpointInspector();
        refreshSetupOverlay();
        refreshSetupParameters();
        if (event.kind == authoring::ChangeKind::SetupParameters) fillToolCharacters();
    }
    // Who this edit can affect in the scene playing (when it is this setup's).
    if (scene_ && sceneIsPreview_ && qs(event.setup) == previewSetup_ && doc_) {
        if (replanBase_.empty())
            for (const sim::SceneCharacter& c : scene_->scene().characters) replanBase_.emplace_back(c.name, c.track);
        setup::SetupEdit edit;
        using authoring::ChangeKind;
        if (event.kind == ChangeKind::SetupFloor && !event.pixels.empty()) {
            auto st = doc_->sceneSetup(event.setup);
            if (st && st->floor) {
                const setup::FloorPaint& f = *st->floor;
                edit.kind = setup::SetupEdit::Kind::Stroke;
                edit.lo = {f.origin.x + event.pixels.x * f.metresPerPixel, f.origin.z + event.pixels.y * f.metresPerPixel};
                edit.hi = {f.origin.x + (event.pixels.x + event.pixels.width) * f.metresPerPixel,
                           f.origin.z + (event.pixels.y + event.pixels.height) * f.metresPerPixel};
            }
        } else if (event.kind == ChangeKind::SetupTrajectory && !event.character.empty()) {
            edit.kind = setup::SetupEdit::Kind::Checkpoint;
            edit.character = event.character;
        } else if (event.kind == ChangeKind::SetupPlacement && !event.character.empty()) {
            edit.kind = setup::SetupEdit::Kind::Start;
            edit.character = event.character;
        }
        if (edit.kind == setup::SetupEdit::Kind::Other) replanOther_ = true;
        for (int c : setup::affectedCharacters(scene_->scene(), scene_->library(), edit))
            if (std::find(replanAffected_.begin(), replanAffected_.end(), c) == replanAffected_.end()) replanAffected_.push_back(c);
    }
    if (!live_ || !live_->isChecked() || event.setup.empty() || qs(event.setup) != currentSetup()) return;
    replanTimer_->start();
}

QStringList MainWindow::sceneSources() const {
    QStringList out;
    for (int i = 0; i < sceneSource_->count(); ++i) out << sceneSource_->itemData(i).toString();
    return out;
}

bool MainWindow::selectSceneSource(const QString& specFile) {
    const QFileInfo info(specFile);
    if (!info.isFile() || !info.isReadable()) {
        showError("Scene spec", specFile + ": cannot read the file");
        return false;
    }
    const QString path = info.absoluteFilePath();
    int index = -1;
    for (int i = 0; i < sceneSource_->count(); ++i)
        if (QFileInfo(sceneSource_->itemData(i).toString()).absoluteFilePath() == path) index = i;
    if (index < 0) {
        sceneSource_->addItem(info.fileName(), path);
        index = sceneSource_->count() - 1;
    }
    sceneSource_->setCurrentIndex(index);
    return true;
}

// ---- background jobs

bool MainWindow::startJob(const QString& what, std::function<void(const ProgressFn&)> work, std::function<void()> done) {
    if (jobThread_) {
        statusBar()->showMessage(QString("%1 is running: wait for it or Cancel it first").arg(jobName_), 8000);
        return false;
    }
    jobCancel_ = false;
    jobName_ = what;
    jobDone_ = std::move(done);
    progress_->setValue(0);
    progress_->setFormat(what + " %p%");
    progress_->show();
    cancelButton_->show();
    auto posted = std::make_shared<std::atomic<double>>(-1.0);
    ProgressFn progress = [this, posted](double f, std::string_view stage) {
        if (f - posted->load() >= 0.005 || f >= 1.0 || f < posted->load()) {
            posted->store(f);
            const QString name = QString::fromUtf8(stage.data(), static_cast<int>(stage.size()));
            QMetaObject::invokeMethod(this, [this, f, name] { analysisProgress(f, name); }, Qt::QueuedConnection);
        }
        return !jobCancel_.load();
    };
    jobThread_ = QThread::create([work = std::move(work), progress] { work(progress); });
    connect(jobThread_, &QThread::finished, this, &MainWindow::jobFinished);
    jobThread_->start(QThread::LowPriority);
    updateBusy();
    return true;
}

void MainWindow::jobFinished() {
    jobThread_->deleteLater();
    jobThread_ = nullptr;
    auto done = std::move(jobDone_);
    jobDone_ = nullptr;
    updateBusy();
    if (done) done();
    // A scene generated (or a job that held off the solve) while physics is on.
    if (!jobThread_) solvePosture();
}

void MainWindow::updateBusy() {
    const bool any = jobThread_ || analysisThread_;
    progress_->setVisible(any);
    cancelButton_->setVisible(any);
    if (generateButton_) generateButton_->setEnabled(!jobThread_);
    if (generateAction_) generateAction_->setEnabled(!jobThread_);
}

// ---- generate

void MainWindow::generate() {
    if (!doc_) {
        showError("Generate", "Open a project first: scenes are planned on a project's actions (File > Open)");
        return;
    }
    const bool replan = generatingReplan_;
    generatingReplan_ = false;
    const QString source = sceneSource_->currentData().toString();
    if (source.isEmpty()) {
        showError("Generate", "Pick a scene setup or spec first (Scene > Open scene spec)");
        return;
    }
    auto input = std::make_shared<GenerateInput>();
    input->projectFile = projectFile_.toStdString();
    input->project = doc_->project();
    input->patches = patchLibrary_;
    input->cachedSession = generateSession_;
    if (!graphCache_) graphCache_ = std::make_shared<pipeline::GraphCache>();
    input->graphs = graphCache_;
    if (!planCache_) planCache_ = std::make_shared<sim::PlanCache>();
    input->plans = planCache_;
    QString specFile = source;
    if (source.startsWith(kSetupPrefix)) {
        auto st = doc_->sceneSetup(currentSetup().toStdString());
        if (!st) {
            showError("Generate", qs(st.error().message));
            return;
        }
        input->setup = std::move(*st);
        specFile = currentSetup() + ".setup";
    } else {
        std::ifstream in(source.toStdString(), std::ios::binary);
        if (!in) {
            showError("Generate", source + ": cannot read the file");
            return;
        }
        std::stringstream text;
        text << in.rdbuf();
        input->specText = text.str();
        input->specName = QFileInfo(source).fileName().toStdString();
        input->specDir = QFileInfo(source).absolutePath().toStdString();
    }
    auto result = std::make_shared<std::optional<Result<GeneratedScene>>>();
    auto shown = std::make_shared<PreparedPreview>();
    auto clock = std::make_shared<QElapsedTimer>();
    clock->start();
    sceneInfo_->setText("Generating " + QFileInfo(specFile).fileName() + "...");
    generatingReplan_ = replan;
    startJob(
        "generating " + QFileInfo(specFile).completeBaseName(),
        [input, result, shown](const ProgressFn& progress) {
            result->emplace(generateScene(*input, progress));
            // What the UI thread shows, prepared here: the posed stage and the track.
            if (*result && **result) {
                GeneratedScene& g = (*result)->value();
                shown->session = g.session;
                shown->summary = g.summary + QString(" (%1 s)").arg(g.seconds, 0, 'f', 2);
                shown->replan = g.replan;
                if (g.replan && g.replan->incremental) {
                    shown->summary += QString("; re-planned from %1 s on (%2 of %3 decisions kept)")
                                          .arg(g.replan->resumedAt, 0, 'f', 2)
                                          .arg(g.replan->decisionsKept)
                                          .arg(g.replan->decisionsKept + g.replan->decisionsPlanned);
                }
                shown->metrics = g.metrics;
                shown->stage = std::make_unique<cli::SceneStage>(std::move(g.loaded));
                const cli::SceneStage& stage = *shown->stage;
                shown->gantt = ganttFromScene(stage.scene(), stage.library(), [&stage](int c) {
                    const glm::vec3 t = stage.tint(c);
                    return QColor::fromRgbF(t.x, t.y, t.z);
                });
                if (input->setup && setup::isTreeExpansion(input->setup->kind)) {
                    shown->pins = input->setup->pins;
                    markPinnedBars(shown->gantt, shown->pins);
                }
            }
        },
        [this, result, clock, specFile, shown] {
            const bool wasReplan = generatingReplan_;
            generatingReplan_ = false;
            if (!*result || !**result) {
                const bool wasCancelled = *result && (*result)->error().isCancelled();
                const QString why = *result ? qs((*result)->error().message) : QString("no result");
                sceneInfo_->setText(wasCancelled ? "Generating cancelled." : "Generating failed: " + why);
                if (wasCancelled && wasReplan) return;  // a newer edit's re-plan follows
                if (wasCancelled) statusBar()->showMessage("Generating cancelled", 8000);
                else showError("Generate", why);
                if (options_.quitAfter > 0 && !options_.generateSpec.isEmpty()) fail("generate: " + why);
                return;
            }
            generateSession_ = shown->session;
            lastReplan_ = shown->replan;
            // Who kept their tracks, of those the edits since the last scene could not affect.
            QString kept;
            replanOthers_ = replanKept_ = -1;
            if (wasReplan && !replanBase_.empty() && !replanOther_) {
                const auto& now = shown->stage->scene().characters;
                const auto same = [](const std::vector<sim::ActionInstance>& a, const std::vector<sim::ActionInstance>& b) {
                    if (a.size() != b.size()) return false;
                    for (std::size_t i = 0; i < a.size(); ++i)
                        if (a[i].action != b[i].action || a[i].start != b[i].start || a[i].end != b[i].end ||
                            a[i].offset != b[i].offset || a[i].root.pos != b[i].root.pos || a[i].root.heading != b[i].root.heading ||
                            a[i].forced != b[i].forced || a[i].loop != b[i].loop)
                            return false;
                    return true;
                };
                int others = 0, keptCount = 0;
                for (std::size_t c = 0; c < replanBase_.size(); ++c) {
                    if (std::find(replanAffected_.begin(), replanAffected_.end(), static_cast<int>(c)) != replanAffected_.end()) continue;
                    ++others;
                    // Matched by name: a longer or shorter chain renumbers no one else.
                    const auto it = std::find_if(now.begin(), now.end(), [&](const sim::SceneCharacter& x) { return x.name == replanBase_[c].first; });
                    keptCount += it != now.end() && same(replanBase_[c].second, it->track) ? 1 : 0;
                }
                replanOthers_ = others;
                replanKept_ = keptCount;
                kept = QString("; the edits could affect %1 of %2 characters, %3 of the other %4 kept their tracks")
                           .arg(replanAffected_.size())
                           .arg(replanBase_.size())
                           .arg(keptCount)
                           .arg(others);
            }
            replanBase_.clear();
            replanAffected_.clear();
            replanOther_ = false;
            previewSetup_ = specFile.endsWith(".setup") ? currentSetup() : QString();
            showGenerated(std::move(*shown));
            if (!kept.isEmpty()) {
                statusBar()->showMessage(statusBar()->currentMessage() + kept, 15000);
                std::printf("fray: re-plan%s\n", kept.toUtf8().constData());
            }
            lastGenerateSeconds_ = static_cast<double>(clock->elapsed()) / 1000.0;
            std::printf("fray: %s %s in %.2f s", wasReplan ? "re-planned" : "generated",
                        QFileInfo(specFile).fileName().toUtf8().constData(), lastGenerateSeconds_);
            if (lastReplan_)
                std::printf(" (planner: %lld decisions kept, %lld planned, from %.2f s%s)", static_cast<long long>(lastReplan_->decisionsKept),
                            static_cast<long long>(lastReplan_->decisionsPlanned), lastReplan_->resumedAt,
                            lastReplan_->incremental ? "" : (", " + lastReplan_->reason).c_str());
            std::printf("\n");
            std::fflush(stdout);
        });
}

void MainWindow::showGenerated(PreparedPreview generated) {
    const QString summary = generated.summary;
    const sim::SceneMetrics& metrics = generated.metrics;
    scene_ = std::move(generated.stage);
    sceneIsPreview_ = true;
    sceneShownAtFrame_ = viewport_ ? viewport_->framesPresented() : 0;
    selected_ = -1;
    time_ = 0.0;
    scrub_->blockSignals(true);
    scrub_->setRange(0, std::max(0, static_cast<int>(std::ceil(scene_->duration() * kSceneSteps))));
    scrub_->setValue(0);
    scrub_->blockSignals(false);
    if (!playing_) togglePlay();
    previewPins_ = std::move(generated.pins);
    gantt_->setData(std::move(generated.gantt));
    gantt_->setTime(0.0);
    gantt_->setSelectedRow(-1);
    ganttDock_->show();
    ganttDock_->raise();
    // Metrics.
    metricsModel_->clear();
    metricsModel_->setHorizontalHeaderLabels(metricsHeader());
    for (const QStringList& r : metricsRows(metrics)) {
        QList<QStandardItem*> items;
        for (int k = 0; k < r.size(); ++k) {
            auto* item = new QStandardItem;
            bool number = false;
            const double v = r[k].toDouble(&number);
            if (k > 0 && number) item->setData(v, Qt::DisplayRole);
            else item->setText(r[k]);
            items << item;
        }
        metricsModel_->appendRow(items);
    }
    metrics_->resizeColumnsToContents();
    metricsSummary_->setText("Scene: " + metricsSummary(metrics));
    sceneInfo_->setText(summary);
    statusBar()->showMessage("Generated " + summary, 15000);
    frameAll();
    showTime();
    solvePosture();  // physics on: this scene is solved too (a previewed patch included)
}

void MainWindow::stopPreview() {
    if (!scene_ || !sceneIsPreview_) return;
    if (jobThread_) {
        statusBar()->showMessage(jobName_ + " is using the scene: wait for it or Cancel it first", 8000);
        return;
    }
    scene_.reset();
    sceneIsPreview_ = false;
    selected_ = -1;
    gantt_->setData({});
    librarySelectionChanged();
}

void MainWindow::ganttBarClicked(int row, int bar) {
    if (!scene_) return;
    selected_ = row;
    gantt_->setSelectedRow(row);
    if (bar >= 0) {
        const auto& track = scene_->scene().characters[static_cast<std::size_t>(row)].track;
        if (bar < static_cast<int>(track.size())) time_ = track[static_cast<std::size_t>(bar)].start;
        if (playing_) togglePlay();
        gantt_->setTime(time_);
    }
    showTime();
}

// ---- export

void MainWindow::exportScene(const QString& format, double fps, const QString& dir, const QString& name,
                             const ExportExtras& extras) {
    if (!scene_) {
        showError("Export", "There is no scene to export: generate one (Scene > Generate) or open a .frayscene");
        return;
    }
    exporter::ExportOptions options;
    const auto f = exporter::parseFormat(format.toStdString());
    if (!f) {
        showError("Export", "unknown format '" + format + "' (expected " + qs(std::string(exporter::kFormatNames)) + ")");
        return;
    }
    options.format = *f;
    options.outDir = dir.toStdString();
    options.fps = fps;
    options.name = name.toStdString();
    options.source = "fray editor";
    const auto rootMotion = exporter::parseRootMotion(extras.rootMotion.toStdString());
    if (!rootMotion) {
        showError("Export", "root motion: expected none, floor or in-place, got '" + extras.rootMotion + "'");
        return;
    }
    options.rootMotion = *rootMotion;
    if (Status st = exporter::validateOptions(options); !st) {
        showError("Export", qs(st.error().message));
        return;
    }
    if (dir.isEmpty()) {
        showError("Export", "Choose the folder to export into");
        return;
    }
    // The worker reads the scene and the library: a copy of the scene, and
    // no generate can replace the stage while the job runs (one job at a time).
    const cli::SceneStage* stage = scene_.get();
    auto report = std::make_shared<std::optional<Result<exporter::ExportReport>>>();
    startJob(
        "exporting " + format,
        [stage, options, report, rigFile = extras.rig.toStdString(), physics = extras.physics](const ProgressFn& progress) {
            exporter::ExportOptions o = options;
            std::vector<std::string> notes;
            if (!rigFile.empty()) {
                auto rig = loadRigSkeleton(rigFile);
                if (!rig) {
                    report->emplace(Error{"rig: " + rig.error().message, rig.error().kind});
                    return;
                }
                notes = rig->warnings;
                o.rig = std::move(rig->target);
                if (rig->skin) o.rigSkin = std::make_shared<const SkinnedMesh>(std::move(*rig->skin));
            }
            // The posture solver's poses: simulated once here, in the worker (docs/POSTURE.md).
            std::optional<posture::ScenePoses> poses;
            if (physics) {
                auto made = posture::ScenePoses::make(posture::Mode::Physics, stage->scene(), stage->library(), {},
                                                      partOf(progress, 0.0, 0.5));
                if (!made) {
                    report->emplace(made.error());
                    return;
                }
                poses.emplace(std::move(*made));
                o.poses = [&poses](int c, double t, Pose& out) { poses->pose(c, t, out); };
            }
            auto r = exporter::exportScene(stage->scene(), stage->library(), o,
                                           physics ? partOf(progress, 0.5, 1.0) : progress);
            if (r) r->notes.insert(r->notes.begin(), notes.begin(), notes.end());
            report->emplace(std::move(r));
        },
        [this, report, dir] {
            if (!*report || !**report) {
                const bool wasCancelled = *report && (*report)->error().isCancelled();
                if (wasCancelled) statusBar()->showMessage("Export cancelled (files already written stay)", 8000);
                else showError("Export", *report ? qs((*report)->error().message) : QString("no result"));
                return;
            }
            const auto& r = ***report;
            QString msg = QString("Exported %1 files (%2 frames) to %3").arg(r.files.size()).arg(r.frames).arg(dir);
            for (const std::string& n : r.notes) msg += "; " + qs(n);
            statusBar()->showMessage(msg, 15000);
            std::printf("fray: %s\n", msg.toUtf8().constData());
            std::fflush(stdout);
        });
}

void MainWindow::exportDialog() {
    if (!scene_) {
        showError("Export", "There is no scene to export: generate one (Scene > Generate) or open a .frayscene");
        return;
    }
    QDialog dialog(this);
    dialog.setObjectName("exportDialog");
    dialog.setWindowTitle("Export scene");
    auto* form = new QFormLayout(&dialog);
    auto* format = new QComboBox;
    format->setObjectName("exportFormat");
    format->addItem("glTF 2.0 (.gltf, one file, buffer embedded)", "gltf");
    format->addItem("GLB (binary glTF)", "glb");
    format->addItem("BVH (one file per character)", "bvh");
    format->addItem("FBX (binary, centimetres)", "fbx");
    auto* fps = new QDoubleSpinBox;
    fps->setObjectName("exportFps");
    fps->setRange(1, 1000);
    fps->setValue(30);
    fps->setSuffix(" fps");
    auto* dir = new QLineEdit(QFileInfo(projectFile_).absolutePath() + "/export");
    dir->setObjectName("exportDir");
    auto* browse = new QPushButton("...");
    connect(browse, &QPushButton::clicked, &dialog, [&dialog, dir] {
        const QString d = QFileDialog::getExistingDirectory(&dialog, "Export folder", dir->text());
        if (!d.isEmpty()) dir->setText(d);
    });
    auto* dirRow = new QHBoxLayout;
    dirRow->addWidget(dir, 1);
    dirRow->addWidget(browse);
    auto* name = new QLineEdit(sceneSource_->currentIndex() >= 0
                                   ? qs(exporter::fileSafeName(QFileInfo(sceneSource_->currentData().toString()).completeBaseName().toStdString()))
                                   : QString("scene"));
    name->setObjectName("exportName");
    form->addRow("Format", format);
    form->addRow("Frame rate", fps);
    form->addRow("Folder", dirRow);
    form->addRow("File name", name);
    auto* rig = new QLineEdit;
    rig->setObjectName("exportRig");
    rig->setPlaceholderText("none: Fray's capsule bodies on the capture skeleton");
    auto* rigBrowse = new QPushButton("...");
    connect(rigBrowse, &QPushButton::clicked, &dialog, [&dialog, rig] {
        const QString f = QFileDialog::getOpenFileName(&dialog, "Rig to retarget onto", rig->text(),
                                                       "Rigs (*.gltf *.glb *.fbx *.dae *.bvh);;All files (*)");
        if (!f.isEmpty()) rig->setText(f);
    });
    auto* rigRow = new QHBoxLayout;
    rigRow->addWidget(rig, 1);
    rigRow->addWidget(rigBrowse);
    auto* root = new QComboBox;
    root->setObjectName("exportRootMotion");
    root->addItem("none (the hips carry the trajectory)", "none");
    root->addItem("root bone on the floor", "floor");
    root->addItem("in place (root bone at the origin)", "in-place");
    auto* physics = new QCheckBox("Physics posture (the posture solver's poses, docs/POSTURE.md)");
    physics->setObjectName("exportPhysics");
    physics->setChecked(postureMode_ == posture::Mode::Physics);
    form->addRow("Rig", rigRow);
    form->addRow("Root motion", root);
    form->addRow(physics);
    auto* note = new QLabel("A rig is retargeted onto by joint roles, proportions and rest pose, feet kept planted "
                            "(docs/EXPORT.md); its own mesh is not copied: the capsule bodies are skinned to it.");
    note->setWordWrap(true);
    form->addRow(note);
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
    buttons->button(QDialogButtonBox::Ok)->setText("Export");
    form->addRow(buttons);
    connect(buttons, &QDialogButtonBox::accepted, &dialog, &QDialog::accept);
    connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
    if (dialog.exec() != QDialog::Accepted) return;
    ExportExtras extras;
    extras.rig = rig->text().trimmed();
    extras.rootMotion = root->currentData().toString();
    extras.physics = physics->isChecked();
    exportScene(format->currentData().toString(), fps->value(), dir->text(), name->text(), extras);
}

}  // namespace fray::editor
