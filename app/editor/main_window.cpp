#include "main_window.h"

#include <QApplication>
#include <QCloseEvent>
#include <QComboBox>
#include <QDockWidget>
#include <QFileInfo>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QImage>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QMenuBar>
#include <QMessageBox>
#include <QPainter>
#include <QPixmap>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QSlider>
#include <QSortFilterProxyModel>
#include <QStandardItemModel>
#include <QStatusBar>
#include <QStyle>
#include <QTableView>
#include <QTextBrowser>
#include <QThread>
#include <QToolButton>
#include <QTreeWidget>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fray/render/image.h"
#include "graph_view.h"
#include "timeline_view.h"
#include "viewport.h"

namespace fray::editor {

namespace {

// Bumped when the docks change, so an old saved layout is not restored onto them.
constexpr int kLayoutVersion = 1;
constexpr int kRoleMotion = Qt::UserRole + 1;
constexpr int kRoleAction = Qt::UserRole + 2;

QString html(const std::string& s) { return QString::fromStdString(s).toHtmlEscaped(); }

QString joined(const std::vector<std::string>& words, const char* empty = "none") {
    if (words.empty()) return QString("<i>%1</i>").arg(empty);
    QStringList out;
    for (const std::string& w : words) out << html(w);
    return out.join(", ");
}

// Annotations as chips: small rounded labels (the inspector is rich text).
QString chips(const std::vector<std::string>& words, const char* colour) {
    if (words.empty()) return "<i>none</i>";
    QString out;
    for (const std::string& w : words)
        out += QString("<span style='background:%1; color:#111; border-radius:6px;'>&nbsp;%2&nbsp;</span> ")
                   .arg(colour, html(w));
    return out;
}

}  // namespace

MainWindow::MainWindow(Viewport* viewport, std::vector<app::LoadedTake> takes, std::unique_ptr<cli::SceneStage> scene,
                       QString projectFile, QString title, EditorOptions options)
    : viewport_(viewport),
      takes_(std::move(takes)),
      scene_(std::move(scene)),
      projectFile_(std::move(projectFile)),
      options_(std::move(options)) {
    setWindowTitle(title + " - Fray");
    setObjectName("MainWindow");
    setDockNestingEnabled(true);

    if (viewport_) {
        viewportContainer_ = QWidget::createWindowContainer(viewport_);
    } else {
        auto* placeholder = new QLabel("viewport (Vulkan)");
        placeholder->setAlignment(Qt::AlignCenter);
        viewportContainer_ = placeholder;
    }
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

    auto* central = new QWidget;
    auto* centralLayout = new QVBoxLayout(central);
    centralLayout->setContentsMargins(0, 0, 0, 0);
    centralLayout->addWidget(viewportContainer_, 1);
    centralLayout->addLayout(transport);
    setCentralWidget(central);

    statsLabel_ = new QLabel;
    progress_ = new QProgressBar;
    progress_->setRange(0, 1000);
    progress_->setMaximumWidth(260);
    progress_->setTextVisible(true);
    progress_->hide();
    cancelButton_ = new QPushButton("Cancel");
    cancelButton_->setToolTip("Stop the analysis (the panels stay empty until it runs again)");
    cancelButton_->hide();
    statusBar()->addPermanentWidget(progress_);
    statusBar()->addPermanentWidget(cancelButton_);
    statusBar()->addPermanentWidget(statsLabel_);
    resize(1400, 880);

    buildDocks();
    buildMenus();
    fillLibrary();
    defaultLayout_ = saveState(kLayoutVersion);
    if (options_.restoreLayout) {
        QSettings settings;
        restoreGeometry(settings.value("window/geometry").toByteArray());
        restoreState(settings.value("window/state").toByteArray(), kLayoutVersion);
    }

    connect(playButton_, &QToolButton::clicked, this, &MainWindow::togglePlay);
    connect(scrub_, &QSlider::valueChanged, this, &MainWindow::scrubbed);
    connect(cancelButton_, &QPushButton::clicked, this, &MainWindow::cancelAnalysis);
    if (viewport_) connect(viewport_, &Viewport::frameAllRequested, this, &MainWindow::frameAll);
    connect(&timer_, &QTimer::timeout, this, &MainWindow::tick);

    if (scene_) {
        scrub_->setRange(0, std::max(0, static_cast<int>(std::ceil(scene_->duration() * kSceneSteps))));
        frameAll();
    } else {
        if (library_->topLevelItemCount() > 0) library_->setCurrentItem(library_->topLevelItem(0));
        librarySelectionChanged();
    }
    if (!projectFile_.isEmpty()) startAnalysis();
    last_ = std::chrono::steady_clock::now();
    if (viewport_) timer_.start(options_.quitAfter > 0 ? 0 : 15);
}

MainWindow::~MainWindow() {
    cancelAnalysis();
    if (analysisThread_) analysisThread_->wait();
}

void MainWindow::buildDocks() {
    const auto dock = [&](const char* name, const QString& title, QWidget* content, Qt::DockWidgetArea area) {
        auto* d = new QDockWidget(title, this);
        d->setObjectName(name);
        d->setWidget(content);
        addDockWidget(area, d);
        return d;
    };

    // Library.
    auto* libraryPanel = new QWidget;
    libraryPanel->setObjectName("libraryPanel");
    auto* libraryLayout = new QVBoxLayout(libraryPanel);
    libraryLayout->setContentsMargins(2, 2, 2, 2);
    libraryFilter_ = new QLineEdit;
    libraryFilter_->setObjectName("libraryFilter");
    libraryFilter_->setPlaceholderText(scene_ ? "Filter characters" : "Filter by annotation or name");
    libraryFilter_->setClearButtonEnabled(true);
    library_ = new QTreeWidget;
    library_->setObjectName("library");
    library_->setHeaderLabels({scene_ ? "Character" : "Motion / action", "Frames", "Annotations"});
    library_->setSelectionMode(scene_ ? QAbstractItemView::SingleSelection : QAbstractItemView::ExtendedSelection);
    library_->setToolTip(scene_ ? "Select a character to highlight it; F frames it, F with none selected frames everyone"
                                : "Select motions to play them side by side; select an action to jump to it");
    library_->header()->setStretchLastSection(true);
    libraryLayout->addWidget(libraryFilter_);
    libraryLayout->addWidget(library_, 1);
    libraryDock_ = dock("LibraryDock", scene_ ? "Characters" : "Library", libraryPanel, Qt::LeftDockWidgetArea);
    connect(library_, &QTreeWidget::itemSelectionChanged, this, &MainWindow::librarySelectionChanged);
    connect(libraryFilter_, &QLineEdit::textChanged, this, &MainWindow::filterLibrary);

    // Timeline.
    timeline_ = new TimelineView;
    timeline_->setObjectName("timeline");
    timelineDock_ = dock("TimelineDock", "Timeline", timeline_, Qt::BottomDockWidgetArea);
    connect(timeline_, &TimelineView::playheadRequested, this, &MainWindow::timelinePlayhead);
    connect(timeline_, &TimelineView::playToggled, this, &MainWindow::togglePlay);
    connect(timeline_, &TimelineView::actionSelected, this, [this](int action) {
        if (currentMotion_ >= 0) showAction(currentMotion_, action);
    });

    // Combination table, tabbed with the timeline.
    auto* combosPanel = new QWidget;
    combosPanel->setObjectName("combosPanel");
    auto* combosLayout = new QVBoxLayout(combosPanel);
    combosLayout->setContentsMargins(2, 2, 2, 2);
    combosFilter_ = new QLineEdit;
    combosFilter_->setObjectName("combosFilter");
    combosFilter_->setPlaceholderText("Filter records (mine or theirs)");
    combosFilter_->setClearButtonEnabled(true);
    combosModel_ = new QStandardItemModel(0, 3, this);
    combosModel_->setHorizontalHeaderLabels({"Mine", "Theirs", "Suitability"});
    combosProxy_ = new QSortFilterProxyModel(this);
    combosProxy_->setSourceModel(combosModel_);
    combosProxy_->setFilterKeyColumn(-1);
    combosProxy_->setFilterCaseSensitivity(Qt::CaseInsensitive);
    combos_ = new QTableView;
    combos_->setObjectName("combos");
    combos_->setModel(combosProxy_);
    combos_->setSortingEnabled(true);
    combos_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    combos_->horizontalHeader()->setStretchLastSection(true);
    combos_->verticalHeader()->hide();
    combosLayout->addWidget(combosFilter_);
    combosLayout->addWidget(combos_, 1);
    combosDock_ = dock("CombosDock", "Combination table", combosPanel, Qt::BottomDockWidgetArea);
    tabifyDockWidget(timelineDock_, combosDock_);
    timelineDock_->raise();
    connect(combosFilter_, &QLineEdit::textChanged, combosProxy_, &QSortFilterProxyModel::setFilterFixedString);

    // Inspector and motion graph, tabbed on the right.
    inspector_ = new QTextBrowser;
    inspector_->setObjectName("inspector");
    inspector_->setOpenLinks(false);
    inspectorDock_ = dock("InspectorDock", "Inspector", inspector_, Qt::RightDockWidgetArea);

    auto* graphPanel = new QWidget;
    graphPanel->setObjectName("graphPanel");
    auto* graphLayout = new QVBoxLayout(graphPanel);
    graphLayout->setContentsMargins(2, 2, 2, 2);
    graph_ = new GraphView;
    graph_->setObjectName("graph");
    nodeActions_ = new QListWidget;
    nodeActions_->setObjectName("nodeActions");
    nodeActions_->setToolTip("Actions leaving the selected node (click one to select it)");
    nodeActions_->setMaximumHeight(150);
    graphLayout->addWidget(graph_, 1);
    graphLayout->addWidget(nodeActions_);
    graphDock_ = dock("GraphDock", "Motion graph", graphPanel, Qt::RightDockWidgetArea);
    tabifyDockWidget(inspectorDock_, graphDock_);
    inspectorDock_->raise();
    connect(graph_, &GraphView::nodeSelected, this, &MainWindow::graphNodeSelected);
    connect(nodeActions_, &QListWidget::itemClicked, this, [this](QListWidgetItem* item) {
        showAction(item->data(kRoleMotion).toInt(), item->data(kRoleAction).toInt());
    });

    resizeDocks({libraryDock_}, {280}, Qt::Horizontal);
    resizeDocks({inspectorDock_}, {360}, Qt::Horizontal);
    resizeDocks({timelineDock_}, {210}, Qt::Vertical);
}

void MainWindow::buildMenus() {
    QMenu* file = menuBar()->addMenu("&File");
    file->setObjectName("FileMenu");
    QAction* open = file->addAction("&Open...", this, &MainWindow::openFile);
    open->setObjectName("actionOpen");
    open->setShortcut(QKeySequence::Open);
    file->addSeparator();
    QAction* quit = file->addAction("&Quit", this, &QWidget::close);
    quit->setObjectName("actionQuit");
    quit->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_Q));

    QMenu* view = menuBar()->addMenu("&View");
    view->setObjectName("ViewMenu");
    for (QDockWidget* d : {libraryDock_, timelineDock_, inspectorDock_, graphDock_, combosDock_}) {
        QAction* toggle = d->toggleViewAction();
        toggle->setObjectName("toggle" + d->objectName());
        view->addAction(toggle);
    }
    view->addSeparator();
    QAction* frame = view->addAction("&Frame all", this, &MainWindow::frameAll);
    frame->setObjectName("actionFrameAll");
    frame->setShortcut(Qt::Key_F);
    QAction* reset = view->addAction("&Reset layout", this, &MainWindow::resetLayout);
    reset->setObjectName("actionResetLayout");

    QMenu* help = menuBar()->addMenu("&Help");
    help->setObjectName("HelpMenu");
    QAction* keys = help->addAction("&Keyboard shortcuts", this, &MainWindow::showShortcuts);
    keys->setObjectName("actionShortcuts");
    QAction* about = help->addAction("&About Fray", this, [this] {
        QMessageBox::about(this, "About Fray",
                           "Fray turns single-actor motion captures into scenes of many interacting characters "
                           "(after H. P. H. Shum, Simulating Interactions Among Multiple Characters).");
    });
    about->setObjectName("actionAbout");
}

