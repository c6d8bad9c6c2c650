// MainWindow: the floor tools (issue 23) and the current setup drawn on the
// floor. The Floor tool bar picks a tool (or none: the mouse moves the camera),
// the character trajectories are drawn for, and imports a PNG as the floor;
// the tool's own options sit on the tool bar beside it.
#include <QActionGroup>
#include <QComboBox>
#include <QFileDialog>
#include <QLabel>
#include <QSignalBlocker>
#include <QStatusBar>
#include <QToolBar>
#include <cstdio>

#include "fray/authoring/project_document.h"
#include "fray/setup/paint.h"
#include "main_window.h"
#include "viewport.h"

namespace fray::editor {

namespace {

QString qs(const std::string& s) { return QString::fromStdString(s); }

}  // namespace

void MainWindow::buildFloorTools() {
    toolBar_ = addToolBar("Floor tools");
    toolBar_->setObjectName("FloorToolBar");
    toolOptions_ = addToolBar("Tool options");
    toolOptions_->setObjectName("ToolOptionsBar");
    auto* group = new QActionGroup(this);
    group->setExclusive(true);
    const auto add = [&](FloorTool* t, const char* name, const QString& key) {
        t->setParent(this);
        t->setObjectName(QString("tool") + name);
        tools_.push_back(t);
        QAction* a = toolBar_->addAction(t->name());
        a->setObjectName(QString("actionTool") + name);
        a->setCheckable(true);
        a->setToolTip(t->statusTip() + (key.isEmpty() ? "" : " (" + key + ")"));
        a->setStatusTip(t->statusTip());
        if (!key.isEmpty()) a->setShortcut(QKeySequence(key));
        group->addAction(a);
        connect(a, &QAction::triggered, this, [this, t] { selectTool(t->name()); });
    };
    QAction* camera = toolBar_->addAction("Camera");
    camera->setObjectName("actionToolCamera");
    camera->setCheckable(true);
    camera->setChecked(true);
    camera->setToolTip("No tool: the left button orbits the camera (Esc)");
    group->addAction(camera);
    connect(camera, &QAction::triggered, this, [this] { selectTool({}); });
    add(new BrushTool(false, *this), "Brush", "B");
    add(new BrushTool(true, *this), "Eraser", "E");
    add(new FillTool(*this), "Fill", "G");
    add(new TextTool(*this), "Text", "T");
    add(new TrajectoryTool(setup::TrajectoryShape::Polyline, *this), "Polyline", "P");
    add(new TrajectoryTool(setup::TrajectoryShape::Arc, *this), "Arc", "A");
    add(new TrajectoryTool(setup::TrajectoryShape::Circle, *this), "Circle", "C");
    add(new MoveTool(*this), "Move", "M");
    toolBar_->addSeparator();
    QAction* import = toolBar_->addAction("Import PNG...", this, [this] {
        const QString f = QFileDialog::getOpenFileName(this, "Floor bitmap", QFileInfo(projectFile_).absolutePath(), "Images (*.png)");
        if (!f.isEmpty()) importFloorPng(f);
    });
    import->setObjectName("actionImportFloor");
    import->setToolTip("Read a black-on-white PNG as the setup's floor bitmap (0.1 m a pixel, centred on the origin)");
    toolBar_->addSeparator();
    toolBar_->addWidget(new QLabel(" character "));
    toolCharacter_ = new QComboBox;
    toolCharacter_->setObjectName("toolCharacter");
    toolCharacter_->setToolTip("The character whose trajectory the Polyline, Arc and Circle tools draw");
    toolCharacter_->setMinimumWidth(90);
    toolBar_->addWidget(toolCharacter_);
    connect(sceneSource_, &QComboBox::currentIndexChanged, this, [this] {
        fillToolCharacters();
        refreshSetupOverlay();
    });
}

bool MainWindow::selectTool(const QString& name) {
    FloorTool* t = name.isEmpty() ? nullptr : tool(name);
    if (!name.isEmpty() && !t) return false;
    if (viewport_) viewport_->setActiveTool(t);
    toolOptions_->clear();
    for (QAction* a : toolBar_->actions())
        if (a->isCheckable()) a->setChecked(a->text() == (t ? t->name() : QString("Camera")));
    if (t) {
        t->populateToolBar(toolOptions_);
        statusBar()->showMessage(t->name() + ": " + t->statusTip(), 8000);
        if (currentSetup().isEmpty()) statusBar()->showMessage("Select a scene setup (Scene panel) to edit it on the floor", 8000);
    }
    refreshSetupOverlay();
    return true;
}

FloorTool* MainWindow::tool(const QString& name) const {
    for (FloorTool* t : tools_)
        if (t->name() == name) return t;
    return nullptr;
}

void MainWindow::fillToolCharacters() {
    if (!toolCharacter_) return;
    const QString was = toolCharacter_->currentText();
    const QSignalBlocker quiet(toolCharacter_);
    toolCharacter_->clear();
    if (!doc_ || currentSetup().isEmpty()) return;
    auto s = doc_->sceneSetup(currentSetup().toStdString());
    if (!s) return;
    for (const setup::SetupCharacter& c : setup::characters(*s)) toolCharacter_->addItem(qs(c.name));
    const int i = toolCharacter_->findText(was);
    if (i >= 0) toolCharacter_->setCurrentIndex(i);
}

bool MainWindow::selectToolCharacter(const QString& name) {
    fillToolCharacters();
    const int i = toolCharacter_->findText(name);
    if (i < 0) return false;
    toolCharacter_->setCurrentIndex(i);
    return true;
}

std::string MainWindow::toolCharacter() { return toolCharacter_ ? toolCharacter_->currentText().toStdString() : std::string(); }

void MainWindow::toolMessage(const QString& message, bool error) {
    if (error) {
        lastError_ = message;
        std::fprintf(stderr, "fray: %s\n", message.toUtf8().constData());
    }
    statusBar()->showMessage(message, error ? 15000 : 6000);
}

bool MainWindow::importFloorPng(const QString& file) {
    if (!doc_ || currentSetup().isEmpty()) {
        toolMessage("Select a scene setup to import its floor bitmap", true);
        return false;
    }
    // The floor keeps its scale and place when it has one; else 0.1 m a pixel, centred on the origin.
    auto s = doc_->sceneSetup(currentSetup().toStdString());
    double mpp = 0.1;
    setup::Point origin{-10.0, -6.0};
    if (s && s->floor && !s->floor->empty()) mpp = s->floor->metresPerPixel, origin = s->floor->origin;
    const Status st = doc_->importFloorImage(currentSetup().toStdString(), file.toStdString(), mpp, origin);
    if (!st) {
        toolMessage(qs(st.error().message), true);
        return false;
    }
    statusBar()->showMessage("Imported " + QFileInfo(file).fileName() + " as the floor of " + currentSetup(), 8000);
    return true;
}

void MainWindow::refreshSetupOverlay() {
    overlayLines_.clear();
    overlayLinePoints_.clear();
    overlayMarks_.clear();
    overlayFloor_ = {};
    overlayPixels_.clear();
    if (!doc_ || currentSetup().isEmpty()) return;
    auto s = doc_->sceneSetup(currentSetup().toStdString());
    if (!s) return;
    if (s->floor && !s->floor->empty()) {
        const setup::FloorPaint& f = *s->floor;
        overlayPixels_.assign(f.painted.size() * 4, 0);
        for (std::size_t i = 0; i < f.painted.size(); ++i) {
            std::uint8_t* px = &overlayPixels_[i * 4];
            if (f.painted[i]) px[0] = 230, px[1] = 40, px[2] = 40, px[3] = 150;
        }
        overlayFloor_.rgba = overlayPixels_.data();
        overlayFloor_.width = f.width;
        overlayFloor_.height = f.height;
        overlayFloor_.min = glm::vec2(static_cast<float>(f.origin.x), static_cast<float>(f.origin.z));
        overlayFloor_.max = overlayFloor_.min + glm::vec2(static_cast<float>(f.width * f.metresPerPixel),
                                                          static_cast<float>(f.height * f.metresPerPixel));
        overlayFloor_.revision = ++overlayRevision_;
    }
    const glm::vec4 amber(1.0f, 0.75f, 0.2f, 0.9f);
    for (const setup::Trajectory& t : s->trajectories) {
        auto line = setup::sampleTrajectory(t, 0.25);
        if (!line || line->empty()) continue;
        std::vector<glm::vec3> pts;
        for (const setup::Point& p : *line) pts.emplace_back(p.x, 0.0f, p.z);
        if (t.loop || t.shape == setup::TrajectoryShape::Circle) pts.push_back(pts.front());
        overlayLinePoints_.push_back(std::move(pts));
        for (const setup::SetupCheckpoint& c : t.checkpoints)
            overlayMarks_.push_back({glm::vec3(c.pos.x, 0.0f, c.pos.z), amber, 0.3f, {}});
        for (const setup::Point& p : t.points) overlayMarks_.push_back({glm::vec3(p.x, 0.0f, p.z), glm::vec4(1, 1, 1, 0.8f), 0.12f, {}});
    }
    for (const auto& pts : overlayLinePoints_) overlayLines_.push_back({pts, amber, 0.06f});
    for (const setup::SetupCharacter& c : setup::characters(*s))
        overlayMarks_.push_back({glm::vec3(c.start.x, 0.0f, c.start.z), glm::vec4(0.3f, 0.8f, 1.0f, 1.0f), 0.4f, {}});
}

}  // namespace fray::editor
