#include "main_window.h"

#include <QApplication>
#include <QCloseEvent>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QDockWidget>
#include <QFileInfo>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QImage>
#include <QFormLayout>
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
#include <QToolBar>
#include <QToolButton>
#include <QTreeWidget>
#include <QUndoGroup>
#include <QUndoStack>
#include <QUndoView>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <tuple>
#include <cstdio>

#include "fray/authoring/autosave.h"
#include "fray/authoring/project_document.h"
#include "fray/authoring/recent_files.h"
#include "fray/render/image.h"
#include "gantt_view.h"
#include "graph_view.h"
#include "inspector_panel.h"
#include "timeline_view.h"
#include "viewport.h"

namespace fray::editor {

namespace {

// Bumped when the docks change, so an old saved layout is not restored onto them.
constexpr int kLayoutVersion = 2;

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
    cancelButton_->setToolTip("Stop the work in the background (an analysis leaves the panels empty until it runs again)");
    cancelButton_->hide();
    statusBar()->addPermanentWidget(progress_);
    statusBar()->addPermanentWidget(cancelButton_);
    statusBar()->addPermanentWidget(statsLabel_);
    resize(1400, 880);

    settings_ = std::make_unique<QSettings>();
    recent_ = new authoring::RecentFiles(*settings_, authoring::RecentFiles::kDefaultCapacity, this);
    undoGroup_ = new QUndoGroup(this);
    setAcceptDrops(true);
    buildDocks();
    buildMenus();
    if (!projectFile_.isEmpty() && !openDocument(projectFile_)) {
        exitCode_ = 1;
        projectFile_.clear();
    }
    fillLibrary();
    fillCombos();
    fillPatterns();
    fillSceneSources();
    updateTitle();
    defaultLayout_ = saveState(kLayoutVersion);
    if (options_.restoreLayout) {
        restoreGeometry(settings_->value("window/geometry").toByteArray());
        restoreState(settings_->value("window/state").toByteArray(), kLayoutVersion);
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
    if (!options_.generateSpec.isEmpty() && selectSceneSource(options_.generateSpec))
        QTimer::singleShot(0, this, &MainWindow::generate);
    last_ = std::chrono::steady_clock::now();
    if (viewport_) timer_.start(options_.quitAfter > 0 ? 0 : 15);
}

MainWindow::~MainWindow() {
    cancelAnalysis();
    // The workers write into this window: both must be done before it goes.
    if (analysisThread_) analysisThread_->wait();
    if (segmentThread_) segmentThread_->wait();
    if (solvingPosture_) jobCancel_ = true;  // a physics solve is only a view: stop it
    if (jobThread_) jobThread_->wait();
}

void MainWindow::buildDocks() {
    const auto dock = [&](const char* name, const QString& title, QWidget* content, Qt::DockWidgetArea area) {
        auto* d = new QDockWidget(title, this);
        d->setObjectName(name);
        d->setWidget(content);
        addDockWidget(area, d);
        return d;
    };

    // A panel of a filter line over a view.
    const auto panel = [](const char* name, QVBoxLayout*& layout) {
        auto* w = new QWidget;
        w->setObjectName(name);
        layout = new QVBoxLayout(w);
        layout->setContentsMargins(2, 2, 2, 2);
        return w;
    };
    const auto filterLine = [](const char* name, const QString& placeholder) {
        auto* edit = new QLineEdit;
        edit->setObjectName(name);
        edit->setPlaceholderText(placeholder);
        edit->setClearButtonEnabled(true);
        return edit;
    };

    // Library.
    QVBoxLayout* libraryLayout = nullptr;
    QWidget* libraryPanel = panel("libraryPanel", libraryLayout);
    libraryFilter_ = filterLine("libraryFilter", scene_ ? "Filter characters" : "Filter by annotation or name");
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

    // The scene's action track right below the viewport, the timeline below it.
    gantt_ = new GanttView;
    gantt_->setObjectName("gantt");
    ganttDock_ = dock("GanttDock", "Action track", gantt_, Qt::BottomDockWidgetArea);

    // Timeline.
    timeline_ = new TimelineView;
    timeline_->setObjectName("timeline");
    timelineDock_ = new QDockWidget("Timeline", this);
    timelineDock_->setObjectName("TimelineDock");
    timelineDock_->setWidget(timeline_);
    addDockWidget(Qt::BottomDockWidgetArea, timelineDock_, Qt::Vertical);
    connect(timeline_, &TimelineView::playheadRequested, this, &MainWindow::timelinePlayhead);
    connect(timeline_, &TimelineView::playToggled, this, &MainWindow::togglePlay);
    connect(timeline_, &TimelineView::actionSelected, this, [this](int action) {
        if (currentMotion_ >= 0) showAction(currentMotion_, action);
    });
    // Timeline gestures become document edits (one undo step each; a drag is one).
    const auto motionId = [this]() -> std::string {
        const prep::Project* p = project();
        if (!p || currentMotion_ < 0 || currentMotion_ >= static_cast<int>(p->motions.size())) return {};
        return p->motions[static_cast<std::size_t>(currentMotion_)].id;
    };
    const auto report = [this](const Status& s) {
        if (!s) editFailed(QString::fromStdString(s.error().message));
    };
    connect(timeline_, &TimelineView::cutDragged, this, [this, motionId, report](int from, int to, bool finished) {
        if (!doc_) return;
        if (cutDrag_ == 0) cutDrag_ = doc_->beginDrag();
        // The cut is wherever the drag has moved it so far: find it from `from`.
        const prep::ProjectMotion* pm = doc_->project().findMotion(motionId());
        if (pm) {
            int current = from;
            if (std::find(pm->actions.cuts.begin(), pm->actions.cuts.end(), from) == pm->actions.cuts.end())
                current = draggedCutAt_;
            if (current != to) report(doc_->moveCut(motionId(), current, to, cutDrag_));
            draggedCutAt_ = to;
        }
        if (finished) cutDrag_ = 0;
    });
    connect(timeline_, &TimelineView::cutAddRequested, this, [this, motionId, report](int frame) {
        if (doc_) report(doc_->addCut(motionId(), frame));
    });
    connect(timeline_, &TimelineView::cutRemoveRequested, this, [this, motionId, report](int frame) {
        if (doc_) report(doc_->removeCut(motionId(), frame));
    });
    connect(timeline_, &TimelineView::mergeRequested, this, [this, motionId, report](int action) {
        if (doc_) report(doc_->mergeActions(motionId(), action));
    });
    connect(timeline_, &TimelineView::contactLabelRequested, this,
            [this, motionId, report](int foot, int first, int last, bool supported) {
                if (!doc_) return;
                prep::ContactLabel label;
                label.firstFrame = first;
                label.lastFrame = last;
                (foot == 0 ? label.left : label.right) = supported;
                report(doc_->addContactLabel(motionId(), label));
            });

    // Combination table, tabbed with the timeline.
    QVBoxLayout* combosLayout = nullptr;
    QWidget* combosPanel = panel("combosPanel", combosLayout);
    combosFilter_ = filterLine("combosFilter", "Filter records (mine or theirs)");
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
    combos_->horizontalHeader()->setStretchLastSection(true);
    combos_->verticalHeader()->hide();
    auto* combosBar = new QHBoxLayout;
    combosBar->addWidget(combosFilter_, 1);
    for (auto [name, text, slot] : {std::tuple{"combosAdd", "Add...", &MainWindow::addComboRecord},
                                    std::tuple{"combosRemove", "Remove", &MainWindow::removeComboRecords},
                                    std::tuple{"combosImport", "Import CSV...", &MainWindow::importCombos},
                                    std::tuple{"combosExport", "Export CSV...", &MainWindow::exportCombos}}) {
        auto* b = new QPushButton(text);
        b->setObjectName(name);
        connect(b, &QPushButton::clicked, this, slot);
        combosBar->addWidget(b);
    }
    combosLayout->addLayout(combosBar);
    combosLayout->addWidget(combos_, 1);
    combos_->setSelectionBehavior(QAbstractItemView::SelectRows);
    combos_->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed);
    // The model never keeps an edit itself: it pushes a command, and the
    // document's change event refills it.
    connect(combosModel_, &QStandardItemModel::itemChanged, this, [this](QStandardItem* item) {
        if (fillingCombos_ || !doc_ || item->column() != 2) return;
        const int row = item->row();
        prep::ComboRecord r{combosModel_->item(row, 0)->text().toStdString(), combosModel_->item(row, 1)->text().toStdString(),
                            item->data(Qt::DisplayRole).toDouble()};
        const Status s = doc_->setComboRecord(r);
        if (!s) {
            editFailed(QString::fromStdString(s.error().message));
            QTimer::singleShot(0, this, [this] { fillCombos(); });
        }
    });
    combosDock_ = dock("CombosDock", "Combination table", combosPanel, Qt::BottomDockWidgetArea);
    tabifyDockWidget(timelineDock_, combosDock_);
    timelineDock_->raise();
    connect(combosFilter_, &QLineEdit::textChanged, combosProxy_, &QSortFilterProxyModel::setFilterFixedString);

