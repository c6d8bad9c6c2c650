#include "floor_tools.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QInputDialog>
#include <QKeyEvent>
#include <QLabel>
#include <QLineEdit>
#include <QMouseEvent>
#include <QToolBar>
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "fray/authoring/project_document.h"

namespace fray::editor {

namespace {

QString qs(const std::string& s) { return QString::fromStdString(s); }
setup::Point pt(glm::vec2 p) { return {static_cast<double>(p.x), static_cast<double>(p.y)}; }
double dist(setup::Point a, glm::vec2 b) { return std::hypot(a.x - static_cast<double>(b.x), a.z - static_cast<double>(b.y)); }

QDoubleSpinBox* option(QToolBar* bar, const char* name, const QString& label, double lo, double hi, double value,
                       const QString& suffix) {
    bar->addWidget(new QLabel(" " + label + " "));
    auto* s = new QDoubleSpinBox;
    s->setObjectName(name);
    s->setRange(lo, hi);
    s->setDecimals(2);
    s->setValue(value);
    s->setSuffix(suffix);
    bar->addWidget(s);
    return s;
}

}  // namespace

std::optional<glm::vec2> pickFloor(const render::OrbitCamera& camera, float aspect, QPointF pixel, QSizeF viewport) {
    if (viewport.width() <= 0 || viewport.height() <= 0) return std::nullopt;
    const float nx = static_cast<float>(2.0 * pixel.x() / viewport.width() - 1.0);
    const float ny = static_cast<float>(1.0 - 2.0 * pixel.y() / viewport.height());
    const float t = std::tan(camera.fovY * 0.5f);
    const glm::vec3 dir = glm::normalize(camera.forward() + nx * t * aspect * camera.right() + ny * t * camera.up());
    const glm::vec3 eye = camera.eye();
    if (std::abs(dir.y) < 1e-6f) return std::nullopt;
    const float s = -eye.y / dir.y;
    if (s <= 0.0f) return std::nullopt;  // the ray leaves the floor behind
    const glm::vec3 hit = eye + s * dir;
    return glm::vec2(hit.x, hit.z);
}

std::optional<QPointF> floorToPixel(const render::OrbitCamera& camera, float aspect, glm::vec2 floor, QSizeF viewport) {
    const glm::vec3 v = glm::vec3(floor.x, 0.0f, floor.y) - camera.eye();
    const float z = glm::dot(v, camera.forward());
    if (z <= 1e-4f) return std::nullopt;
    const float t = std::tan(camera.fovY * 0.5f);
    const float x = glm::dot(v, camera.right()) / (z * t * aspect);
    const float y = glm::dot(v, camera.up()) / (z * t);
    return QPointF((static_cast<double>(x) + 1.0) * 0.5 * viewport.width(), (1.0 - static_cast<double>(y)) * 0.5 * viewport.height());
}

bool FloorTool::check(const Status& s) {
    if (!s) host_.toolMessage(qs(s.error().message), true);
    return static_cast<bool>(s);
}

// ---- brush and eraser

BrushTool::BrushTool(bool erase, FloorToolHost& host)
    : FloorTool(erase ? "Eraser" : "Brush",
                erase ? "Drag on the floor to erase the painted area" : "Drag on the floor to paint the area where people fall",
                host),
      erase_(erase) {}

void BrushTool::mousePressed(glm::vec2 floor, QMouseEvent*) {
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || host().toolSetup().empty()) return host().toolMessage("Select a scene setup to paint its floor", true);
    drag_ = doc->beginDrag();
    last_ = floor;
    setup::FloorStroke stroke;
    stroke.tool = erase_ ? setup::FloorStroke::Tool::Eraser : setup::FloorStroke::Tool::Brush;
    stroke.points = {pt(floor)};
    stroke.radius = radius;
    if (!erase_) stroke.startTime = startTime;
    auto r = doc->paintFloor(host().toolSetup(), stroke, drag_);
    if (!r) {
        drag_ = 0;
        check(r.error());
    }
}

