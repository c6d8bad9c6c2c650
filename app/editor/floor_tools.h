#pragma once
// Tools on the viewport's floor (issue 23), a small class hierarchy after
// Tiled's AbstractTool: each tool has a name, a status tip and a cursor, is
// activated and deactivated, gets the viewport's left-button mouse events
// (picked through the camera onto the floor, y = 0) and its keys, and puts its
// own options on the tool bar. Every stroke or drag is one undo step on the
// document (ProjectDocument's setup commands with a DragId); the tools never
// change the project themselves.
//
//  - Brush / Eraser: paint or erase the setup's floor bitmap (radius; an
//    optional start time makes the stroke a domino chain start).
//  - Fill: flood-fills the region clicked.
//  - Text: stamps letters (the thesis' falling letters), one start time per letter.
//  - Trajectory: clicks add points of a polyline (Enter or a double-click
//    ends it), an arc (3 clicks) or a circle (centre, then a point on it)
//    for the selected character.
//  - Move: drags a checkpoint, a trajectory point or a character's start
//    (Shift: the character's whole team).
//  - Checkpoint: a click on the selected character's trajectory adds a
//    checkpoint there (with the tool bar's time and action); a press on a
//    checkpoint selects it for the Scene panel's checkpoint inspector and
//    dragging it moves it along the floor.
//  - Rat path: a drag draws the rat's trajectory (rat setups).
//  - Run direction: a drag draws an arrow, the football runner's direction
//    from the tool bar's time on (football setups).
//  - Command: a click places a timed user command (move there, punch, kick,
//    avoid) for the main character of a one-vs-many setup.
#include <QCursor>
#include <QObject>
#include <QPointF>
#include <QString>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "fray/core/result.h"
#include "fray/render/camera.h"
#include "fray/setup/scene_setup.h"

class QDoubleSpinBox;
class QComboBox;
class QKeyEvent;
class QMouseEvent;
class QToolBar;

namespace fray::authoring {
class ProjectDocument;
}