    // Inspector and motion graph, tabbed on the right.
    inspector_ = new InspectorPanel;
    inspector_->setObjectName("inspector");
    connect(inspector_, &InspectorPanel::editFailed, this, &MainWindow::editFailed);
    inspectorDock_ = dock("InspectorDock", "Inspector", inspector_, Qt::RightDockWidgetArea);

    QVBoxLayout* graphLayout = nullptr;
    QWidget* graphPanel = panel("graphPanel", graphLayout);
    graph_ = new GraphView;
    graph_->setObjectName("graph");
    nodeActions_ = new QListWidget;
    nodeActions_->setObjectName("nodeActions");
    nodeActions_->setToolTip("Actions leaving the selected node (click one to select it)");
    nodeActions_->setMaximumHeight(150);
    // Graph settings are part of the project (undoable); a change re-analyses in the background.
    auto* graphBar = new QHBoxLayout;
    graphPreset_ = new QComboBox;
    graphPreset_->setObjectName("graphPreset");
    graphPreset_->addItems({"fighting", "locomotion"});
    graphPreset_->setToolTip("Pose-distance weights of the motion graph (SPEC 1.5)");
    graphThreshold_ = new QDoubleSpinBox;
    graphThreshold_->setObjectName("graphThreshold");
    graphThreshold_->setRange(0.01, 5.0);
    graphThreshold_->setSingleStep(0.01);
    graphThreshold_->setDecimals(2);
    graphThreshold_->setKeyboardTracking(false);
    graphThreshold_->setToolTip("Clustering threshold (about radians): lower gives more nodes and fewer connections");
    graphBar->addWidget(new QLabel("preset"));
    graphBar->addWidget(graphPreset_);
    graphBar->addWidget(new QLabel("threshold"));
    graphBar->addWidget(graphThreshold_);
    graphBar->addStretch(1);
    graphLayout->addLayout(graphBar);
    connect(graphPreset_, &QComboBox::textActivated, this, [this](const QString& preset) {
        if (!doc_) return;
        if (Status st = doc_->setGraphPreset(preset.toStdString()); !st) editFailed(QString::fromStdString(st.error().message));
    });
    connect(graphThreshold_, &QDoubleSpinBox::valueChanged, this, [this](double value) {
        if (!doc_ || fillingGraphControls_) return;
        if (Status st = doc_->setGraphThreshold(value); !st) editFailed(QString::fromStdString(st.error().message));
    });
    graphLayout->addWidget(graph_, 1);
    graphLayout->addWidget(nodeActions_);
    graphDock_ = dock("GraphDock", "Motion graph", graphPanel, Qt::RightDockWidgetArea);
    tabifyDockWidget(inspectorDock_, graphDock_);
    inspectorDock_->raise();
    connect(graph_, &GraphView::nodeSelected, this, &MainWindow::graphNodeSelected);
    connect(nodeActions_, &QListWidget::itemClicked, this, [this](QListWidgetItem* item) {
        showAction(item->data(kRoleMotion).toInt(), item->data(kRoleAction).toInt());
    });