QByteArray MainWindow::describeUi() const {
    QJsonObject root;
    root["window"] = windowTitle();
    QJsonArray docks;
    QList<QDockWidget*> all = findChildren<QDockWidget*>();
    std::sort(all.begin(), all.end(), [](QDockWidget* a, QDockWidget* b) { return a->objectName() < b->objectName(); });
    for (QDockWidget* d : all) {
        QJsonObject o;
        o["name"] = d->objectName();
        o["title"] = d->windowTitle();
        const Qt::DockWidgetArea area = dockWidgetArea(d);
        o["area"] = area == Qt::LeftDockWidgetArea     ? "left"
                    : area == Qt::RightDockWidgetArea  ? "right"
                    : area == Qt::TopDockWidgetArea    ? "top"
                    : area == Qt::BottomDockWidgetArea ? "bottom"
                                                       : "none";
        o["panel"] = d->widget() ? d->widget()->objectName() : "";
        o["visible"] = !d->isHidden();
        docks.append(o);
    }
    root["docks"] = docks;
    QJsonArray menus;
    for (QAction* top : menuBar()->actions()) {
        QMenu* menu = top->menu();
        if (!menu) continue;
        QJsonObject m;
        m["title"] = menu->title().remove('&');
        QJsonArray actions;
        for (QAction* a : menu->actions()) {
            if (a->isSeparator()) continue;
            QJsonObject o;
            o["name"] = a->objectName();
            o["text"] = a->text().remove('&');
            o["shortcut"] = a->shortcut().toString(QKeySequence::PortableText);
            o["checkable"] = a->isCheckable();
            actions.append(o);
        }
        m["actions"] = actions;
        menus.append(m);
    }
    root["menus"] = menus;
    return QJsonDocument(root).toJson(QJsonDocument::Indented);
}

