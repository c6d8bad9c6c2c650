// MainWindow: the open project as a document. Panels read the document's
// project; every gesture that changes it goes through a ProjectDocument
// edit (one undo command); the document's change events refresh the panels.
#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QProgressBar>
#include <QPushButton>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QLineEdit>
#include <QListWidget>
#include <QMenu>
#include <QMessageBox>
#include <QMimeData>
#include <QSettings>
#include <QSignalBlocker>
#include <QSortFilterProxyModel>
#include <QStandardItemModel>
#include <QStatusBar>
#include <QTableView>
#include <QThread>
#include <QTreeWidget>
#include <QUndoStack>
#include <algorithm>
#include <cstdio>

#include "fray/authoring/autosave.h"
#include "fray/authoring/project_document.h"
#include "fray/authoring/recent_files.h"
#include "fray/core/atomic_file.h"
#include "fray/io/import.h"
#include "fray/core/joint_guess.h"
#include "fray/prep/combos.h"
#include "fray/prep/contacts.h"
#include "fray/prep/pipeline.h"
#include "fray/prep/segmentation.h"
#include "fray/prep/annotations.h"
#include "fray/prep/motion_graph.h"
#include "gantt_view.h"
#include "patch_browser.h"
#include "graph_view.h"
#include "inspector_panel.h"
#include "main_window.h"
#include "fray/pipeline/sim_session.h"
#include "timeline_view.h"

