#pragma once
// The action-level motion graph drawn as nodes (pose clusters) and edges
// (actions from the cluster of their start pose to the cluster of their end
// pose; SPEC 1.5). Node size grows with the actions leaving it; nodes and
// edges outside the largest strongly connected set are drawn in red. Clicking
// a node selects it (the window lists its actions); wheel zooms, drag pans.
//
// The layout is a deterministic force-directed one (fixed start on a circle,
// fixed iteration count), so the same graph is drawn the same way every time;
// graphs of more than kForceLayoutMax nodes stay on the circle.
#include <QPointF>
#include <QString>
#include <QWidget>
#include <cstdint>
#include <vector>

namespace fray::editor {

struct GraphViewData {
    int nodeCount = 0;
    std::vector<int> startNode, endNode;     // per action (edge)
    std::vector<std::uint8_t> inLargestScc;  // per action
    QString summary;                         // statistics line drawn in a corner
};

class GraphView : public QWidget {
    Q_OBJECT
public:
    static constexpr int kForceLayoutMax = 400;
    explicit GraphView(QWidget* parent = nullptr);
    void setData(GraphViewData data);
    const GraphViewData& data() const { return data_; }
    void setSelectedNode(int node);
    int selectedNode() const { return selected_; }
    // Widget position of a node's centre (for tests that click nodes).
    QPoint nodePosition(int node) const;
    QSize sizeHint() const override { return {420, 360}; }

Q_SIGNALS:
    void nodeSelected(int node);

protected:
    void paintEvent(QPaintEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;

private:
    void layout();
    QPointF toWidget(QPointF p) const;
    double nodeRadius(int node) const;
    int nodeAt(QPoint pos) const;

    GraphViewData data_;
    std::vector<QPointF> positions_;  // layout space, roughly [-1, 1]^2
    std::vector<int> outDegree_;
    std::vector<std::uint8_t> nodeInScc_;
    int selected_ = -1;
    double zoom_ = 1.0;
    QPointF pan_{0, 0};
    bool panning_ = false;
    QPoint lastMouse_;
};

}  // namespace fray::editor