void BrushTool::mouseMoved(glm::vec2 floor, QMouseEvent*) {
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || drag_ == 0 || glm::length(floor - last_) < 1e-3f) return;
    setup::FloorStroke stroke;
    stroke.tool = erase_ ? setup::FloorStroke::Tool::Eraser : setup::FloorStroke::Tool::Brush;
    stroke.points = {pt(last_), pt(floor)};
    stroke.radius = radius;
    last_ = floor;
    auto r = doc->paintFloor(host().toolSetup(), stroke, drag_);
    if (!r) check(r.error());
}

void BrushTool::mouseReleased(glm::vec2 floor, QMouseEvent* event) {
    mouseMoved(floor, event);
    drag_ = 0;
}

void BrushTool::populateToolBar(QToolBar* bar) {
    QDoubleSpinBox* size = option(bar, erase_ ? "eraserRadius" : "brushRadius", "radius", 0.05, 10.0, radius, " m");
    connect(size, &QDoubleSpinBox::valueChanged, this, [this](double v) { radius = v; });
    if (erase_) return;
    QDoubleSpinBox* start = option(bar, "brushStart", "falls from", -1, 3600, startTime.value_or(-1), " s");
    start->setSpecialValueText("no start");
    start->setToolTip("The domino chain starts where this stroke begins, at this time (no start: paint only)");
    connect(start, &QDoubleSpinBox::valueChanged, this, [this](double v) {
        if (v < 0) startTime.reset();
        else startTime = v;
    });
}

// ---- fill

FillTool::FillTool(FloorToolHost& host) : FloorTool("Fill", "Click inside an area to fill it", host) {}

void FillTool::mousePressed(glm::vec2 floor, QMouseEvent*) {
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || host().toolSetup().empty()) return host().toolMessage("Select a scene setup to paint its floor", true);
    setup::FloorStroke stroke;
    stroke.tool = setup::FloorStroke::Tool::Fill;
    stroke.points = {pt(floor)};
    auto r = doc->paintFloor(host().toolSetup(), stroke);
    if (!r) check(r.error());
}

// ---- text

TextTool::TextTool(FloorToolHost& host)
    : FloorTool("Text", "Click where the first letter goes: letters of people falling one after another", host) {}

void TextTool::mousePressed(glm::vec2 floor, QMouseEvent*) {
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || host().toolSetup().empty()) return host().toolMessage("Select a scene setup to paint its floor", true);
    QString t = text;
    if (t.isEmpty()) {
        bool ok = false;
        t = QInputDialog::getText(host().toolDialogParent(), "Text stamp", "Letters (A-Z, 0-9, space)", QLineEdit::Normal, "FRAY", &ok);
        if (!ok || t.isEmpty()) return;
    }
    setup::FloorStroke stroke;
    stroke.tool = setup::FloorStroke::Tool::Text;
    stroke.points = {pt(floor)};
    stroke.text = t.toStdString();
    stroke.letterHeight = letterHeight;
    stroke.startTime = startTime;
    stroke.letterInterval = letterInterval;
    auto r = doc->paintFloor(host().toolSetup(), stroke);
    if (!r) check(r.error());
}

void TextTool::populateToolBar(QToolBar* bar) {
    QDoubleSpinBox* h = option(bar, "textHeight", "letter height", 0.3, 20, letterHeight, " m");
    connect(h, &QDoubleSpinBox::valueChanged, this, [this](double v) { letterHeight = v; });
    QDoubleSpinBox* every = option(bar, "textInterval", "a letter every", 0, 60, letterInterval, " s");
    connect(every, &QDoubleSpinBox::valueChanged, this, [this](double v) { letterInterval = v; });
}

// ---- trajectories

TrajectoryTool::TrajectoryTool(setup::TrajectoryShape shape, FloorToolHost& host)
    : FloorTool(shape == setup::TrajectoryShape::Polyline ? "Polyline"
                : shape == setup::TrajectoryShape::Arc    ? "Arc"
                                                          : "Circle",
                shape == setup::TrajectoryShape::Polyline ? "Click the points of the selected character's path; Enter or a double-click ends it"
                : shape == setup::TrajectoryShape::Arc    ? "Click the arc's start, a point on it and its end"
                                                          : "Click the circle's centre, then a point on it (where it starts)",
                host),
      shape_(shape) {}

