// MainWindow: the floor tools (issue 23) and the current setup drawn on the
// floor. The Floor tool bar picks a tool (or none: the mouse moves the camera),
// the character trajectories are drawn for, and imports a PNG as the floor;
// the tool's own options sit on the tool bar beside it.
#include <QActionGroup>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QPushButton>
#include <QFileDialog>
#include <QLabel>
#include <QLineEdit>
#include <QSignalBlocker>
#include <QStatusBar>
#include <QToolBar>
#include <cmath>
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
    add(new CheckpointTool(*this), "Checkpoint", "K");
    add(new RatPathTool(*this), "RatPath", "R");
    add(new DirectionTool(*this), "RunDirection", "D");
    add(new CommandTool(*this), "Command", "U");
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
        cpCharacter_.clear(), cpIndex_ = -1;
        refreshCheckpointInspector();
        refreshSetupOverlay();
        refreshSetupParameters();
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
        if (t->name() == name || t->objectName() == "tool" + name) return t;
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
    overlayLabels_.clear();
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
    // Labels first (the marks hold views of them: no reallocation after).
    std::vector<std::pair<render::Checkpoint, std::string>> labelled;
    const auto seconds = [](double t) { return QString::number(t, 'g', 4).toStdString() + " s"; };
    for (const setup::Trajectory& t : s->trajectories) {
        auto line = setup::sampleTrajectory(t, 0.25);
        if (!line || line->empty()) continue;
        std::vector<glm::vec3> pts;
        for (const setup::Point& p : *line) pts.emplace_back(p.x, 0.0f, p.z);
        if (t.loop || t.shape == setup::TrajectoryShape::Circle) pts.push_back(pts.front());
        overlayLinePoints_.push_back(std::move(pts));
        for (std::size_t i = 0; i < t.checkpoints.size(); ++i) {
            const setup::SetupCheckpoint& c = t.checkpoints[i];
            const bool sel = t.character == cpCharacter_ && static_cast<int>(i) == cpIndex_;
            std::string label = (c.time ? seconds(*c.time) : std::string()) + (c.action.empty() ? "" : (c.time ? " " : "") + c.action);
            labelled.push_back({{glm::vec3(c.pos.x, 0.0f, c.pos.z), sel ? glm::vec4(1, 0.35f, 0.1f, 1) : amber, sel ? 0.4f : 0.3f, {}}, label});
        }
        for (const setup::Point& p : t.points) overlayMarks_.push_back({glm::vec3(p.x, 0.0f, p.z), glm::vec4(1, 1, 1, 0.8f), 0.12f, {}});
    }
    // The rat's trajectory.
    if (s->kind == setup::SetupKind::Rat) {
        std::vector<glm::vec3> pts;
        for (const setup::Point& p : setup::ratPath(*s)) pts.emplace_back(p.x, 0.0f, p.z);
        if (pts.size() >= 2) {
            overlayLinePoints_.push_back(pts);
            labelled.push_back({{pts.front(), glm::vec4(0.55f, 0.35f, 0.2f, 1.0f), 0.35f, {}}, "rat"});
        }
    }
    // Football running directions: an arrow each where it was drawn, labelled with its time.
    if (s->kind == setup::SetupKind::Football) {
        const auto dirs = setup::runDirections(*s);
        for (std::size_t i = 0; i < dirs.size(); ++i) {
            const setup::RunDirection& d = dirs[i];
            const setup::Point at = d.at.value_or(setup::Point{-6.0 + 3.0 * static_cast<double>(i), -4.0});
            const double h = d.headingDeg * 3.14159265358979323846 / 180.0;
            const glm::vec3 a(at.x, 0.0f, at.z), b(at.x + 2.0 * std::sin(h), 0.0f, at.z + 2.0 * std::cos(h));
            const glm::vec3 side(-0.5 * std::cos(h), 0.0f, 0.5 * std::sin(h));
            const glm::vec3 back = a + (b - a) * 0.7f;
            overlayLinePoints_.push_back({a, b, back + side, b, back - side});
            labelled.push_back({{a, glm::vec4(0.2f, 0.9f, 0.4f, 1.0f), 0.2f, {}}, seconds(d.time)});
        }
    }
    // One-vs-many commands where they were placed.
    if (s->kind == setup::SetupKind::OneVsMany || s->kind == setup::SetupKind::OneVsOne) {
        for (const setup::TimedCommand& c : setup::timedCommands(*s)) {
            if (!c.at) continue;
            const glm::vec4 colour = c.action == "move" ? glm::vec4(0.3f, 0.6f, 1.0f, 1.0f) : glm::vec4(0.95f, 0.3f, 0.6f, 1.0f);
            labelled.push_back({{glm::vec3(c.at->x, 0.0f, c.at->z), colour, 0.35f, {}}, c.action + " " + seconds(c.time)});
        }
    }
    overlayLabels_.reserve(labelled.size());
    for (auto& [mark, label] : labelled) {
        overlayLabels_.push_back(std::move(label));
        mark.label = overlayLabels_.back();
        overlayMarks_.push_back(mark);
    }
    for (const auto& pts : overlayLinePoints_) overlayLines_.push_back({pts, amber, 0.06f});
    for (const setup::SetupCharacter& c : setup::characters(*s))
        overlayMarks_.push_back({glm::vec3(c.start.x, 0.0f, c.start.z), glm::vec4(0.3f, 0.8f, 1.0f, 1.0f), 0.4f, {}});
}

// ---- the checkpoint inspector

