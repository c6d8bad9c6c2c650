#include "graph_view.h"

#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <map>
#include <set>

namespace fray::editor {

GraphView::GraphView(QWidget* parent) : QWidget(parent) {
    setMinimumSize(200, 160);
    setToolTip("Click a node to list its actions; wheel zooms, drag pans. Red: outside the largest strongly connected set.");
}

void GraphView::setData(GraphViewData data) {
    data_ = std::move(data);
    const int n = data_.nodeCount;
    outDegree_.assign(static_cast<std::size_t>(std::max(0, n)), 0);
    nodeInScc_.assign(static_cast<std::size_t>(std::max(0, n)), 0);
    for (std::size_t a = 0; a < data_.startNode.size() && a < data_.endNode.size(); ++a) {
        const int s = data_.startNode[a], e = data_.endNode[a];
        if (s < 0 || s >= n || e < 0 || e >= n) continue;
        ++outDegree_[static_cast<std::size_t>(s)];
        if (a < data_.inLargestScc.size() && data_.inLargestScc[a]) {
            nodeInScc_[static_cast<std::size_t>(s)] = 1;
            nodeInScc_[static_cast<std::size_t>(e)] = 1;
        }
    }
    if (selected_ >= n) selected_ = -1;
    layout();
    update();
}

void GraphView::setSelectedNode(int node) {
    selected_ = node >= 0 && node < data_.nodeCount ? node : -1;
    update();
}

void GraphView::layout() {
    const int n = data_.nodeCount;
    positions_.assign(static_cast<std::size_t>(std::max(0, n)), {});
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * std::numbers::pi * i / std::max(1, n);
        positions_[static_cast<std::size_t>(i)] = {std::cos(a), std::sin(a)};
    }
    if (n < 2 || n > kForceLayoutMax) return;
    // Fruchterman-Reingold on the undirected node pairs, cooled linearly.
    std::set<std::pair<int, int>> pairs;
    for (std::size_t a = 0; a < data_.startNode.size() && a < data_.endNode.size(); ++a) {
        const int s = data_.startNode[a], e = data_.endNode[a];
        if (s != e && s >= 0 && e >= 0 && s < n && e < n) pairs.insert({std::min(s, e), std::max(s, e)});
    }
    const double k = std::sqrt(4.0 / n);
    const int iterations = 150;
    std::vector<QPointF> disp(static_cast<std::size_t>(n));
    for (int it = 0; it < iterations; ++it) {
        std::fill(disp.begin(), disp.end(), QPointF{0, 0});
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j) {
                QPointF d = positions_[static_cast<std::size_t>(i)] - positions_[static_cast<std::size_t>(j)];
                const double len = std::max(1e-3, std::hypot(d.x(), d.y()));
                const QPointF f = d / len * (k * k / len);
                disp[static_cast<std::size_t>(i)] += f;
                disp[static_cast<std::size_t>(j)] -= f;
            }
        for (auto [i, j] : pairs) {
            QPointF d = positions_[static_cast<std::size_t>(i)] - positions_[static_cast<std::size_t>(j)];
            const double len = std::max(1e-3, std::hypot(d.x(), d.y()));
            const QPointF f = d / len * (len * len / k);
            disp[static_cast<std::size_t>(i)] -= f;
            disp[static_cast<std::size_t>(j)] += f;
        }
        // A weak pull to the centre keeps isolated nodes near the rest.
        for (int i = 0; i < n; ++i) disp[static_cast<std::size_t>(i)] -= positions_[static_cast<std::size_t>(i)] * (1.5 * k);
        const double temperature = 0.1 * (1.0 - static_cast<double>(it) / iterations) + 0.002;
        for (int i = 0; i < n; ++i) {
            QPointF d = disp[static_cast<std::size_t>(i)];
            const double len = std::max(1e-9, std::hypot(d.x(), d.y()));
            QPointF& p = positions_[static_cast<std::size_t>(i)];
            p += d / len * std::min(len, temperature);
            p.setX(std::clamp(p.x(), -1.5, 1.5));
            p.setY(std::clamp(p.y(), -1.5, 1.5));
        }
    }
    // Centre, then fit into [-1, 1].
    QPointF mean(0, 0);
    for (const QPointF& p : positions_) mean += p / n;
    for (QPointF& p : positions_) p -= mean;
    double m = 1e-6;
    for (const QPointF& p : positions_) m = std::max({m, std::abs(p.x()), std::abs(p.y())});
    for (QPointF& p : positions_) p /= m;
}

QPointF GraphView::toWidget(QPointF p) const {
    const double s = 0.42 * std::min(width(), height()) * zoom_;
    return QPointF(width() / 2.0, height() / 2.0) + pan_ + p * s;
}

double GraphView::nodeRadius(int node) const {
    const int d = outDegree_[static_cast<std::size_t>(node)];
    const double base = data_.nodeCount > 200 ? 2.0 : 4.0;
    return std::min(base + 1.2 * std::sqrt(static_cast<double>(d)), 14.0) * std::sqrt(zoom_);
}

