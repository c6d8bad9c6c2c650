#pragma once
// The timeline of one motion (thesis fig. 3.1, live): the acceleration
// profile with its high-acceleration bands and threshold, the action blocks
// with their names, the left and right foot-contact bands with the user's
// contact labels, the cut markers and the playhead.
//
// The view holds no authoritative state: it draws a TimelineData snapshot and
// reports what the user asked for through signals (move a cut, add one, merge
// two actions, label a foot over a range...). The window turns each request
// into an undo command on the document, and the document's change event
// brings back a new snapshot.
//
// Mouse: click or drag in the ruler or curve to scrub; drag a cut marker to
// move it (one undo step per drag); double-click to add a cut; right-click
// for a menu (add cut here, delete cut, merge with the next action); drag
// with the left button over a foot band to label it supported, with the
// right button to label it free. Wheel zooms around the pointer, Shift+wheel
// or a middle-button drag pans. Keys: Space play/pause, Left/Right one frame,
// Up/Down ten frames, Home frames the whole motion, Delete removes the cut
// under the playhead.
#include <QString>
#include <QWidget>
#include <cstdint>
#include <optional>
#include <vector>

namespace fray::editor {

struct TimelineContactLabel {
    int first = 0, last = 0;      // frames, inclusive
    std::optional<bool> left, right;
};

struct TimelineData {
    int frameCount = 0;
    double fps = 60.0;
    std::vector<float> acceleration;     // per frame (smoothed profile)
    double threshold = 0.0;              // high-acceleration threshold (same units)
    std::vector<std::uint8_t> highAccel; // per frame
    std::vector<std::uint8_t> contactLeft, contactRight;  // per frame: 1 supporting
    std::vector<int> cuts;               // first frames of actions 1..n
    std::vector<QString> actionNames;    // per action; a trailing '?' marks a proposal only
    std::vector<TimelineContactLabel> labels;
};

class TimelineView : public QWidget {
    Q_OBJECT
public:
    explicit TimelineView(QWidget* parent = nullptr);

    void setData(TimelineData data);
    const TimelineData& data() const { return data_; }
    void setPlayhead(int frame);
    int playhead() const { return playhead_; }
    void setSelectedAction(int action);
    int selectedAction() const { return selectedAction_; }
    // The visible frame range [first, last] (zoom and pan).
    double viewFirst() const { return viewFirst_; }
    double viewLast() const { return viewLast_; }
    void frameAll();
    void showFrames(double first, double last);
    static constexpr double kInitialSeconds = 20.0;

    // Geometry, for tests that drive the view with real mouse events.
    int xOfFrame(double frame) const;
    double frameAtX(int x) const;
    int rulerY() const;          // a y inside the ruler
    int curveY() const;          // a y inside the acceleration curve
    int actionsY() const;        // a y inside the action blocks
    int footY(int foot) const;   // a y inside the left (0) or right (1) contact band

    QSize sizeHint() const override { return {900, 190}; }
    QSize minimumSizeHint() const override { return {300, 150}; }

Q_SIGNALS:
    void playheadRequested(int frame);
    void playToggled();
    void actionSelected(int action);
    // A drag of the cut that was at `fromFrame` when the drag began, now at
    // `toFrame`; `finished` on release. Every step of one drag names the same
    // fromFrame so the document merges them into one undo step.
    void cutDragged(int fromFrame, int toFrame, bool finished);
    void cutAddRequested(int frame);
    void cutRemoveRequested(int frame);
    void mergeRequested(int action);  // merge action with action + 1
    void contactLabelRequested(int foot, int first, int last, bool supported);

protected:
    void paintEvent(QPaintEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void mouseDoubleClickEvent(QMouseEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;
    void contextMenuEvent(QContextMenuEvent* event) override;
    void resizeEvent(QResizeEvent* event) override;

private:
    enum class Drag { None, Scrub, Cut, Pan, Label };
    struct Rows {
        int ruler0, ruler1, curve0, curve1, actions0, actions1, left0, left1, right0, right1;
    };
    Rows rows() const;
    int clampFrame(double frame) const;
    int cutNear(int x) const;  // index of the cut marker within a few pixels of x, or -1
    int footAt(int y) const;   // 0, 1, or -1
    void zoomAround(double frame, double factor);
    void clampView();
    void requestPlayhead(int frame);

    TimelineData data_;
    int playhead_ = 0;
    int selectedAction_ = -1;
    double viewFirst_ = 0, viewLast_ = 1;
    bool viewSet_ = false;
    float curveMax_ = 1.0f;

    Drag drag_ = Drag::None;
    int dragCutFrom_ = 0;      // the cut's frame when the drag began
    int dragCutLast_ = 0;      // the last frame reported
    int dragFoot_ = -1;
    int dragLabelStart_ = 0, dragLabelEnd_ = 0;
    bool dragLabelSupported_ = true;
    int panStartX_ = 0;
    double panStartFirst_ = 0;
};

}  // namespace fray::editor