void TrajectoryTool::mousePressed(glm::vec2 floor, QMouseEvent*) {
    points_.push_back(pt(floor));
    const std::size_t needed = shape_ == setup::TrajectoryShape::Arc ? 3 : shape_ == setup::TrajectoryShape::Circle ? 2 : 0;
    if (needed > 0 && points_.size() == needed) finish();
    else host().toolMessage(QString("%1 point%2; %3").arg(points_.size()).arg(points_.size() == 1 ? "" : "s").arg(statusTip()), false);
}

void TrajectoryTool::mouseDoubleClicked(glm::vec2, QMouseEvent*) {
    if (shape_ == setup::TrajectoryShape::Polyline) finish();
}

bool TrajectoryTool::keyPressed(QKeyEvent* event) {
    if (event->key() == Qt::Key_Return || event->key() == Qt::Key_Enter) {
        finish();
        return true;
    }
    if (event->key() == Qt::Key_Escape) {
        points_.clear();
        host().toolMessage("Trajectory dropped", false);
        return true;
    }
    return false;
}

void TrajectoryTool::finish() {
    std::vector<setup::Point> points = std::move(points_);
    points_.clear();
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || host().toolSetup().empty()) return host().toolMessage("Select a scene setup to draw its trajectories", true);
    if (points.empty()) return host().toolMessage("The trajectory is empty: click its points on the floor first", true);
    const std::string character = host().toolCharacter();
    if (character.empty()) return host().toolMessage("Select the character who follows the trajectory (Scene panel)", true);
    setup::Trajectory t;
    t.character = character;
    t.shape = shape_;
    t.points = std::move(points);
    t.loop = shape_ == setup::TrajectoryShape::Circle;
    // A character has one trajectory: a new one replaces it (one undo step).
    auto current = doc->sceneSetup(host().toolSetup());
    bool had = false;
    if (current)
        for (const setup::Trajectory& old : current->trajectories) had = had || old.character == character;
    if (had) {
        doc->undoStack()->beginMacro("Redraw the trajectory of " + qs(character));
        const bool removed = check(doc->removeTrajectory(host().toolSetup(), character));
        const bool added = removed && check(doc->addTrajectory(host().toolSetup(), t));
        doc->undoStack()->endMacro();
        if (removed && !added) doc->undoStack()->undo();
        return;
    }
    check(doc->addTrajectory(host().toolSetup(), t));
}

// ---- move

MoveTool::MoveTool(FloorToolHost& host)
    : FloorTool("Move", "Drag a checkpoint, a trajectory point or a character's start (Shift: the whole team)", host) {}

void MoveTool::mousePressed(glm::vec2 floor, QMouseEvent* event) {
    what_ = What::None;
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || host().toolSetup().empty()) return;
    auto s = doc->sceneSetup(host().toolSetup());
    if (!s) return;
    double best = kReach;
    for (const setup::Trajectory& t : s->trajectories) {
        for (std::size_t i = 0; i < t.checkpoints.size(); ++i)
            if (const double d = dist(t.checkpoints[i].pos, floor); d < best)
                best = d, what_ = What::Checkpoint, character_ = t.character, index_ = static_cast<int>(i);
        for (std::size_t i = 0; i < t.points.size(); ++i)
            if (const double d = dist(t.points[i], floor); d < best)
                best = d, what_ = What::Point, character_ = t.character, index_ = static_cast<int>(i);
    }
    for (const setup::SetupCharacter& c : setup::characters(*s)) {
        if (const double d = dist({c.start.x, c.start.z}, floor); d < best) {
            best = d, what_ = (event->modifiers() & Qt::ShiftModifier) ? What::Team : What::Start, character_ = c.name;
            side_ = c.side, start_ = c.start;
        }
    }
    if (what_ == What::None) return host().toolMessage("Nothing to move here: press on a checkpoint, a path point or a start", false);
    drag_ = doc->beginDrag();
    last_ = floor;
}