namespace fray::editor {

namespace {

QString qs(const std::string& s) { return QString::fromStdString(s); }

bool isMotionFile(const QString& path) {
    const QString ext = QFileInfo(path).suffix().toLower();
    return ext == "bvh" || ext == "fbx" || ext == "gltf" || ext == "glb" || ext == "dae";
}

}  // namespace

const prep::Project* MainWindow::project() const { return doc_ ? &doc_->project() : nullptr; }

int MainWindow::motionIndex(const std::string& id) const {
    const prep::Project* p = project();
    if (!p) return -1;
    for (std::size_t i = 0; i < p->motions.size(); ++i)
        if (p->motions[i].id == id) return static_cast<int>(i);
    return -1;
}

QStringList MainWindow::jointNames(int motion) const {
    QStringList out;
    if (motion < 0 || motion >= static_cast<int>(takes_.size())) return out;
    const Skeleton& sk = takes_[static_cast<std::size_t>(motion)].motion->skeleton();
    for (const std::string& name : sk.names) out << qs(name);
    return out;
}

// ---- opening, saving, importing

bool MainWindow::openDocument(const QString& file) {
    const std::filesystem::path path = file.toStdString();
    std::unique_ptr<authoring::ProjectDocument> doc;
    if (auto recovery = authoring::findRecovery(path)) {
        bool recover = options_.recovery == EditorOptions::Recovery::Recover;
        if (options_.recovery == EditorOptions::Recovery::Ask) {
            recover = QMessageBox::question(this, "Recover unsaved changes?",
                                            QString("%1 has an autosave newer than the project itself (Fray may have "
                                                    "stopped before a save). Recover it?\n\nRecover: open the autosaved "
                                                    "state (the project file stays as it is until you save).\nDiscard: "
                                                    "delete the autosave and open the project.")
                                                .arg(QFileInfo(file).fileName()),
                                            QMessageBox::Yes | QMessageBox::Discard, QMessageBox::Yes) == QMessageBox::Yes;
        }
        if (recover) {
            auto recovered = authoring::recoverDocument(*recovery);
            if (!recovered) {
                showError("Recover", qs(recovered.error().message));
            } else {
                doc = std::move(*recovered);
                statusBar()->showMessage("Recovered the autosave of " + QFileInfo(file).fileName(), 15000);
                std::printf("fray: recovered %s\n", recovery->autosaveFile.string().c_str());
                std::fflush(stdout);
            }
        } else if (Status s = authoring::discardRecovery(*recovery); !s) {
            showError("Recover", qs(s.error().message));
        }
    }
    if (!doc) {
        auto opened = authoring::ProjectDocument::open(path);
        if (!opened) {
            showError("Open", qs(opened.error().message));
            return false;
        }
        doc = std::move(*opened);
    }
    // The takes shown come from the document (a recovered one may differ from the file).
    auto takes = app::loadProjectTakes(doc->project(), path);
    if (!takes) {
        showError("Open", qs(takes.error().message));
        return false;
    }
    takes_ = std::move(*takes);
    delete autosaver_;
    autosaver_ = nullptr;
    doc_ = std::move(doc);
    projectFile_ = file;
    autosaver_ = new authoring::Autosaver(doc_.get(), this);
    autosaver_->setIntervalSeconds(options_.autosaveSeconds >= 0 ? options_.autosaveSeconds
                                                                 : authoring::Autosaver::intervalFromSettings(*settings_));
    connect(autosaver_, &authoring::Autosaver::failed, this, &MainWindow::editFailed);
    connect(doc_.get(), &authoring::ProjectDocument::changed, this, &MainWindow::documentChanged);
    connect(doc_.get(), &authoring::ProjectDocument::dirtyChanged, this, [this] { updateTitle(); });
    connect(doc_.get(), &authoring::ProjectDocument::fileChanged, this, [this](const QString& f) {
        projectFile_ = f;
        updateTitle();
    });
    undoGroupChanged();
    recent_->add(QFileInfo(file).absoluteFilePath());
    fillRecentMenu();
    updateTitle();
    return true;
}

bool MainWindow::openPath(const QString& path) {
    if (!maybeSave()) return false;
    cancelAnalysis();
    if (analysisThread_) analysisThread_->wait();
    if (analysisThread_) analysisFinished();
    analysis_.reset();
    graph_->setData({});
    nodeActions_->clear();
    if (path.endsWith(".frayproj")) {
        if (!openDocument(path)) return false;
    } else {
        auto loaded = app::loadTakes({path.toStdString()});
        if (!loaded) {
            showError("Open", qs(loaded.error().message));
            return false;
        }
        delete autosaver_;
        autosaver_ = nullptr;
        doc_.reset();
        undoGroupChanged();
        takes_ = std::move(*loaded);
        projectFile_.clear();
    }
    updateTitle();
    refreshAll();
    if (library_->topLevelItemCount() > 0) library_->setCurrentItem(library_->topLevelItem(0));
    librarySelectionChanged();
    if (doc_ && !doc_->project().motions.empty()) startAnalysis();
    return true;
}

void MainWindow::openFile() {
    const QString path = QFileDialog::getOpenFileName(
        this, "Open", QFileInfo(projectFile_).absolutePath(),
        "Fray projects and motions (*.frayproj *.bvh *.fbx *.gltf *.glb *.dae);;All files (*)");
    if (!path.isEmpty()) openPath(path);
}

void MainWindow::newProject() {
    const QString path = QFileDialog::getSaveFileName(this, "New project", QFileInfo(projectFile_).absolutePath(),
                                                      "Fray projects (*.frayproj)");
    if (path.isEmpty()) return;
    if (!maybeSave()) return;
    const QString file = path.endsWith(".frayproj") ? path : path + ".frayproj";
    const prep::Project fresh = prep::makeProject(QFileInfo(file).completeBaseName().toStdString());
    if (Status s = prep::saveProject(fresh, file.toStdString()); !s) {
        showError("New project", qs(s.error().message));
        return;
    }
    openPath(file);
}

bool MainWindow::save() {
    if (!doc_) return false;
    if (doc_->filePath().empty()) return saveAs();
    if (Status s = doc_->save(); !s) {
        showError("Save", qs(s.error().message));
        return false;
    }
    if (autosaver_) autosaver_->removeAutosave();
    statusBar()->showMessage("Saved " + projectFile_, 5000);
    return true;
}

bool MainWindow::saveAs() {
    if (!doc_) return false;
    const QString path = QFileDialog::getSaveFileName(this, "Save project as", projectFile_, "Fray projects (*.frayproj)");
    if (path.isEmpty()) return false;
    const QString file = path.endsWith(".frayproj") ? path : path + ".frayproj";
    if (Status s = doc_->saveAs(file.toStdString()); !s) {
        showError("Save As", qs(s.error().message));
        return false;
    }
    recent_->add(QFileInfo(file).absoluteFilePath());
    fillRecentMenu();
    statusBar()->showMessage("Saved " + file, 5000);
    return true;
}

bool MainWindow::maybeSave() {
    if (!doc_ || !doc_->isDirty()) return true;
    if (options_.quitAfter > 0) return true;  // scripted runs never wait for a click
    const auto answer = QMessageBox::warning(
        this, "Unsaved changes", QString("%1 has unsaved changes. Save them?").arg(QFileInfo(projectFile_).fileName()),
        QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
    if (answer == QMessageBox::Cancel) return false;
    if (answer == QMessageBox::Save) return save();
    if (autosaver_) autosaver_->removeAutosave();
    return true;
}

void MainWindow::updateTitle() {
    QString name = projectFile_.isEmpty() ? windowTitle().section(" - Fray", 0, 0).remove("[*]")
                                          : QFileInfo(projectFile_).fileName();
    setWindowTitle(name + "[*] - Fray");
    setWindowModified(doc_ && doc_->isDirty());
    const bool hasDoc = doc_ != nullptr;
    if (saveAction_) saveAction_->setEnabled(hasDoc);
    if (saveAsAction_) saveAsAction_->setEnabled(hasDoc);
    if (importAction_) importAction_->setEnabled(hasDoc);
    if (analyseAction_) analyseAction_->setEnabled(hasDoc);
}

void MainWindow::fillRecentMenu() {
    if (!recentMenu_) return;
    recentMenu_->clear();
    for (const auto& entry : recent_->entries()) {
        QAction* a = recentMenu_->addAction(QFileInfo(entry.path).fileName() + "   " + entry.path);
        a->setEnabled(entry.exists);
        const QString path = entry.path;
        connect(a, &QAction::triggered, this, [this, path] { openPath(path); });
    }
    if (recentMenu_->isEmpty()) recentMenu_->addAction("(none)")->setEnabled(false);
    recentMenu_->addSeparator();
    recentMenu_->addAction("Clear the list", this, [this] {
        recent_->clear();
        fillRecentMenu();
    });
}

void MainWindow::importMotionFiles(const QStringList& files) {
    if (!doc_) {
        statusBar()->showMessage("Open or create a project first (File > New project)", 8000);
        return;
    }
    std::vector<prep::ProjectMotion> entries;
    std::vector<app::LoadedTake> newTakes;
    const std::filesystem::path projectPath = doc_->filePath();
    for (const QString& file : files) {
        auto motion = loadMotion(file.toStdString());
        if (!motion) {
            showError("Import motions", qs(motion.error().message));
            return;
        }
        if (motion->frameCount() == 0) {
            showError("Import motions", file + ": the motion has no frames");
            return;
        }
        prep::ProjectMotion m;
        m.id = QFileInfo(file).completeBaseName().toStdString();
        m.path = prep::relativeMotionPath(projectPath, file.toStdString());
        m.actions = prep::MotionActions::whole(motion->frameCount());
        entries.push_back(std::move(m));
    }
    const std::size_t before = doc_->project().motions.size();
    if (Status s = doc_->importMotions(entries); !s) {
        showError("Import motions", qs(s.error().message));
        return;
    }
    statusBar()->showMessage(QString("Imported %1 motion(s); Analyse (Ctrl+G) to see their profiles and the graph")
                                 .arg(doc_->project().motions.size() - before),
                             10000);
}

void MainWindow::importMotionsDialog() {
    const QStringList files = QFileDialog::getOpenFileNames(this, "Import motions", QFileInfo(projectFile_).absolutePath(),
                                                            "Motions (*.bvh *.fbx *.gltf *.glb *.dae)");
    if (!files.isEmpty()) importMotionFiles(files);
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
    if (!event->mimeData()->hasUrls()) return;
    for (const QUrl& url : event->mimeData()->urls())
        if (url.isLocalFile() && (isMotionFile(url.toLocalFile()) || url.toLocalFile().endsWith(".frayproj"))) {
            event->acceptProposedAction();
            return;
        }
}

bool MainWindow::event(QEvent* event) {
    // QMainWindow keeps drops for its dock layout; files dropped anywhere import.
    if (event->type() == QEvent::DragEnter) {
        dragEnterEvent(static_cast<QDragEnterEvent*>(event));
        return true;
    }
    if (event->type() == QEvent::Drop) {
        dropEvent(static_cast<QDropEvent*>(event));
        return true;
    }
    return QMainWindow::event(event);
}

void MainWindow::dropEvent(QDropEvent* event) {
    QStringList motions;
    for (const QUrl& url : event->mimeData()->urls()) {
        if (!url.isLocalFile()) continue;
        const QString f = url.toLocalFile();
        if (f.endsWith(".frayproj")) {
            openPath(f);
            return;
        }
        if (isMotionFile(f)) motions << f;
    }
    if (!motions.isEmpty()) importMotionFiles(motions);
    event->acceptProposedAction();
}

void MainWindow::segmentCurrentMotion() {
    const prep::Project* p = project();
    if (!doc_ || !p || segmentThread_ || currentMotion_ < 0 || currentMotion_ >= static_cast<int>(p->motions.size()) ||
        currentMotion_ >= static_cast<int>(takes_.size())) {
        statusBar()->showMessage("Select a motion of the project to segment it", 5000);
        return;
    }
    const prep::ProjectMotion entry = p->motions[static_cast<std::size_t>(currentMotion_)];
    std::shared_ptr<const Motion> motion = takes_[static_cast<std::size_t>(currentMotion_)].motion;
    // The analysed contacts (SVM when trained) when they are for this motion; else the heuristic.
    prep::FootContacts contacts;
    if (analysis_)
        for (const MotionAnalysis& a : analysis_->motions)
            if (a.id == entry.id && a.timeline.frameCount == entry.actions.frameCount) {
                contacts.left = a.timeline.contactLeft;
                contacts.right = a.timeline.contactRight;
            }
    const prep::SegmentationParams params = prep::segmentationParams(p->settings);
    segmentMotion_ = entry.id;
    segmentResult_.reset();
    progress_->setRange(0, 0);
    progress_->setFormat("segmenting " + qs(entry.id));
    progress_->show();
    cancelButton_->show();
    segmentThread_ = QThread::create([this, entry, motion, contacts, params] {
        const StandardJoints joints = guessStandardJoints(motion->skeleton());
        auto signals = prep::computeSignals(*motion, joints);
        if (!signals) {
            segmentResult_.emplace(makeError(entry.id + ": " + signals.error().message));
            return;
        }
        const prep::FootContacts used = contacts.frameCount() == signals->frameCount ? contacts : prep::heuristicContacts(*signals);
        const prep::SegmentationResult seg = prep::segment(*signals, used, params);
        prep::MotionActions next = prep::recut(entry.actions, seg.cuts);
        prep::proposeAll(next, *motion, joints, *signals);
        segmentResult_.emplace(std::move(next));
    });
    connect(segmentThread_, &QThread::finished, this, &MainWindow::segmentFinished);
    segmentThread_->start(QThread::LowPriority);
}

void MainWindow::segmentFinished() {
    segmentThread_->deleteLater();
    segmentThread_ = nullptr;
    progress_->setRange(0, 1000);
    if (!analysisThread_) {
        progress_->hide();
        cancelButton_->hide();
    }
    const std::string id = segmentMotion_;
    segmentMotion_.clear();
    if (id.empty() || !segmentResult_ || !doc_) {
        statusBar()->showMessage("Segmentation cancelled", 5000);
        return;
    }
    if (!*segmentResult_) return editFailed(qs(segmentResult_->error().message));
    const int before = doc_->project().findMotion(id) ? doc_->project().findMotion(id)->actions.actionCount() : 0;
    prep::MotionActions next = std::move(segmentResult_->value());
    segmentResult_.reset();
    const int after = next.actionCount();
    if (Status st = doc_->setMotionActions(id, std::move(next), "Segment " + qs(id)); !st) return editFailed(qs(st.error().message));
    statusBar()->showMessage(QString("Segmented %1: %2 actions (was %3); proposals await confirmation in the inspector")
                                 .arg(qs(id))
                                 .arg(after)
                                 .arg(before),
                             10000);
    std::printf("fray: segmented %s: %d actions\n", id.c_str(), after);
    std::fflush(stdout);
}

void MainWindow::showError(const QString& title, const QString& message) {
    // One message naming the file and the problem: a dialog for a person,
    // the status bar and stderr for scripted runs and tests.
    statusBar()->showMessage(message, 30000);
    std::fprintf(stderr, "fray: %s\n", message.toUtf8().constData());
    lastError_ = message;
    if (options_.quitAfter == 0 && !options_.noDialogs) QMessageBox::warning(this, title, message);
}

void MainWindow::editFailed(const QString& message) {
    statusBar()->showMessage(message, 10000);
    std::fprintf(stderr, "fray: %s\n", message.toUtf8().constData());
}

// ---- refreshing the panels from the document

void MainWindow::documentChanged(const authoring::ChangeEvent& event) {
    using authoring::ChangeKind;
    switch (event.kind) {
    case ChangeKind::MotionsAdded: {
        // Load the new takes so they can be shown.
        auto takes = app::loadProjectTakes(doc_->project(), doc_->filePath());
        if (takes) takes_ = std::move(*takes);
        else editFailed(qs(takes.error().message));
        refreshAll();
        break;
    }
    case ChangeKind::MotionsRemoved: {
        auto takes = app::loadProjectTakes(doc_->project(), doc_->filePath());
        if (takes) takes_ = std::move(*takes);
        shown_.clear();
        app::stageTakes(shown_, stage_);
        currentMotion_ = -1;
        refreshAll();
        break;
    }
    case ChangeKind::Cuts:
    case ChangeKind::ContactLabels:
    case ChangeKind::Action:
        if (event.kind != ChangeKind::Action) graphStale_ = true;
        fillLibrary();
        refreshTimeline();
        inspector_->refresh();
        break;
    case ChangeKind::Combos:
        fillCombos();
        break;
    case ChangeKind::PatternLists:
        fillPatterns();
        break;
    case ChangeKind::SetupAdded:
    case ChangeKind::SetupRemoved:
    case ChangeKind::SetupRenamed:
        fillSceneSources();
        break;
    case ChangeKind::SetupPatches:
        rebuildPatchLibrary();  // when the hand-made patches changed
        if (patchBrowser_) patchBrowser_->setRejected(rejectedPatches());
        break;
    case ChangeKind::SetupParameters:
    case ChangeKind::SetupPlacement:
    case ChangeKind::SetupTrajectory:
    case ChangeKind::SetupFloor:
    case ChangeKind::SetupPaths:
    case ChangeKind::SetupPins:
        setupEdited(event);
        break;
    case ChangeKind::Settings:
        refreshAll();
        // A new preset or threshold: rebuild the graph in the background.
        if (!analysisThread_) startAnalysis();
        break;
    default:
        refreshAll();
        break;
    }
    if (graphStale_ && analysis_)
        graph_->setToolTip("Out of date after edits: Project > Analyse (Ctrl+G) rebuilds it");
}

void MainWindow::refreshAll() {
    if (const prep::Project* p = project()) {
        fillingGraphControls_ = true;
        graphPreset_->setCurrentText(qs(p->settings.graphPreset));
        graphThreshold_->setValue(p->settings.graphThreshold.value_or(prep::GraphOptions{}.threshold));
        fillingGraphControls_ = false;
    }
    fillLibrary();
    refreshTimeline();
    fillCombos();
    fillPatterns();
    fillSceneSources();
    if (currentMotion_ >= 0 && currentAction_ >= 0) showAction(currentMotion_, currentAction_);
    else showMotion(currentMotion_);
}

void MainWindow::refreshTimeline() {
    const prep::Project* p = project();
    if (!p || currentMotion_ < 0 || currentMotion_ >= static_cast<int>(p->motions.size())) {
        timeline_->setData({});
        timelineDock_->setWindowTitle("Timeline");
        return;
    }
    const prep::ProjectMotion& pm = p->motions[static_cast<std::size_t>(currentMotion_)];
    TimelineData t;
    // The profile and contacts from the analysis (when it has this motion),
    // cuts, names and labels from the document as they are now.
    if (analysis_) {
        for (const MotionAnalysis& a : analysis_->motions)
            if (a.id == pm.id && a.timeline.frameCount == pm.actions.frameCount) t = a.timeline;
    }
    t.frameCount = pm.actions.frameCount;
    if (currentMotion_ < static_cast<int>(takes_.size())) t.fps = takes_[static_cast<std::size_t>(currentMotion_)].motion->fps();
    t.cuts = pm.actions.cuts;
    t.actionNames.clear();
    for (const prep::ActionInfo& info : pm.actions.actions) t.actionNames.push_back(actionLabel(info));
    t.labels.clear();
    for (const prep::ContactLabel& l : pm.contactLabels) t.labels.push_back({l.firstFrame, l.lastFrame, l.left, l.right});
    timeline_->setData(std::move(t));
    timelineDock_->setWindowTitle("Timeline: " + qs(pm.id));
}

void MainWindow::fillLibrary() {
    // Refilling never changes what is selected: the current motion (or action) stays selected.
    const QSignalBlocker quiet(library_);
    library_->clear();
    if (scene_ && !sceneIsPreview_) {
        for (int c = 0; c < scene_->characterCount(); ++c) {
            const glm::vec3 tint = scene_->tint(c);
            QPixmap swatch(12, 12);
            swatch.fill(QColor::fromRgbF(tint.x, tint.y, tint.z));
            auto* item = new QTreeWidgetItem({qs(scene_->scene().characters[static_cast<std::size_t>(c)].name)});
            item->setIcon(0, QIcon(swatch));
            item->setData(0, kRoleMotion, c);
            library_->addTopLevelItem(item);
        }
        return;
    }
    const prep::Project* p = project();
    for (std::size_t i = 0; i < takes_.size(); ++i) {
        const app::LoadedTake& t = takes_[i];
        auto* item = new QTreeWidgetItem(
            {qs(t.name), QString("%1 (%2 s)").arg(t.motion->frameCount()).arg(t.motion->duration(), 0, 'f', 1)});
        item->setData(0, kRoleMotion, static_cast<int>(i));
        item->setData(0, kRoleAction, -1);
        if (p && i < p->motions.size()) {
            const prep::MotionActions& acts = p->motions[i].actions;
            for (int a = 0; a < acts.actionCount(); ++a) {
                const prep::ActionInfo& info = acts.actions[static_cast<std::size_t>(a)];
                QStringList words;
                for (const std::string& w : info.annotations) words << qs(w);
                for (const std::string& w : info.proposed) words << qs(w) + "?";
                auto* child = new QTreeWidgetItem(
                    {actionLabel(info), QString("%1-%2").arg(acts.firstFrame(a)).arg(acts.lastFrame(a)), words.join(" ")});
                child->setData(0, kRoleMotion, static_cast<int>(i));
                child->setData(0, kRoleAction, a);
                item->addChild(child);
            }
            item->setText(2, QString("%1 actions").arg(acts.actionCount()));
        }
        library_->addTopLevelItem(item);
        if (static_cast<int>(i) == currentMotion_) {
            item->setExpanded(true);
            QTreeWidgetItem* selected = currentAction_ >= 0 && currentAction_ < item->childCount() ? item->child(currentAction_) : item;
            selected->setSelected(true);
            library_->setCurrentItem(selected, 0, QItemSelectionModel::NoUpdate);
        }
    }
    library_->resizeColumnToContents(0);
    filterLibrary(libraryFilter_->text());
}

void MainWindow::filterLibrary(const QString& text) {
    const QString needle = text.trimmed();
    for (int i = 0; i < library_->topLevelItemCount(); ++i) {
        QTreeWidgetItem* top = library_->topLevelItem(i);
        bool any = needle.isEmpty() || top->text(0).contains(needle, Qt::CaseInsensitive);
        for (int k = 0; k < top->childCount(); ++k) {
            QTreeWidgetItem* child = top->child(k);
            const bool match = needle.isEmpty() || child->text(0).contains(needle, Qt::CaseInsensitive) ||
                               child->text(2).contains(needle, Qt::CaseInsensitive);
            child->setHidden(!match);
            any = any || match;
        }
        top->setHidden(!any);
        if (!needle.isEmpty() && any && top->childCount() > 0) top->setExpanded(true);
    }
}

void MainWindow::librarySelectionChanged() {
    const auto rows = library_->selectedItems();
    if (scene_ && sceneIsPreview_ && !rows.empty() && !jobThread_) {
        // Picking a motion ends the preview of a generated scene.
        scene_.reset();
        sceneIsPreview_ = false;
        selected_ = -1;
        gantt_->setData({});
    }
    if (scene_ && !sceneIsPreview_) {
        // Selecting a character highlights it; the time keeps running.
        selected_ = rows.empty() ? -1 : rows.front()->data(0, kRoleMotion).toInt();
        return;
    }
    // An action: its motion alone, from the action's first frame.
    if (rows.size() == 1 && rows.front()->data(0, kRoleAction).toInt() >= 0) {
        showAction(rows.front()->data(0, kRoleMotion).toInt(), rows.front()->data(0, kRoleAction).toInt());
        return;
    }
    shown_.clear();
    int first = -1;
    for (QTreeWidgetItem* item : rows) {
        const int m = item->data(0, kRoleMotion).toInt();
        if (item->data(0, kRoleAction).toInt() >= 0 || m < 0 || m >= static_cast<int>(takes_.size())) continue;
        if (first < 0) first = m;
        shown_.push_back(takes_[static_cast<std::size_t>(m)]);
    }
    app::stageTakes(shown_, stage_);
    time_ = 0.0;
    stage_.pose(0.0);
    scrub_->blockSignals(true);
    scrub_->setRange(0, std::max(0, stage_.longestFrameCount() - 1));
    scrub_->setValue(0);
    scrub_->blockSignals(false);
    showMotion(first);
    frameAll();
}

void MainWindow::showMotion(int motion) {
    currentMotion_ = motion;
    currentAction_ = -1;
    refreshTimeline();
    timeline_->setSelectedAction(-1);
    const prep::Project* p = project();
    if (!p || motion < 0 || motion >= static_cast<int>(p->motions.size())) {
        inspector_->clear(projectFile_.isEmpty() ? "Open a project (File > Open) to annotate its actions."
                                                 : "Select a motion or an action in the library.");
        return;
    }
    const prep::ProjectMotion& pm = p->motions[static_cast<std::size_t>(motion)];
    inspector_->clear(QString("%1: %2 actions, %3 frames. Select an action in the library or the timeline.")
                          .arg(qs(pm.id))
                          .arg(pm.actions.actionCount())
                          .arg(pm.actions.frameCount));
}

void MainWindow::showAction(int motion, int action) {
    const prep::Project* p = project();
    if (!p || motion < 0 || motion >= static_cast<int>(p->motions.size())) return;
    const prep::MotionActions& acts = p->motions[static_cast<std::size_t>(motion)].actions;
    if (action < 0 || action >= acts.actionCount()) return;
    if (motion != currentMotion_ || shown_.size() != 1) {
        shown_ = {takes_[static_cast<std::size_t>(motion)]};
        app::stageTakes(shown_, stage_);
        scrub_->blockSignals(true);
        scrub_->setRange(0, std::max(0, stage_.longestFrameCount() - 1));
        scrub_->blockSignals(false);
        showMotion(motion);
        frameAll();
    }
    currentAction_ = action;
    timeline_->setSelectedAction(action);
    const int first = acts.firstFrame(action);
    timelinePlayhead(first);
    timeline_->setPlayhead(first);

    const double fps = takes_[static_cast<std::size_t>(motion)].motion->fps();
    QString context = QString("%1, action %2: frames %3-%4 (%5 s)")
                          .arg(qs(p->motions[static_cast<std::size_t>(motion)].id))
                          .arg(action)
                          .arg(first)
                          .arg(acts.lastFrame(action))
                          .arg((acts.lastFrame(action) - first + 1) / fps, 0, 'f', 2);
    // Where the action sits in the motion graph (when the graph is current).
    if (analysis_ && !graphStale_) {
        int g = 0;
        for (int m = 0; m < motion; ++m) g += p->motions[static_cast<std::size_t>(m)].actions.actionCount();
        g += action;
        if (g < static_cast<int>(analysis_->graph.startNode.size())) {
            context += QString("\nmotion graph: node %1 to node %2").arg(analysis_->graph.startNode[g]).arg(analysis_->graph.endNode[g]);
            if (g < static_cast<int>(analysis_->graph.inLargestScc.size()) && !analysis_->graph.inLargestScc[g])
                context += " (outside the largest strongly connected set)";
        }
    }
    inspector_->showAction(doc_.get(), p->motions[static_cast<std::size_t>(motion)].id, action, jointNames(motion), context);
}

void MainWindow::graphNodeSelected(int node) {
    nodeActions_->clear();
    if (!analysis_) return;
    const prep::Project& p = analysis_->project;
    for (std::size_t g = 0; g < analysis_->graph.startNode.size() && g < analysis_->graphActions.size(); ++g) {
        if (analysis_->graph.startNode[g] != node) continue;
        const auto [m, a] = analysis_->graphActions[g];
        const prep::ProjectMotion& pm = p.motions[static_cast<std::size_t>(m)];
        auto* item = new QListWidgetItem(QString("%1  %2 #%3  -> node %4")
                                             .arg(actionLabel(pm.actions.actions[static_cast<std::size_t>(a)]))
                                             .arg(qs(pm.id))
                                             .arg(a)
                                             .arg(analysis_->graph.endNode[g]));
        item->setData(kRoleMotion, motionIndex(pm.id));
        item->setData(kRoleAction, a);
        nodeActions_->addItem(item);
    }
}

// ---- the combination table: the model pushes commands

void MainWindow::fillCombos() {
    fillingCombos_ = true;
    combosModel_->removeRows(0, combosModel_->rowCount());
    if (const prep::Project* p = project()) {
        for (const prep::ComboRecord& r : p->combos.records()) {
            auto* mine = new QStandardItem(qs(r.mine));
            auto* theirs = new QStandardItem(qs(r.theirs));
            mine->setEditable(false);
            theirs->setEditable(false);
            auto* value = new QStandardItem;
            value->setData(r.suitability, Qt::DisplayRole);
            value->setToolTip("Double-click to edit: > 0 encourages, < 0 discourages");
            combosModel_->appendRow({mine, theirs, value});
        }
    }
    combosDock_->setWindowTitle(QString("Combination table (%1)").arg(combosModel_->rowCount()));
    fillingCombos_ = false;
}

void MainWindow::addComboRecord() {
    if (!doc_) return;
    bool ok = false;
    const QString text = QInputDialog::getText(this, "Add a record",
                                               "mine, theirs, suitability (names or @annotations), e.g. jab, @block, -1",
                                               QLineEdit::Normal, "", &ok);
    if (!ok || text.trimmed().isEmpty()) return;
    const QStringList parts = text.split(',');
    bool number = false;
    const double value = parts.size() == 3 ? parts[2].trimmed().toDouble(&number) : 0.0;
    if (parts.size() != 3 || !number) {
        editFailed("a record is three fields: mine, theirs, suitability (a number)");
        return;
    }
    const Status s = doc_->setComboRecord({parts[0].trimmed().toStdString(), parts[1].trimmed().toStdString(), value});
    if (!s) editFailed(qs(s.error().message));
}

void MainWindow::removeComboRecords() {
    if (!doc_) return;
    const auto rows = combos_->selectionModel()->selectedRows();
    if (rows.isEmpty()) return;
    std::vector<std::pair<std::string, std::string>> keys;
    for (const QModelIndex& proxy : rows) {
        const QModelIndex row = combosProxy_->mapToSource(proxy);
        keys.emplace_back(combosModel_->item(row.row(), 0)->text().toStdString(),
                          combosModel_->item(row.row(), 1)->text().toStdString());
    }
    doc_->undoStack()->beginMacro(QString("Remove %1 combination record(s)").arg(keys.size()));
    for (const auto& [mine, theirs] : keys)
        if (Status s = doc_->removeComboRecord(mine, theirs); !s) editFailed(qs(s.error().message));
    doc_->undoStack()->endMacro();
}

void MainWindow::importCombos() {
    if (!doc_) return;
    const QString file = QFileDialog::getOpenFileName(this, "Import a combination table", QFileInfo(projectFile_).absolutePath(),
                                                      "CSV (*.csv)");
    if (file.isEmpty()) return;
    auto text = readWholeFile(file.toStdString(), "the combination table");
    if (!text) return editFailed(qs(text.error().message));
    auto table = prep::ComboTable::fromCsv(*text, file.toStdString());
    if (!table) return editFailed(qs(table.error().message));
    doc_->undoStack()->beginMacro(QString("Import %1 combination record(s)").arg(table->records().size()));
    for (const prep::ComboRecord& r : table->records())
        if (Status s = doc_->setComboRecord(r); !s) {
            editFailed(qs(s.error().message));
            break;
        }
    doc_->undoStack()->endMacro();
}

void MainWindow::exportCombos() {
    if (!project()) return;
    const QString file = QFileDialog::getSaveFileName(this, "Export the combination table", QFileInfo(projectFile_).absolutePath(),
                                                      "CSV (*.csv)");
    if (file.isEmpty()) return;
    if (Status s = writeFileAtomically(file.toStdString(), project()->combos.toCsv()); !s) editFailed(qs(s.error().message));
}

}  // namespace fray::editor
