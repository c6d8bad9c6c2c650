#include "gantt_view.h"

#include <QContextMenuEvent>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <map>

namespace fray::editor {

namespace {

// Fixed colours of the demo vocabulary's words and the annotation groups.
const std::map<QString, QColor>& fixedColours() {
    static const std::map<QString, QColor> colours = {
        {"punch", QColor(214, 48, 49)},     {"kick", QColor(230, 126, 34)},    {"attack", QColor(192, 57, 43)},
        {"block", QColor(41, 98, 214)},     {"avoid", QColor(0, 168, 190)},    {"dodge", QColor(0, 150, 136)},
        {"step", QColor(76, 175, 80)},      {"walk", QColor(56, 142, 60)},     {"run", QColor(27, 94, 32)},
        {"idle", QColor(158, 158, 158)},    {"turn", QColor(205, 180, 40)},    {"transition", QColor(190, 160, 110)},
        {"falling", QColor(142, 68, 173)},  {"fall", QColor(142, 68, 173)},    {"pushed", QColor(233, 30, 140)},
        {"stagger", QColor(233, 30, 140)},  {"hand", QColor(121, 85, 72)},     {"receive", QColor(161, 120, 100)},
        {"carry", QColor(96, 125, 139)},    {"tackle", QColor(183, 28, 28)},   {"getup", QColor(103, 58, 183)},
    };
    return colours;
}

}  // namespace

GanttView::GanttView(QWidget* parent) : QWidget(parent) {
    setFocusPolicy(Qt::StrongFocus);
    setMouseTracking(false);
    setAutoFillBackground(false);
}

QColor GanttView::annotationColour(const QString& annotation) {
    const auto& fixed = fixedColours();
    if (const auto it = fixed.find(annotation.toLower()); it != fixed.end()) return it->second;
    if (annotation.isEmpty()) return QColor(120, 120, 120);
    // Other words: a stable hue from the word (qHash is seeded per process).
    unsigned h = 2166136261u;
    for (QChar c : annotation.toLower()) h = (h ^ c.unicode()) * 16777619u;
    return QColor::fromHsv(static_cast<int>(h % 360), 150, 200);
}

void GanttView::setData(GanttData data) {
    data_ = std::move(data);
    selected_ = selected_ < static_cast<int>(data_.rows.size()) ? selected_ : -1;
    frameAll();
}

void GanttView::setTime(double t) {
    if (t == time_) return;
    time_ = t;
    update();
}

void GanttView::setSelectedRow(int row) {
    if (row == selected_) return;
    selected_ = row;
    update();
}

void GanttView::frameAll() {
    viewFirst_ = 0;
    viewLast_ = std::max(1.0, data_.duration);
    update();
}

void GanttView::clampView() {
    const double total = std::max(1.0, data_.duration);
    double span = std::clamp(viewLast_ - viewFirst_, 0.2, total);
    viewFirst_ = std::clamp(viewFirst_, 0.0, total - span);
    viewLast_ = viewFirst_ + span;
}

int GanttView::rowHeight() const {
    const int n = std::max<int>(1, static_cast<int>(data_.rows.size()));
    const int avail = height() - kRulerHeight - kLegendHeight;
    return std::clamp(avail / n, 6, 24);
}

int GanttView::xOfTime(double t) const {
    const double w = std::max(1, width() - kNameWidth - 4);
    return kNameWidth + static_cast<int>(std::lround((t - viewFirst_) / (viewLast_ - viewFirst_) * w));
}

double GanttView::timeAtX(int x) const {
    const double w = std::max(1, width() - kNameWidth - 4);
    return viewFirst_ + (x - kNameWidth) / w * (viewLast_ - viewFirst_);
}

int GanttView::rowY(int row) const { return kRulerHeight + row * rowHeight() + rowHeight() / 2; }

int GanttView::rowAt(int y) const {
    if (y < kRulerHeight) return -1;
    const int row = (y - kRulerHeight) / rowHeight();
    const int bottom = height() - kLegendHeight;
    if (y >= bottom || row >= static_cast<int>(data_.rows.size())) return -1;
    return row;
}

int GanttView::barAt(int row, int x) const {
    if (row < 0 || row >= static_cast<int>(data_.rows.size()) || x < kNameWidth) return -1;
    const double t = timeAtX(x);
    const auto& bars = data_.rows[static_cast<std::size_t>(row)].bars;
    for (std::size_t b = 0; b < bars.size(); ++b)
        if (t >= bars[b].start && t < bars[b].end) return static_cast<int>(b);
    return -1;
}

void GanttView::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), QColor(38, 40, 44));
    const int rh = rowHeight();
    const int bottom = height() - kLegendHeight;
    if (data_.rows.empty()) {
        p.setPen(QColor(170, 170, 170));
        p.drawText(rect(), Qt::AlignCenter, "No scene: Scene > Generate plans one (its action track shows here)");
        return;
    }
    // Ruler: a tick per second (or per 5 / 10 s when zoomed out).
    p.fillRect(QRect(0, 0, width(), kRulerHeight), QColor(52, 55, 60));
    const double span = viewLast_ - viewFirst_;
    const double step = span > 120 ? 10.0 : span > 40 ? 5.0 : span > 8 ? 1.0 : 0.5;
    QFont small = font();
    small.setPointSizeF(std::max(6.0, small.pointSizeF() * 0.8));
    p.setFont(small);
    for (double t = std::ceil(viewFirst_ / step) * step; t <= viewLast_; t += step) {
        const int x = xOfTime(t);
        p.setPen(QColor(120, 124, 130));
        p.drawLine(x, kRulerHeight - 5, x, kRulerHeight);
        p.setPen(QColor(200, 200, 200));
        p.drawText(x + 2, kRulerHeight - 5, QString::number(t, 'g', 4) + "s");
    }
    // Rows.
    p.setClipRect(QRect(0, kRulerHeight, width(), bottom - kRulerHeight));
    for (std::size_t r = 0; r < data_.rows.size(); ++r) {
        const GanttRow& row = data_.rows[r];
        const int y0 = kRulerHeight + static_cast<int>(r) * rh;
        if (y0 >= bottom) break;
        const bool sel = static_cast<int>(r) == selected_;
        p.fillRect(QRect(0, y0, width(), rh), sel ? QColor(70, 74, 88) : (r % 2 ? QColor(44, 46, 50) : QColor(40, 42, 46)));
        p.fillRect(QRect(0, y0 + 1, 5, rh - 2), row.tint);
        p.setPen(sel ? Qt::white : QColor(210, 210, 210));
        if (rh >= 10) p.drawText(QRect(8, y0, kNameWidth - 10, rh), Qt::AlignVCenter | Qt::AlignLeft, row.name);
        p.setClipRect(QRect(kNameWidth, kRulerHeight, width() - kNameWidth, bottom - kRulerHeight));
        for (const GanttBar& bar : row.bars) {
            if (bar.end < viewFirst_ || bar.start > viewLast_) continue;
            const int x0 = xOfTime(bar.start), x1 = std::max(x0 + 1, xOfTime(bar.end));
            const QRect box(x0, y0 + 2, x1 - x0, rh - 4);
            const QColor c = annotationColour(bar.annotation);
            p.fillRect(box, c);
            if (bar.forced) p.fillRect(box, QBrush(QColor(0, 0, 0, 90), Qt::BDiagPattern));
            p.setPen(bar.fallback ? QPen(Qt::yellow, 1, Qt::DashLine) : QPen(c.darker(160)));
            p.drawRect(box.adjusted(0, 0, -1, -1));
            int textLeft = 3;
            if (bar.pin >= 0) {
                // Pinned: a white outline and a pin (a disc on a stem) at the start.
                p.setPen(QPen(Qt::white, 2));
                p.setBrush(Qt::NoBrush);
                p.drawRect(box.adjusted(1, 1, -1, -1));
                const int head = std::clamp(rh / 5, 2, 4);
                const int cx = x0 + head + 3, cy = y0 + 2 + head + 1;
                p.setPen(QPen(Qt::white, 1));
                p.drawLine(cx, cy, cx, std::min(y0 + rh - 4, cy + 2 * head + 2));
                p.setBrush(QColor(230, 40, 40));
                p.drawEllipse(QPoint(cx, cy), head, head);
                p.setBrush(Qt::NoBrush);
                textLeft = 2 * head + 7;
            }
            if (box.width() > 30 && rh >= 12) {
                p.setPen(c.lightness() > 140 ? Qt::black : Qt::white);
                p.drawText(box.adjusted(textLeft, 0, -2, 0), Qt::AlignVCenter | Qt::AlignLeft, bar.label);
            }
        }
        p.setClipRect(QRect(0, kRulerHeight, width(), bottom - kRulerHeight));
    }
    // Hits: a triangle pointing down on the attacker's row, up on the defender's.
    p.setClipRect(QRect(kNameWidth, kRulerHeight, width() - kNameWidth, bottom - kRulerHeight));
    const auto triangle = [&](int x, int yMid, bool down, const QColor& colour, bool hollow) {
        const int s = std::clamp(rh / 3, 3, 6);
        QPainterPath path;
        if (down) {
            path.moveTo(x - s, yMid - s);
            path.lineTo(x + s, yMid - s);
            path.lineTo(x, yMid + s);
        } else {
            path.moveTo(x - s, yMid + s);
            path.lineTo(x + s, yMid + s);
            path.lineTo(x, yMid - s);
        }
        path.closeSubpath();
        p.setPen(QPen(Qt::white, 1));
        p.setBrush(hollow ? Qt::NoBrush : QBrush(colour));
        p.drawPath(path);
    };
    for (const GanttHit& hit : data_.hits) {
        if (hit.time < viewFirst_ || hit.time > viewLast_) continue;
        const int x = xOfTime(hit.time);
        if (hit.attacker >= 0 && hit.attacker < static_cast<int>(data_.rows.size()))
            triangle(x, rowY(hit.attacker), true, QColor(255, 40, 40), hit.blocked);
        if (hit.defender >= 0 && hit.defender < static_cast<int>(data_.rows.size()))
            triangle(x, rowY(hit.defender), false, QColor(20, 20, 20), hit.blocked);
    }
    // Playhead.
    p.setClipping(false);
    if (time_ >= viewFirst_ && time_ <= viewLast_) {
        const int x = xOfTime(time_);
        p.setPen(QPen(QColor(255, 220, 0), 2));
        p.drawLine(x, 0, x, bottom);
    }
    // Legend: the annotations in this scene, in first-use order.
    p.fillRect(QRect(0, bottom, width(), kLegendHeight), QColor(30, 31, 34));
    std::vector<QString> seen;
    for (const GanttRow& row : data_.rows)
        for (const GanttBar& bar : row.bars)
            if (std::find(seen.begin(), seen.end(), bar.annotation) == seen.end()) seen.push_back(bar.annotation);
    const QString hint =
        QString::fromUtf8("\u25BC hit given  \u25B2 hit taken  hollow: blocked  hatched: reaction  outlined: pinned (right-click a bar)");
    const QFontMetrics fm(small);
    const int legendEnd = width() - fm.horizontalAdvance(hint) - 16;
    int x = 6;
    for (const QString& a : seen) {
        const QString text = a.isEmpty() ? QString("(none)") : a;
        if (x + 13 + fm.horizontalAdvance(text) > legendEnd) break;
        p.fillRect(QRect(x, bottom + 4, 10, kLegendHeight - 8), annotationColour(a));
        p.setPen(QColor(210, 210, 210));
        p.drawText(x + 13, bottom + kLegendHeight - 4, text);
        x += 13 + fm.horizontalAdvance(text) + 12;
    }
    p.setPen(QColor(210, 210, 210));
    p.drawText(QRect(0, bottom, width() - 6, kLegendHeight), Qt::AlignRight | Qt::AlignVCenter, hint);
}