void MoveTool::mouseMoved(glm::vec2 floor, QMouseEvent*) {
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || what_ == What::None) return;
    const std::string setupName = host().toolSetup();
    bool ok = true;
    switch (what_) {
    case What::Checkpoint: ok = check(doc->moveCheckpoint(setupName, character_, index_, pt(floor), drag_)); break;
    case What::Point: ok = check(doc->moveTrajectoryPoint(setupName, character_, index_, pt(floor), drag_)); break;
    case What::Start: {
        setup::Placement p = start_;
        p.x = floor.x, p.z = floor.y;
        ok = check(doc->setCharacterStart(setupName, character_, p, drag_));
        break;
    }
    case What::Team:
        ok = check(doc->moveTeam(setupName, side_, floor.x - last_.x, floor.y - last_.y, drag_));
        break;
    case What::None: break;
    }
    last_ = floor;
    if (!ok) what_ = What::None;
}

void MoveTool::mouseReleased(glm::vec2 floor, QMouseEvent* event) {
    mouseMoved(floor, event);
    what_ = What::None;
    drag_ = 0;
}

}  // namespace fray::editor

namespace fray::editor {

namespace {

double mm(double v) { return std::round(v * 1000.0) / 1000.0; }
setup::Point mmPoint(glm::vec2 p) { return {mm(static_cast<double>(p.x)), mm(static_cast<double>(p.y))}; }

// A time option whose lowest value means "none".
QDoubleSpinBox* timeOption(QToolBar* bar, const char* name, const QString& label, std::optional<double> value, const QString& none) {
    QDoubleSpinBox* s = option(bar, name, label, none.isEmpty() ? 0 : -1, 3600, value.value_or(none.isEmpty() ? 0 : -1), " s");
    if (!none.isEmpty()) s->setSpecialValueText(none);
    return s;
}

}  // namespace

// ---- checkpoints

CheckpointTool::CheckpointTool(FloorToolHost& host)
    : FloorTool("Checkpoint",
                "Click on the selected character's trajectory to add a checkpoint (time and action from the tool bar); "
                "press on a checkpoint to select it for the Scene panel, drag it to move it",
                host) {}

void CheckpointTool::mousePressed(glm::vec2 floor, QMouseEvent*) {
    index_ = -1, drag_ = 0, moved_ = false;
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || host().toolSetup().empty()) return host().toolMessage("Select a scene setup to edit its checkpoints", true);
    auto s = doc->sceneSetup(host().toolSetup());
    if (!s) return (void)check(s.error());
    // An existing checkpoint within reach: select it (and drag it).
    double best = MoveTool::kReach;
    for (const setup::Trajectory& t : s->trajectories)
        for (std::size_t i = 0; i < t.checkpoints.size(); ++i)
            if (const double d = dist(t.checkpoints[i].pos, floor); d < best) best = d, character_ = t.character, index_ = static_cast<int>(i);
    if (index_ >= 0) {
        drag_ = doc->beginDrag();
        host().toolCheckpointSelected(character_, index_);
        return;
    }
    // Else a new checkpoint on the selected character's trajectory, where the click is nearest to it.
    const std::string character = host().toolCharacter();
    if (character.empty()) return host().toolMessage("Select the character whose trajectory gets the checkpoint", true);
    const setup::Trajectory* t = nullptr;
    for (const setup::Trajectory& c : s->trajectories)
        if (c.character == character) t = &c;
    if (!t) return host().toolMessage(qs("'" + character + "' has no trajectory: draw one first (Polyline, Arc or Circle)"), true);
    auto line = setup::sampleTrajectory(*t, 0.05);
    if (!line) return (void)check(line.error());
    double near = 0;
    (void)setup::trajectoryParameter(*line, pt(floor), &near);
    if (near > kSnap) {
        return host().toolMessage(QString("Click within %1 m of %2's trajectory to add a checkpoint").arg(kSnap).arg(qs(character)), true);
    }
    setup::Point on = (*line)[0];
    double bestOn = 1e30;
    for (const setup::Point& p : *line)
        if (const double d = dist(p, floor); d < bestOn) bestOn = d, on = p;
    setup::SetupCheckpoint c;
    c.pos = {mm(on.x), mm(on.z)};
    c.time = time;
    c.action = action;
    auto added = doc->addCheckpoint(host().toolSetup(), character, c);
    if (!added) return (void)check(added.error());
    character_ = character;
    host().toolCheckpointSelected(character, *added);
    host().toolMessage(QString("Checkpoint %1 of %2 added").arg(*added + 1).arg(qs(character)), false);
    index_ = -1;  // a click adds; dragging moves existing checkpoints only
}

