#pragma once
// The action track of a scene (thesis fig. 6.5), below the viewport: one row
// per character, each action a bar from its start to its end coloured by its
// first annotation (the legend names the colours), forced reactions hatched,
// hits marked with a red triangle on the attacker's row and a black one on
// the defender's (hollow when blocked), the playhead as a vertical line.
//
// Like TimelineView it holds no authoritative state: it draws a GanttData
// snapshot and reports what the user asked for through signals. Clicking a bar
// selects its character and seeks the playhead to the bar's start; clicking
// empty space in a row selects the row's character and seeks to the time
// under the pointer. The wheel zooms around the pointer, Shift+wheel pans,
// Home shows the whole scene. A right click on a bar asks for its context
// menu (barMenuRequested: replace, pin, unpin; MainWindow builds it); bars
// chosen by a pin are drawn with a white outline and a pin mark.
#include <QColor>
#include <QPoint>
#include <QString>
#include <QWidget>
#include <vector>

namespace fray::editor {

struct GanttBar {
    double start = 0, end = 0;  // scene time (s)
    QString label;              // the action's name
    QString annotation;         // its first annotation ("" when none): the colour
    bool forced = false;        // a reaction to a hit
    bool fallback = false;      // the planner had no legal action
    int action = -1;            // index in the scene's action library
    int pin = -1;               // the setup's pin that chose it (index in its pins), else -1: drawn marked
};

struct GanttHit {
    double time = 0;
    int attacker = 0, defender = 0;  // rows
    bool blocked = false;
};

struct GanttRow {
    QString name;
    QColor tint;                // the character's colour in the viewport
    std::vector<GanttBar> bars;  // time-ordered
};

struct GanttData {
    double duration = 0;
    std::vector<GanttRow> rows;
    std::vector<GanttHit> hits;
};

class GanttView : public QWidget {
    Q_OBJECT
public:
    explicit GanttView(QWidget* parent = nullptr);

    void setData(GanttData data);
    const GanttData& data() const { return data_; }
    void setTime(double t);
    double time() const { return time_; }
    void setSelectedRow(int row);
    int selectedRow() const { return selected_; }
    void frameAll();

    // The colour of an annotation (fixed for the common words, hashed for others).
    static QColor annotationColour(const QString& annotation);

    // Geometry, for tests that drive the view with real mouse events.
    int xOfTime(double t) const;
    double timeAtX(int x) const;
    int rowY(int row) const;  // the middle of a row
    // The row under y (-1: none) and the bar under (x, y) (-1: none).
    int rowAt(int y) const;
    int barAt(int row, int x) const;

    QSize sizeHint() const override { return {900, 160}; }
    QSize minimumSizeHint() const override { return {300, 60}; }

Q_SIGNALS:
    // A click on a bar (bar >= 0) or on the empty part of a row (bar -1).
    void barClicked(int row, int bar);
    void rowSelected(int row);
    void seekRequested(double time);
    // A right click on a bar: the window shows its menu at `global`.
    void barMenuRequested(int row, int bar, QPoint global);

protected:
    void paintEvent(QPaintEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;
    void contextMenuEvent(QContextMenuEvent* event) override;

private:
    static constexpr int kNameWidth = 90;
    static constexpr int kRulerHeight = 18;
    static constexpr int kLegendHeight = 16;
    int rowHeight() const;
    void clampView();

    GanttData data_;
    double time_ = 0;
    int selected_ = -1;
    double viewFirst_ = 0, viewLast_ = 1;
    bool scrubbing_ = false;
};

}  // namespace fray::editor