void GanttView::mousePressEvent(QMouseEvent* event) {
    const QPoint pos = event->position().toPoint();
    if (event->button() != Qt::LeftButton) return;
    if (pos.y() < kRulerHeight && pos.x() >= kNameWidth) {
        scrubbing_ = true;
        Q_EMIT seekRequested(std::clamp(timeAtX(pos.x()), 0.0, data_.duration));
        return;
    }
    const int row = rowAt(pos.y());
    if (row < 0) return;
    const int bar = barAt(row, pos.x());
    setSelectedRow(row);
    Q_EMIT rowSelected(row);
    Q_EMIT barClicked(row, bar);
    if (bar >= 0) Q_EMIT seekRequested(data_.rows[static_cast<std::size_t>(row)].bars[static_cast<std::size_t>(bar)].start);
    else if (pos.x() >= kNameWidth) Q_EMIT seekRequested(std::clamp(timeAtX(pos.x()), 0.0, data_.duration));
}

void GanttView::mouseMoveEvent(QMouseEvent* event) {
    if (!scrubbing_ || !(event->buttons() & Qt::LeftButton)) {
        scrubbing_ = false;
        return;
    }
    Q_EMIT seekRequested(std::clamp(timeAtX(event->position().toPoint().x()), 0.0, data_.duration));
}

void GanttView::wheelEvent(QWheelEvent* event) {
    const double steps = event->angleDelta().y() / 120.0;
    const double span = viewLast_ - viewFirst_;
    if (event->modifiers() & Qt::ShiftModifier) {
        viewFirst_ -= steps * span * 0.1;
        viewLast_ -= steps * span * 0.1;
    } else {
        const double at = timeAtX(event->position().toPoint().x());
        const double factor = std::pow(0.85, steps);
        viewFirst_ = at - (at - viewFirst_) * factor;
        viewLast_ = at + (viewLast_ - at) * factor;
    }
    clampView();
    update();
}

void GanttView::contextMenuEvent(QContextMenuEvent* event) {
    const int row = rowAt(event->pos().y());
    const int bar = row >= 0 ? barAt(row, event->pos().x()) : -1;
    if (bar < 0) return;
    setSelectedRow(row);
    Q_EMIT rowSelected(row);
    Q_EMIT barMenuRequested(row, bar, event->globalPos());
}

void GanttView::keyPressEvent(QKeyEvent* event) {
    if (event->key() == Qt::Key_Home) frameAll();
    else QWidget::keyPressEvent(event);
}

}  // namespace fray::editor