    auto* history = new QUndoView(undoGroup_);
    history->setObjectName("history");
    history->setEmptyLabel("<opened>");
    historyDock_ = dock("HistoryDock", "Undo history", history, Qt::RightDockWidgetArea);
    tabifyDockWidget(graphDock_, historyDock_);
    inspectorDock_->raise();

    buildSceneDocks();
    buildPatchDocks();
    buildFloorTools();

    resizeDocks({libraryDock_}, {280}, Qt::Horizontal);
    resizeDocks({inspectorDock_}, {360}, Qt::Horizontal);
    resizeDocks({timelineDock_}, {210}, Qt::Vertical);
}

void MainWindow::buildMenus() {
    const auto named = [](QAction* a, const char* name, QKeySequence key = {}) {
        a->setObjectName(name);
        if (!key.isEmpty()) a->setShortcut(key);
        return a;
    };
    QMenu* file = menuBar()->addMenu("&File");
    file->setObjectName("FileMenu");
    named(file->addAction("&New project...", this, &MainWindow::newProject), "actionNew", QKeySequence(Qt::CTRL | Qt::Key_N));
    named(file->addAction("&Open...", this, &MainWindow::openFile), "actionOpen", QKeySequence(Qt::CTRL | Qt::Key_O));
    recentMenu_ = file->addMenu("Open &Recent");
    recentMenu_->setObjectName("RecentMenu");
    recentMenu_->menuAction()->setObjectName("actionOpenRecent");
    fillRecentMenu();
    file->addSeparator();
    saveAction_ = named(file->addAction("&Save", this, &MainWindow::save), "actionSave", QKeySequence(Qt::CTRL | Qt::Key_S));
    saveAsAction_ = named(file->addAction("Save &As...", this, &MainWindow::saveAs), "actionSaveAs",
                          QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_S));
    file->addSeparator();
    importAction_ = named(file->addAction("&Import motions...", this, &MainWindow::importMotionsDialog), "actionImport",
                          QKeySequence(Qt::CTRL | Qt::Key_I));
    file->addSeparator();
    named(file->addAction("&Quit", this, &QWidget::close), "actionQuit", QKeySequence(Qt::CTRL | Qt::Key_Q));