void CheckpointTool::mouseMoved(glm::vec2 floor, QMouseEvent*) {
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || index_ < 0 || drag_ == 0) return;
    moved_ = true;
    if (!check(doc->moveCheckpoint(host().toolSetup(), character_, index_, mmPoint(floor), drag_))) index_ = -1;
}

void CheckpointTool::mouseReleased(glm::vec2 floor, QMouseEvent* event) {
    if (moved_) mouseMoved(floor, event);
    index_ = -1, drag_ = 0, moved_ = false;
}

void CheckpointTool::populateToolBar(QToolBar* bar) {
    QDoubleSpinBox* t = timeOption(bar, "checkpointToolTime", "time", time, "no time");
    t->setToolTip("New checkpoints are not to be passed before this time (no time: whenever)");
    connect(t, &QDoubleSpinBox::valueChanged, this, [this](double v) {
        if (v < 0) time.reset();
        else time = v;
    });
    bar->addWidget(new QLabel(" action "));
    auto* a = new QComboBox;
    a->setObjectName("checkpointToolAction");
    a->setEditable(true);
    a->addItems({"", "@punch", "@kick", "@avoid", "@attack", "@defence"});
    a->setCurrentText(qs(action));
    a->setToolTip("The action new checkpoints require there: @annotation or an action name (empty: none)");
    connect(a, &QComboBox::currentTextChanged, this, [this](const QString& v) { action = v.trimmed().toStdString(); });
    bar->addWidget(a);
}

// ---- the rat's trajectory

RatPathTool::RatPathTool(FloorToolHost& host)
    : FloorTool("Rat path", "Drag the rat's trajectory on the floor (rat setups): one drag, one undo step", host) {}

void RatPathTool::mousePressed(glm::vec2 floor, QMouseEvent*) {
    active_ = false;
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || host().toolSetup().empty()) return host().toolMessage("Select a rat setup to draw the rat's trajectory", true);
    auto s = doc->sceneSetup(host().toolSetup());
    if (!s) return (void)check(s.error());
    if (s->kind != setup::SetupKind::Rat) return host().toolMessage(qs("'" + s->name + "' is not a rat setup: the rat's trajectory belongs to rat setups"), true);
    points_ = {mmPoint(floor)};
    drag_ = doc->beginDrag();
    active_ = true;
}

void RatPathTool::mouseMoved(glm::vec2 floor, QMouseEvent*) {
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || !active_ || dist(points_.back(), floor) < kSpacing) return;
    points_.push_back(mmPoint(floor));
    // Shown while drawn: every change merges into the drag's one undo step.
    if (!check(doc->setRatPath(host().toolSetup(), points_, drag_))) active_ = false;
}

void RatPathTool::mouseReleased(glm::vec2 floor, QMouseEvent* event) {
    if (!active_) return;
    if (dist(points_.back(), floor) > 0.05) {
        points_.push_back(mmPoint(floor));
        (void)check(host().toolDocument()->setRatPath(host().toolSetup(), points_, drag_));
    } else if (points_.size() < 2) {
        host().toolMessage("The rat's trajectory is empty: drag along the floor to draw it", true);
    }
    (void)event;
    active_ = false, drag_ = 0;
    points_.clear();
}

// ---- football running directions

DirectionTool::DirectionTool(FloorToolHost& host)
    : FloorTool("Run direction",
                "Drag an arrow on the floor: from the tool bar's time on the football runner heads that way (0 degrees: "
                "straight at the goal line, +Z)",
                host) {}