QWidget* MainWindow::makeCheckpointInspector() {
    cpBox_ = new QGroupBox("Checkpoint");
    cpBox_->setObjectName("checkpointInspector");
    cpBox_->setToolTip("The checkpoint picked with the Checkpoint tool: when it may be passed and what is played there");
    auto* form = new QFormLayout(cpBox_);
    form->setContentsMargins(4, 2, 4, 2);
    cpLabel_ = new QLabel("none: pick one with the Checkpoint tool (K)");
    cpLabel_->setObjectName("checkpointLabel");
    form->addRow(cpLabel_);
    cpTime_ = new QDoubleSpinBox;
    cpTime_->setObjectName("checkpointTime");
    cpTime_->setRange(-1, 3600);
    cpTime_->setDecimals(2);
    cpTime_->setSuffix(" s");
    cpTime_->setSpecialValueText("no time");
    cpTime_->setKeyboardTracking(false);
    cpTime_->setToolTip("Not to be passed before this time (no time: whenever the character gets there)");
    form->addRow("Time", cpTime_);
    cpAction_ = new QComboBox;
    cpAction_->setObjectName("checkpointAction");
    cpAction_->setEditable(true);
    cpAction_->setInsertPolicy(QComboBox::NoInsert);
    cpAction_->setToolTip("The action required there: @annotation (a word of the vocabulary) or an action name; empty: none");
    form->addRow("Action", cpAction_);
    cpRemove_ = new QPushButton("Remove checkpoint");
    cpRemove_->setObjectName("checkpointRemove");
    form->addRow(cpRemove_);
    connect(cpTime_, &QDoubleSpinBox::valueChanged, this, [this](double v) {
        if (!doc_ || cpIndex_ < 0) return;
        const std::optional<double> t = v < 0 ? std::nullopt : std::optional<double>(v);
        if (Status st = doc_->setCheckpointTime(currentSetup().toStdString(), cpCharacter_, cpIndex_, t); !st) {
            toolMessage(qs(st.error().message), true);
            refreshCheckpointInspector();
        }
    });
    const auto applyAction = [this] {
        if (!doc_ || cpIndex_ < 0) return;
        const std::string a = cpAction_->currentText().trimmed().toStdString();
        auto s = doc_->sceneSetup(currentSetup().toStdString());
        if (s)
            for (const setup::Trajectory& t : s->trajectories)
                if (t.character == cpCharacter_ && cpIndex_ < static_cast<int>(t.checkpoints.size()) &&
                    t.checkpoints[static_cast<std::size_t>(cpIndex_)].action == a)
                    return;
        if (Status st = doc_->setCheckpointAction(currentSetup().toStdString(), cpCharacter_, cpIndex_, a); !st) {
            toolMessage(qs(st.error().message), true);
            refreshCheckpointInspector();
        }
    };
    connect(cpAction_, &QComboBox::activated, this, applyAction);
    connect(cpAction_->lineEdit(), &QLineEdit::editingFinished, this, applyAction);
    connect(cpRemove_, &QPushButton::clicked, this, [this] {
        if (!doc_ || cpIndex_ < 0) return;
        const int i = cpIndex_;
        cpIndex_ = -1;
        if (Status st = doc_->removeCheckpoint(currentSetup().toStdString(), cpCharacter_, i); !st) toolMessage(qs(st.error().message), true);
        refreshCheckpointInspector();
        refreshSetupOverlay();
    });
    refreshCheckpointInspector();
    return cpBox_;
}

void MainWindow::refreshCheckpointInspector() {
    if (!cpBox_) return;
    const setup::SetupCheckpoint* c = nullptr;
    std::optional<setup::SceneSetup> s;
    if (doc_ && !currentSetup().isEmpty() && cpIndex_ >= 0) {
        if (auto r = doc_->sceneSetup(currentSetup().toStdString())) s = std::move(*r);
        if (s)
            for (const setup::Trajectory& t : s->trajectories)
                if (t.character == cpCharacter_ && cpIndex_ < static_cast<int>(t.checkpoints.size()))
                    c = &t.checkpoints[static_cast<std::size_t>(cpIndex_)];
    }
    if (!c) cpIndex_ = -1;
    const QSignalBlocker q1(cpTime_), q2(cpAction_);
    cpTime_->setEnabled(c != nullptr);
    cpAction_->setEnabled(c != nullptr);
    cpRemove_->setEnabled(c != nullptr);
    if (!c) {
        cpLabel_->setText("none: pick one with the Checkpoint tool (K)");
        cpTime_->setValue(-1);
        cpAction_->setCurrentText({});
        return;
    }
    cpLabel_->setText(QString("%1 of %2, at (%3, %4) m").arg(cpIndex_ + 1).arg(qs(cpCharacter_)).arg(c->pos.x, 0, 'f', 2).arg(c->pos.z, 0, 'f', 2));
    cpTime_->setValue(c->time.value_or(-1));
    if (cpAction_->count() == 0) {
        cpAction_->addItem({});
        if (const prep::Project* p = project())
            for (const std::string& w : p->vocabulary) cpAction_->addItem("@" + qs(w));
    }
    cpAction_->setCurrentText(qs(c->action));
}

void MainWindow::toolCheckpointSelected(const std::string& character, int index) {
    cpCharacter_ = character;
    cpIndex_ = index;
    refreshCheckpointInspector();
    refreshSetupOverlay();
}

bool MainWindow::selectCheckpoint(const QString& character, int index) {
    toolCheckpointSelected(character.toStdString(), index);
    return cpIndex_ == index && index >= 0;
}

}  // namespace fray::editor