    // Undo and redo name the command ("Undo Move cut in walking").
    QMenu* edit = menuBar()->addMenu("&Edit");
    edit->setObjectName("EditMenu");
    QAction* undo = undoGroup_->createUndoAction(this, "&Undo");
    undo->setObjectName("actionUndo");
    undo->setShortcuts({QKeySequence(Qt::CTRL | Qt::Key_Z)});
    QAction* redo = undoGroup_->createRedoAction(this, "&Redo");
    redo->setObjectName("actionRedo");
    redo->setShortcuts({QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_Z), QKeySequence(Qt::CTRL | Qt::Key_Y)});
    edit->addAction(undo);
    edit->addAction(redo);
    edit->addSeparator();
    named(edit->addAction("Undo &history",
                          [this] {
                              historyDock_->show();
                              historyDock_->raise();
                          }),
          "actionUndoHistory");

    QMenu* projectMenu = menuBar()->addMenu("&Project");
    projectMenu->setObjectName("ProjectMenu");
    segmentAction_ = named(projectMenu->addAction("&Segment the selected motion", this, &MainWindow::segmentCurrentMotion),
                           "actionSegment", QKeySequence(Qt::CTRL | Qt::Key_E));
    analyseAction_ = named(projectMenu->addAction("Train contacts and &analyse: contacts, profiles, motion graph", this,
                                                  [this] {
                                                      if (!analysisThread_) startAnalysis();
                                                  }),
                           "actionAnalyse", QKeySequence(Qt::CTRL | Qt::Key_G));

    buildSceneMenu();

    QMenu* view = menuBar()->addMenu("&View");
    view->setObjectName("ViewMenu");
    for (QDockWidget* d : {libraryDock_, timelineDock_, inspectorDock_, graphDock_, combosDock_, historyDock_, sceneDock_,
                          ganttDock_, metricsDock_, patternsDock_, patchesDock_}) {
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
    buildPostureMenu(view);

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
    // Tool bars: the floor tools and their options.
    QJsonArray bars;
    for (QToolBar* bar : findChildren<QToolBar*>()) {
        QJsonObject b;
        b["name"] = bar->objectName();
        b["title"] = bar->windowTitle();
        QJsonArray actions;
        for (QAction* a : bar->actions()) {
            if (a->isSeparator() || a->objectName().isEmpty()) continue;
            QJsonObject o;
            o["name"] = a->objectName();
            o["text"] = a->text();
            o["shortcut"] = a->shortcut().toString(QKeySequence::PortableText);
            o["tip"] = a->statusTip().isEmpty() ? a->toolTip() : a->statusTip();
            actions.append(o);
        }
        b["actions"] = actions;
        bars.append(b);
    }
    root["toolbars"] = bars;
    // Context menus built on demand: the Gantt bar's (window_pins.cpp).
    QJsonArray contextMenus;
    contextMenus.append(QJsonObject{{"name", "ganttBarMenu"},
                                    {"panel", "gantt"},
                                    {"opens", "right click on an action bar"},
                                    {"items", QJsonArray{"ganttReplaceMenu", "ganttPin", "ganttUnpin"}}});
    root["contextMenus"] = contextMenus;
    // The Scene panel's Setup box: the kinds New setup offers and the
    // parameter widgets (window_graph_setup.cpp).
    QJsonObject setupBox;
    setupBox["panel"] = "scenePanel";  // inside the dock's scenePanelScroll
    QJsonArray kinds;
    for (setup::SetupKind k : setup::allSetupKinds()) kinds.append(QString(setup::setupKindName(k)));
    setupBox["kinds"] = kinds;
    setupBox["chooser"] = "sceneNewKind";
    setupBox["button"] = "sceneNewSetup";
    // graphParameters: the Interaction Graph kinds' (param_*); planParameters:
    // duel's and chase's (plan_*: duration, seed, a depth per character);
    // characterParameters: duel's and chase's per character (the character
    // picked, preset, a weight, takes, actions: window_plan_setup.cpp);
    // composeParameters: the Interaction Patches kinds' numbers (compose_*).
    QJsonArray params, planParams, composeParams, characterParams;
    const auto describe = [&](QWidget* w, QWidget* row) {
        QJsonObject o;
        o["name"] = w->objectName();
        o["label"] = paramsForm_ && paramsForm_->labelForField(row) ? static_cast<QLabel*>(paramsForm_->labelForField(row))->text() : QString();
        o["tip"] = w->toolTip();
        o["widget"] = QString(w->metaObject()->className());
        return o;
    };
    for (QWidget* w : paramWidgets_) {
        const QString name = w->objectName();
        (name.startsWith("plan_") ? planParams : name.startsWith("compose_") ? composeParams : params).append(describe(w, w));
    }
    for (QWidget* row : planRows_) {
        if (row->objectName() != "plan_weightRow") characterParams.append(describe(row, row));
        else
            for (QWidget* w : {static_cast<QWidget*>(planWeightKey_), static_cast<QWidget*>(planWeight_)}) characterParams.append(describe(w, row));
    }
    setupBox["graphParameters"] = params;
    setupBox["planParameters"] = planParams;
    setupBox["characterParameters"] = characterParams;
    setupBox["composeParameters"] = composeParams;
    root["setupBox"] = setupBox;
    return QJsonDocument(root).toJson(QJsonDocument::Indented);
}