QPoint GraphView::nodePosition(int node) const {
    if (node < 0 || node >= data_.nodeCount) return {};
    return toWidget(positions_[static_cast<std::size_t>(node)]).toPoint();
}

int GraphView::nodeAt(QPoint pos) const {
    int best = -1;
    double bestDist = 1e9;
    for (int i = 0; i < data_.nodeCount; ++i) {
        const QPointF d = toWidget(positions_[static_cast<std::size_t>(i)]) - QPointF(pos);
        const double dist = std::hypot(d.x(), d.y());
        if (dist <= nodeRadius(i) + 3 && dist < bestDist) {
            bestDist = dist;
            best = i;
        }
    }
    return best;
}

void GraphView::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing);
    p.fillRect(rect(), QColor(34, 36, 40));
    if (data_.nodeCount <= 0) {
        p.setPen(QColor(170, 170, 170));
        p.drawText(rect(), Qt::AlignCenter, "No motion graph yet: Build graph (Ctrl+G)");
        return;
    }
    // Edges: a curved arrow per distinct (start, end) pair, thicker for more
    // actions; self-loops as small circles.
    std::map<std::pair<int, int>, std::pair<int, bool>> edges;  // -> count, any in SCC
    for (std::size_t a = 0; a < data_.startNode.size() && a < data_.endNode.size(); ++a) {
        auto& e = edges[{data_.startNode[a], data_.endNode[a]}];
        ++e.first;
        e.second = e.second || (a < data_.inLargestScc.size() && data_.inLargestScc[a]);
    }
    for (const auto& [key, value] : edges) {
        const auto [s, e] = key;
        if (s < 0 || e < 0 || s >= data_.nodeCount || e >= data_.nodeCount) continue;
        const bool touchesSelection = s == selected_ || e == selected_;
        QColor c = value.second ? QColor(120, 160, 210, 110) : QColor(220, 90, 90, 140);
        if (touchesSelection) c = s == selected_ ? QColor(255, 196, 84, 230) : QColor(120, 230, 160, 230);
        p.setPen(QPen(c, std::min(4.0, 0.6 + 0.4 * value.first)));
        const QPointF a = toWidget(positions_[static_cast<std::size_t>(s)]);
        const QPointF b = toWidget(positions_[static_cast<std::size_t>(e)]);
        if (s == e) {
            const double r = nodeRadius(s);
            p.setBrush(Qt::NoBrush);
            p.drawEllipse(a + QPointF(r, -r), r * 0.8, r * 0.8);
            continue;
        }
        const QPointF mid = (a + b) / 2.0;
        const QPointF d = b - a;
        const QPointF normal(-d.y() * 0.15, d.x() * 0.15);  // bend to the left: A->B and B->A do not overlap
        QPainterPath path(a);
        path.quadTo(mid + normal, b);
        p.setBrush(Qt::NoBrush);
        p.drawPath(path);
    }
    // Nodes.
    for (int i = 0; i < data_.nodeCount; ++i) {
        const QPointF c = toWidget(positions_[static_cast<std::size_t>(i)]);
        const double r = nodeRadius(i);
        QColor fill = nodeInScc_[static_cast<std::size_t>(i)] ? QColor(90, 140, 210) : QColor(210, 80, 80);
        if (i == selected_) fill = QColor(255, 196, 84);
        p.setPen(QPen(QColor(20, 20, 20), 1));
        p.setBrush(fill);
        p.drawEllipse(c, r, r);
        if (data_.nodeCount <= 80 || i == selected_) {
            p.setPen(QColor(230, 230, 230));
            p.drawText(c + QPointF(r + 2, -r), QString::number(i));
        }
    }
    p.setPen(QColor(200, 200, 200));
    p.drawText(rect().adjusted(6, 4, -6, -4), Qt::AlignLeft | Qt::AlignTop, data_.summary);
}

void GraphView::mousePressEvent(QMouseEvent* event) {
    const int node = nodeAt(event->position().toPoint());
    if (event->button() == Qt::LeftButton && node >= 0) {
        setSelectedNode(node);
        Q_EMIT nodeSelected(node);
        return;
    }
    panning_ = true;
    lastMouse_ = event->position().toPoint();
}

void GraphView::mouseMoveEvent(QMouseEvent* event) {
    if (!panning_) return;
    const QPoint p = event->position().toPoint();
    pan_ += QPointF(p - lastMouse_);
    lastMouse_ = p;
    update();
}

void GraphView::mouseReleaseEvent(QMouseEvent*) { panning_ = false; }

void GraphView::wheelEvent(QWheelEvent* event) {
    const double steps = event->angleDelta().y() / 120.0;
    zoom_ = std::clamp(zoom_ * std::pow(1.2, steps), 0.2, 20.0);
    update();
    event->accept();
}

}  // namespace fray::editor