void MainWindow::closeEvent(QCloseEvent* event) {
    QSettings settings;
    settings.setValue("window/geometry", saveGeometry());
    settings.setValue("window/state", saveState(kLayoutVersion));
    QMainWindow::closeEvent(event);
}

void MainWindow::resetLayout() { restoreState(defaultLayout_, kLayoutVersion); }

void MainWindow::showShortcuts() {
    QMessageBox::information(
        this, "Keyboard shortcuts",
        "Space: play / pause\nLeft / Right: one frame (timeline)\nUp / Down: ten frames (timeline)\n"
        "Home: frame the whole motion (timeline)\nF: frame all (viewport)\nDelete: remove the cut under the playhead "
        "(timeline)\nCtrl+O: open\nCtrl+Q: quit");
}

void MainWindow::fillLibrary() {
    library_->clear();
    if (scene_) {
        for (int c = 0; c < scene_->characterCount(); ++c) {
            const glm::vec3 tint = scene_->tint(c);
            QPixmap swatch(12, 12);
            swatch.fill(QColor::fromRgbF(tint.x, tint.y, tint.z));
            auto* item = new QTreeWidgetItem(
                {QString::fromStdString(scene_->scene().characters[static_cast<std::size_t>(c)].name)});
            item->setIcon(0, QIcon(swatch));
            item->setData(0, kRoleMotion, c);
            library_->addTopLevelItem(item);
        }
        return;
    }
    const prep::Project* project = analysis_ ? &analysis_->project : nullptr;
    for (std::size_t i = 0; i < takes_.size(); ++i) {
        const app::LoadedTake& t = takes_[i];
        auto* item = new QTreeWidgetItem({QString::fromStdString(t.name),
                                          QString("%1 (%2 s)").arg(t.motion->frameCount()).arg(t.motion->duration(), 0, 'f', 1)});
        item->setData(0, kRoleMotion, static_cast<int>(i));
        item->setData(0, kRoleAction, -1);
        if (project && i < project->motions.size()) {
            const prep::MotionActions& acts = project->motions[i].actions;
            for (int a = 0; a < acts.actionCount(); ++a) {
                const prep::ActionInfo& info = acts.actions[static_cast<std::size_t>(a)];
                QStringList words;
                for (const std::string& w : info.annotations) words << QString::fromStdString(w);
                for (const std::string& w : info.proposed) words << QString::fromStdString(w) + "?";
                auto* child = new QTreeWidgetItem(
                    {actionLabel(info), QString("%1-%2").arg(acts.firstFrame(a)).arg(acts.lastFrame(a)), words.join(" ")});
                child->setData(0, kRoleMotion, static_cast<int>(i));
                child->setData(0, kRoleAction, a);
                item->addChild(child);
            }
            item->setText(2, QString("%1 actions").arg(acts.actionCount()));
        }
        library_->addTopLevelItem(item);
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
    if (scene_) {
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
    if (analysis_ && motion >= 0 && motion < static_cast<int>(analysis_->motions.size())) {
        timeline_->setData(analysis_->motions[static_cast<std::size_t>(motion)].timeline);
        timelineDock_->setWindowTitle("Timeline: " + QString::fromStdString(analysis_->motions[static_cast<std::size_t>(motion)].id));
    } else {
        timeline_->setData({});
        timelineDock_->setWindowTitle("Timeline");
    }
    timeline_->setSelectedAction(-1);
    if (!analysis_ || motion < 0) {
        inspector_->setHtml(projectFile_.isEmpty()
                                ? "<p>Open a project (File &gt; Open) to see actions and their annotations.</p>"
                                : "<p>Analysing the project...</p>");
        return;
    }
    const prep::ProjectMotion& pm = analysis_->project.motions[static_cast<std::size_t>(motion)];
    inspector_->setHtml(QString("<h3>%1</h3><p>%2 actions, %3 frames, %4 cuts<br>%5</p><p>Select an action in the "
                                "library or the timeline.</p>")
                            .arg(html(pm.id))
                            .arg(pm.actions.actionCount())
                            .arg(pm.actions.frameCount)
                            .arg(pm.actions.cuts.size())
                            .arg(html(pm.path)));
}

void MainWindow::showAction(int motion, int action) {
    if (!analysis_ || motion < 0 || motion >= static_cast<int>(analysis_->project.motions.size())) return;
    const prep::MotionActions& acts = analysis_->project.motions[static_cast<std::size_t>(motion)].actions;
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

    const prep::ActionInfo& info = acts.actions[static_cast<std::size_t>(action)];
    const double fps = takes_[static_cast<std::size_t>(motion)].motion->fps();
    QString body = QString("<h3>%1</h3><p>%2, action %3: frames %4-%5 (%6 s)</p>")
                       .arg(info.name.empty() ? QString("<i>unnamed</i>") : html(info.name))
                       .arg(html(analysis_->project.motions[static_cast<std::size_t>(motion)].id))
                       .arg(action)
                       .arg(first)
                       .arg(acts.lastFrame(action))
                       .arg((acts.lastFrame(action) - first + 1) / fps, 0, 'f', 2);
    body += "<p><b>Annotations</b><br>" + chips(info.annotations, "#9cc3f0") + "</p>";
    body += "<p><b>Proposals</b> (awaiting confirmation)<br>" + chips(info.proposed, "#f0d79c") + "</p>";
    body += "<p><b>Joints used</b><br>" + joined(info.joints) + "</p>";
    body += "<p><b>Attack direction</b>: " + (info.attackDirection ? html(*info.attackDirection) : QString("<i>none</i>")) +
            "<br><b>Defended part</b>: " + (info.defendedPart ? html(*info.defendedPart) : QString("<i>none</i>")) + "</p>";
    if (info.initialConditions) {
        const prep::InitialConditions& ic = *info.initialConditions;
        const double deg = 180.0 / 3.14159265358979323846;
        body += QString("<p><b>Initial conditions</b><br>distance %1-%2 m<br>angle %3-%4 deg<br>facing %5-%6 deg<br>"
                        "timing %7-%8 s</p>")
                    .arg(ic.minDistance, 0, 'f', 2)
                    .arg(ic.maxDistance, 0, 'f', 2)
                    .arg(ic.minAngle * deg, 0, 'f', 0)
                    .arg(ic.maxAngle * deg, 0, 'f', 0)
                    .arg(ic.minFacing * deg, 0, 'f', 0)
                    .arg(ic.maxFacing * deg, 0, 'f', 0)
                    .arg(ic.minTiming, 0, 'f', 2)
                    .arg(ic.maxTiming, 0, 'f', 2);
    } else {
        body += "<p><b>Initial conditions</b>: <i>any</i></p>";
    }
    // Where the action sits in the motion graph.
    for (std::size_t g = 0; g < analysis_->graphActions.size(); ++g) {
        if (analysis_->graphActions[g] != std::pair{motion, action}) continue;
        if (g < analysis_->graph.startNode.size())
            body += QString("<p><b>Motion graph</b>: node %1 to node %2%3</p>")
                        .arg(analysis_->graph.startNode[g])
                        .arg(analysis_->graph.endNode[g])
                        .arg(g < analysis_->graph.inLargestScc.size() && !analysis_->graph.inLargestScc[g]
                                 ? " (outside the largest strongly connected set)"
                                 : "");
        break;
    }
    inspector_->setHtml(body);
}

void MainWindow::fillCombos() {
    combosModel_->removeRows(0, combosModel_->rowCount());
    if (!analysis_) return;
    for (const prep::ComboRecord& r : analysis_->project.combos.records()) {
        auto* value = new QStandardItem;
        value->setData(r.suitability, Qt::DisplayRole);
        combosModel_->appendRow({new QStandardItem(QString::fromStdString(r.mine)),
                                 new QStandardItem(QString::fromStdString(r.theirs)), value});
    }
    combosDock_->setWindowTitle(QString("Combination table (%1)").arg(combosModel_->rowCount()));
}

void MainWindow::graphNodeSelected(int node) {
    nodeActions_->clear();
    if (!analysis_) return;
    for (std::size_t g = 0; g < analysis_->graph.startNode.size() && g < analysis_->graphActions.size(); ++g) {
        if (analysis_->graph.startNode[g] != node) continue;
        const auto [m, a] = analysis_->graphActions[g];
        const prep::ProjectMotion& pm = analysis_->project.motions[static_cast<std::size_t>(m)];
        auto* item = new QListWidgetItem(QString("%1  %2 #%3  -> node %4")
                                             .arg(actionLabel(pm.actions.actions[static_cast<std::size_t>(a)]))
                                             .arg(QString::fromStdString(pm.id))
                                             .arg(a)
                                             .arg(analysis_->graph.endNode[g]));
        item->setData(kRoleMotion, m);
        item->setData(kRoleAction, a);
        nodeActions_->addItem(item);
    }
}

void MainWindow::timelinePlayhead(int frame) {
    if (shown_.empty()) return;
    time_ = frame / shown_.front().motion->fps();
    if (playing_) togglePlay();
}

void MainWindow::startAnalysis() {
    if (analysisThread_) return;
    cancelRequested_ = false;
    lastPosted_ = -1.0;
    analysisResult_.reset();
    progress_->setValue(0);
    progress_->setFormat("analysing %p%");
    progress_->show();
    cancelButton_->show();
    const std::filesystem::path file = projectFile_.toStdString();
    analysisThread_ = QThread::create([this, file] {
        ProgressFn progress = [this](double f, std::string_view stage) {
            // At most one update per half percent reaches the UI thread.
            if (f - lastPosted_.load() >= 0.005 || f >= 1.0) {
                lastPosted_ = f;
                const QString name = QString::fromUtf8(stage.data(), static_cast<int>(stage.size()));
                QMetaObject::invokeMethod(this, [this, f, name] { analysisProgress(f, name); }, Qt::QueuedConnection);
            }
            return !cancelRequested_.load();
        };
        analysisResult_.emplace(analyseProject(file, progress));
    });
    connect(analysisThread_, &QThread::finished, this, &MainWindow::analysisFinished);
    analysisThread_->start(QThread::LowPriority);
}

void MainWindow::cancelAnalysis() { cancelRequested_ = true; }

void MainWindow::analysisProgress(double fraction, const QString& stage) {
    progress_->setValue(static_cast<int>(fraction * 1000));
    progress_->setFormat(stage + " %p%");
}

void MainWindow::analysisFinished() {
    analysisThread_->deleteLater();
    analysisThread_ = nullptr;
    progress_->hide();
    cancelButton_->hide();
    if (!analysisResult_ || !*analysisResult_) {
        const QString why = analysisResult_ ? QString::fromStdString(analysisResult_->error().message) : "no result";
        statusBar()->showMessage(why == "cancelled" ? "Analysis cancelled" : "Analysis failed: " + why);
        if (why != "cancelled") std::fprintf(stderr, "fray: analysis failed: %s\n", why.toUtf8().constData());
        return;
    }
    analysis_ = std::move(analysisResult_->value());
    analysisResult_.reset();
    const int keepMotion = currentMotion_;
    library_->blockSignals(true);
    fillLibrary();
    for (int i = 0; i < library_->topLevelItemCount(); ++i)
        if (library_->topLevelItem(i)->data(0, kRoleMotion).toInt() == keepMotion) library_->topLevelItem(i)->setSelected(true);
    library_->blockSignals(false);
    showMotion(keepMotion);
    graph_->setData(analysis_->graph);
    fillCombos();
    statusBar()->showMessage(QString("%1: %2 motions, %3; motion graph %4")
                                 .arg(QFileInfo(projectFile_).fileName())
                                 .arg(analysis_->motions.size())
                                 .arg(QString::fromStdString(analysis_->contactsSummary))
                                 .arg(analysis_->graph.summary),
                             15000);
    std::printf("fray: analysed %zu motions, graph %d nodes\n", analysis_->motions.size(), analysis_->graphStats.nodes);
    std::fflush(stdout);
}

void MainWindow::openFile() {
    const QString path = QFileDialog::getOpenFileName(
        this, "Open", QFileInfo(projectFile_).absolutePath(),
        "Fray projects and motions (*.frayproj *.bvh *.fbx *.gltf *.glb *.dae);;All files (*)");
    if (path.isEmpty()) return;
    auto loaded = app::loadTakes({path.toStdString()});
    if (!loaded) {
        QMessageBox::warning(this, "Open", QString::fromStdString(loaded.error().message));
        return;
    }
    cancelAnalysis();
    if (analysisThread_) analysisThread_->wait();
    if (analysisThread_) analysisFinished();
    takes_ = std::move(*loaded);
    analysis_.reset();
    projectFile_ = path.endsWith(".frayproj") ? path : QString();
    setWindowTitle(QFileInfo(path).fileName() + " - Fray");
    graph_->setData({});
    nodeActions_->clear();
    fillCombos();
    fillLibrary();
    if (library_->topLevelItemCount() > 0) library_->setCurrentItem(library_->topLevelItem(0));
    librarySelectionChanged();
    if (!projectFile_.isEmpty()) startAnalysis();
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
    if (b.empty() || !viewport_) return;
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
    if (!scene_ && !shown_.empty()) timeline_->setPlayhead(stage_.frameOf(0));
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
    const bool analysing = analysisThread_ != nullptr || (!projectFile_.isEmpty() && !analysis_ && !analysisResult_);
    if (options_.quitAfter > 0 && viewport_->framesPresented() >= options_.quitAfter &&
        !(options_.waitForAnalysis && analysing))
        finish();
    // Not exposed yet (or minimised): keep ticking; a run with --quit-after
    // that never gets a frame on screen is stopped by its caller's timeout.
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