void MainWindow::closeEvent(QCloseEvent* event) {
    if (!maybeSave()) {
        event->ignore();
        return;
    }
    settings_->setValue("window/geometry", saveGeometry());
    settings_->setValue("window/state", saveState(kLayoutVersion));
    QMainWindow::closeEvent(event);
}

void MainWindow::undoGroupChanged() {
    if (doc_) {
        if (!undoGroup_->stacks().contains(doc_->undoStack())) undoGroup_->addStack(doc_->undoStack());
        undoGroup_->setActiveStack(doc_->undoStack());
    } else {
        undoGroup_->setActiveStack(nullptr);
    }
}

void MainWindow::resetLayout() { restoreState(defaultLayout_, kLayoutVersion); }

void MainWindow::showShortcuts() {
    QMessageBox::information(
        this, "Keyboard shortcuts",
        "Space: play / pause\nLeft / Right: one frame (timeline)\nUp / Down: ten frames (timeline)\n"
        "Home: frame the whole motion (timeline)\nF: frame all (viewport)\nDelete: remove the cut under the playhead "
        "(timeline)\nCtrl+O: open\nCtrl+Q: quit");
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
    const prep::Project snapshot = project() ? *project() : prep::Project{};
    analysisRevision_ = doc_ ? doc_->revision() : 0;
    analysisThread_ = QThread::create([this, file, snapshot] {
        ProgressFn progress = [this](double f, std::string_view stage) {
            // At most one update per half percent reaches the UI thread.
            if (f - lastPosted_.load() >= 0.005 || f >= 1.0) {
                lastPosted_ = f;
                const QString name = QString::fromUtf8(stage.data(), static_cast<int>(stage.size()));
                QMetaObject::invokeMethod(this, [this, f, name] { analysisProgress(f, name); }, Qt::QueuedConnection);
            }
            return !cancelRequested_.load();
        };
        analysisResult_.emplace(analyseProject(snapshot, file, progress));
    });
    connect(analysisThread_, &QThread::finished, this, &MainWindow::analysisFinished);
    analysisThread_->start(QThread::LowPriority);
}