namespace fray::editor {

// The floor point (x, z) under a viewport pixel: the ray from the camera's eye
// through the pixel meets the plane y = 0; nullopt when it points at the sky.
std::optional<glm::vec2> pickFloor(const render::OrbitCamera& camera, float aspect, QPointF pixel, QSizeF viewport);
// The pixel where a floor point shows (for tests and hit-testing); nullopt behind the camera.
std::optional<QPointF> floorToPixel(const render::OrbitCamera& camera, float aspect, glm::vec2 floor, QSizeF viewport);

// What a tool works on: the document, the setup being edited, the character
// selected; and where it reports.
class FloorToolHost {
public:
    virtual ~FloorToolHost() = default;
    virtual authoring::ProjectDocument* toolDocument() = 0;
    virtual std::string toolSetup() = 0;          // "" : none selected
    virtual std::string toolCharacter() = 0;      // the selected setup character ("" : none)
    virtual void toolMessage(const QString& message, bool error) = 0;
    virtual QWidget* toolDialogParent() = 0;      // for the Text tool's input
    // A checkpoint was picked on the floor (index < 0: none).
    virtual void toolCheckpointSelected(const std::string& character, int index) { (void)character, (void)index; }
};

class FloorTool : public QObject {
    Q_OBJECT
public:
    FloorTool(QString name, QString statusTip, FloorToolHost& host) : name_(std::move(name)), tip_(std::move(statusTip)), host_(host) {}
    const QString& name() const { return name_; }
    const QString& statusTip() const { return tip_; }
    virtual QCursor cursor() const { return Qt::CrossCursor; }
    virtual void activate() {}
    virtual void deactivate() {}
    virtual void mousePressed(glm::vec2 floor, QMouseEvent* event) = 0;
    virtual void mouseMoved(glm::vec2 floor, QMouseEvent* event) { (void)floor, (void)event; }
    virtual void mouseReleased(glm::vec2 floor, QMouseEvent* event) { (void)floor, (void)event; }
    virtual void mouseDoubleClicked(glm::vec2 floor, QMouseEvent* event) { (void)floor, (void)event; }
    // True when the key was the tool's.
    virtual bool keyPressed(QKeyEvent* event) { (void)event; return false; }
    // The tool's options, added to the tool bar while it is active.
    virtual void populateToolBar(QToolBar* bar) { (void)bar; }

protected:
    // Reports a failed edit (nothing changed) to the user.
    bool check(const Status& s);
    FloorToolHost& host() { return host_; }

private:
    QString name_, tip_;
    FloorToolHost& host_;
};

// Brush and eraser: one drag is one stroke, one undo step.
class BrushTool : public FloorTool {
    Q_OBJECT
public:
    BrushTool(bool erase, FloorToolHost& host);
    void mousePressed(glm::vec2 floor, QMouseEvent* event) override;
    void mouseMoved(glm::vec2 floor, QMouseEvent* event) override;
    void mouseReleased(glm::vec2 floor, QMouseEvent* event) override;
    void populateToolBar(QToolBar* bar) override;
    double radius = 0.5;                 // m
    std::optional<double> startTime;     // domino chain start of a brush stroke (s)

private:
    bool erase_;
    int drag_ = 0;
    glm::vec2 last_{0.0f};
};

class FillTool : public FloorTool {
    Q_OBJECT
public:
    explicit FillTool(FloorToolHost& host);
    void mousePressed(glm::vec2 floor, QMouseEvent* event) override;
};

class TextTool : public FloorTool {
    Q_OBJECT
public:
    explicit TextTool(FloorToolHost& host);
    void mousePressed(glm::vec2 floor, QMouseEvent* event) override;
    void populateToolBar(QToolBar* bar) override;
    // The text stamped by the next click ("" : asked for in a dialog).
    QString text;
    double letterHeight = 2.0;
    std::optional<double> startTime = 0.5;
    double letterInterval = 1.0;
};

class TrajectoryTool : public FloorTool {
    Q_OBJECT
public:
    TrajectoryTool(setup::TrajectoryShape shape, FloorToolHost& host);
    void deactivate() override { points_.clear(); }
    void mousePressed(glm::vec2 floor, QMouseEvent* event) override;
    void mouseDoubleClicked(glm::vec2 floor, QMouseEvent* event) override;
    bool keyPressed(QKeyEvent* event) override;
    // Ends the trajectory being drawn (an empty one is refused with a message).
    void finish();
    const std::vector<setup::Point>& points() const { return points_; }

private:
    setup::TrajectoryShape shape_;
    std::vector<setup::Point> points_;
};

// Drags whatever is nearest within reach: a checkpoint, a trajectory point or
// a character's start (Shift: the team).
class MoveTool : public FloorTool {
    Q_OBJECT
public:
    explicit MoveTool(FloorToolHost& host);
    QCursor cursor() const override { return Qt::OpenHandCursor; }
    void mousePressed(glm::vec2 floor, QMouseEvent* event) override;
    void mouseMoved(glm::vec2 floor, QMouseEvent* event) override;
    void mouseReleased(glm::vec2 floor, QMouseEvent* event) override;
    static constexpr double kReach = 0.6;  // m

private:
    enum class What { None, Checkpoint, Point, Start, Team } what_ = What::None;
    std::string character_;
    int index_ = -1, side_ = 0, drag_ = 0;
    glm::vec2 last_{0.0f};
    setup::Placement start_;
};

// Adds, selects and drags checkpoints of trajectories.
class CheckpointTool : public FloorTool {
    Q_OBJECT
public:
    explicit CheckpointTool(FloorToolHost& host);
    void mousePressed(glm::vec2 floor, QMouseEvent* event) override;
    void mouseMoved(glm::vec2 floor, QMouseEvent* event) override;
    void mouseReleased(glm::vec2 floor, QMouseEvent* event) override;
    void populateToolBar(QToolBar* bar) override;
    // What the next added checkpoint gets.
    std::optional<double> time;
    std::string action;  // "" : none; "@annotation" or an action name
    // How far from the trajectory a click may be to add a checkpoint (m).
    static constexpr double kSnap = 1.0;

private:
    std::string character_;
    int index_ = -1, drag_ = 0;
    bool moved_ = false;
};

// Draws the rat's trajectory of a rat setup: one drag, one undo step.
class RatPathTool : public FloorTool {
    Q_OBJECT
public:
    explicit RatPathTool(FloorToolHost& host);
    void mousePressed(glm::vec2 floor, QMouseEvent* event) override;
    void mouseMoved(glm::vec2 floor, QMouseEvent* event) override;
    void mouseReleased(glm::vec2 floor, QMouseEvent* event) override;
    static constexpr double kSpacing = 0.5;  // m between the points kept

private:
    std::vector<setup::Point> points_;
    int drag_ = 0;
    bool active_ = false;
};

// Draws a football running-direction arrow: press where it starts, release
// where it points; from `time` on the runner heads that way (0 = +Z, the goal).
class DirectionTool : public FloorTool {
    Q_OBJECT
public:
    explicit DirectionTool(FloorToolHost& host);
    void mousePressed(glm::vec2 floor, QMouseEvent* event) override;
    void mouseReleased(glm::vec2 floor, QMouseEvent* event) override;
    void populateToolBar(QToolBar* bar) override;
    double time = 0;  // s

private:
    std::optional<glm::vec2> from_;
};

// Places a timed user command of a one-vs-many setup where it is clicked.
class CommandTool : public FloorTool {
    Q_OBJECT
public:
    explicit CommandTool(FloorToolHost& host);
    void mousePressed(glm::vec2 floor, QMouseEvent* event) override;
    void populateToolBar(QToolBar* bar) override;
    double time = 0;              // s
    std::string action = "move";  // move, punch, kick, avoid
};

}  // namespace fray::editor