void DirectionTool::mousePressed(glm::vec2 floor, QMouseEvent*) {
    from_.reset();
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || host().toolSetup().empty()) return host().toolMessage("Select a football setup to draw its running directions", true);
    auto s = doc->sceneSetup(host().toolSetup());
    if (!s) return (void)check(s.error());
    if (s->kind != setup::SetupKind::Football) return host().toolMessage(qs("'" + s->name + "' is not a football setup: running directions belong to football setups"), true);
    from_ = floor;
}

void DirectionTool::mouseReleased(glm::vec2 floor, QMouseEvent*) {
    if (!from_) return;
    const glm::vec2 from = *from_;
    from_.reset();
    const glm::vec2 d = floor - from;
    if (glm::length(d) < 0.3f) return host().toolMessage("Drag further: the arrow points where you release the button", true);
    authoring::ProjectDocument* doc = host().toolDocument();
    auto s = doc->sceneSetup(host().toolSetup());
    if (!s) return (void)check(s.error());
    setup::RunDirection r;
    r.time = time;
    r.headingDeg = std::round(std::atan2(static_cast<double>(d.x), static_cast<double>(d.y)) * 180.0 / 3.14159265358979323846 * 10.0) / 10.0;
    r.at = mmPoint(from);
    // One arrow per time: a new one at the same time replaces it; the list stays in time order.
    std::vector<setup::RunDirection> all = setup::runDirections(*s);
    std::erase_if(all, [&](const setup::RunDirection& o) { return std::fabs(o.time - r.time) < 1e-6; });
    auto at = std::find_if(all.begin(), all.end(), [&](const setup::RunDirection& o) { return o.time > r.time; });
    all.insert(at, r);
    if (check(doc->setRunDirections(host().toolSetup(), all)))
        host().toolMessage(QString("Runs at %1 degrees from %2 s").arg(r.headingDeg).arg(r.time), false);
}

void DirectionTool::populateToolBar(QToolBar* bar) {
    QDoubleSpinBox* t = timeOption(bar, "directionTime", "from", time, {});
    t->setToolTip("The runner takes the arrow's direction from this time on");
    connect(t, &QDoubleSpinBox::valueChanged, this, [this](double v) { time = v; });
}

// ---- one-vs-many commands

CommandTool::CommandTool(FloorToolHost& host)
    : FloorTool("Command",
                "Click on the floor to give the main character a command at the tool bar's time: move there, punch, kick or avoid "
                "(one-vs-many setups)",
                host) {}

void CommandTool::mousePressed(glm::vec2 floor, QMouseEvent*) {
    authoring::ProjectDocument* doc = host().toolDocument();
    if (!doc || host().toolSetup().empty()) return host().toolMessage("Select a one-vs-many setup to give its commands", true);
    auto s = doc->sceneSetup(host().toolSetup());
    if (!s) return (void)check(s.error());
    if (s->kind != setup::SetupKind::OneVsMany)
        return host().toolMessage(qs("'" + s->name + "' is not a one-vs-many setup: timed commands belong to one-vs-many setups"), true);
    setup::TimedCommand c;
    c.time = time;
    c.action = action;
    c.at = mmPoint(floor);
    std::vector<setup::TimedCommand> all = setup::timedCommands(*s);
    auto at = std::find_if(all.begin(), all.end(), [&](const setup::TimedCommand& o) { return o.time > c.time; });
    all.insert(at, c);
    if (check(doc->setTimedCommands(host().toolSetup(), all)))
        host().toolMessage(QString("Command %1 at %2 s").arg(qs(c.action)).arg(c.time), false);
}

void CommandTool::populateToolBar(QToolBar* bar) {
    bar->addWidget(new QLabel(" command "));
    auto* a = new QComboBox;
    a->setObjectName("commandAction");
    a->addItems({"move", "punch", "kick", "avoid"});
    a->setCurrentText(qs(action));
    a->setToolTip("move: the main character walks to the place clicked; punch, kick, avoid: the patches it prefers from then on");
    connect(a, &QComboBox::currentTextChanged, this, [this](const QString& v) { action = v.toStdString(); });
    bar->addWidget(a);
    QDoubleSpinBox* t = timeOption(bar, "commandTime", "at", time, {});
    connect(t, &QDoubleSpinBox::valueChanged, this, [this](double v) { time = v; });
}

}  // namespace fray::editor