void MainWindow::cancelAnalysis() {
    cancelRequested_ = true;
    jobCancel_ = true;
    segmentMotion_.clear();  // a running segmentation's result is dropped
}

void MainWindow::analysisProgress(double fraction, const QString& stage) {
    progress_->setValue(static_cast<int>(fraction * 1000));
    progress_->setFormat(stage + " %p%");
}

void MainWindow::analysisFinished() {
    analysisThread_->deleteLater();
    analysisThread_ = nullptr;
    updateBusy();
    if (!analysisResult_ || !*analysisResult_) {
        const bool wasCancelled = analysisResult_ && analysisResult_->error().isCancelled();
        const QString why = analysisResult_ ? QString::fromStdString(analysisResult_->error().message) : "no result";
        if (wasCancelled) statusBar()->showMessage("Analysis cancelled");
        else showError("Analysis", "Analysis failed: " + why);
        return;
    }
    analysis_ = std::move(analysisResult_->value());
    analysisResult_.reset();
    refreshAll();
    graph_->setData(analysis_->graph);
    graphStale_ = doc_ && doc_->revision() != analysisRevision_;
    statusBar()->showMessage(QString("%1: %2 motions, %3; motion graph %4")
                                 .arg(QFileInfo(projectFile_).fileName())
                                 .arg(analysis_->motions.size())
                                 .arg(QString::fromStdString(analysis_->contactsSummary))
                                 .arg(analysis_->graph.summary),
                             15000);
    std::printf("fray: analysed %zu motions, graph %d nodes\n", analysis_->motions.size(), analysis_->graphStats.nodes);
    std::fflush(stdout);
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
        gantt_->setTime(time_);
        if (viewport_->activeTool()) {
            // Editing the setup: its floor, trajectories and starts, not the scene's.
            viewport_->frame().trajectories = overlayLines_;
            viewport_->frame().checkpoints = overlayMarks_;
            viewport_->frame().floorBitmap = overlayFloor_.width > 0 ? &overlayFloor_ : nullptr;
        }
    } else {
        stage_.pose(time_, true);
        viewport_->frame().characters = stage_.instances();
        // The selected setup on the floor (nothing when none is selected).
        viewport_->frame().trajectories = overlayLines_;
        viewport_->frame().checkpoints = overlayMarks_;
        viewport_->frame().floorBitmap = overlayFloor_.width > 0 ? &overlayFloor_ : nullptr;
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
    const bool analysing = analysisThread_ != nullptr || (!projectFile_.isEmpty() && !analysis_ && !analysisResult_) ||
                           (!options_.generateSpec.isEmpty() && (jobThread_ || !scene_) && exitCode_ == 0);
    const int framesShown = viewport_->framesPresented() - (options_.generateSpec.isEmpty() ? 0 : sceneShownAtFrame_);
    if (options_.quitAfter > 0 && framesShown >= options_.quitAfter &&
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
