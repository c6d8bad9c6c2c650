#include "timeline_view.h"

#include <QContextMenuEvent>
#include <QKeyEvent>
#include <QMenu>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>

namespace fray::editor {

namespace {

constexpr int kMargin = 4;
constexpr int kCutGrabPixels = 5;

// Alternating block colours keep neighbouring actions apart; a proposal-only
// action is drawn lighter and italic.
QColor blockColour(int action, bool selected) {
    if (selected) return {255, 196, 84};
    return action % 2 == 0 ? QColor(88, 122, 170) : QColor(110, 150, 196);
}

}  // namespace

TimelineView::TimelineView(QWidget* parent) : QWidget(parent) {
    setFocusPolicy(Qt::StrongFocus);
    setMouseTracking(true);
    setAutoFillBackground(false);
    setToolTip(
        "Click or drag to scrub; drag a cut to move it; double-click adds a cut; right-click for more.\n"
        "Drag over a foot band: left button marks it supporting, right button free.\n"
        "Wheel zooms, Shift+wheel or middle-drag pans; Space plays, arrows step, Home frames all.");
}

void TimelineView::setData(TimelineData data) {
    const bool sameLength = data.frameCount == data_.frameCount;
    data_ = std::move(data);
    // The curve's scale: twice the threshold, or the profile's 99th
    // percentile when that is higher, so one spike does not flatten the rest.
    std::vector<float> sorted = data_.acceleration;
    float p99 = 0.0f;
    if (!sorted.empty()) {
        const std::size_t k = std::min(sorted.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(sorted.size())));
        std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
        p99 = sorted[k];
    }
    curveMax_ = std::max({p99, static_cast<float>(2.0 * data_.threshold), 1e-6f});
    // A new motion opens on its first kInitialSeconds (Home frames it all).
    if (!sameLength || !viewSet_) showFrames(0, std::min<double>(std::max(1, data_.frameCount - 1), kInitialSeconds * std::max(1.0, data_.fps)));
    playhead_ = clampFrame(playhead_);
    if (selectedAction_ >= static_cast<int>(data_.cuts.size()) + 1) selectedAction_ = -1;
    update();
}

void TimelineView::setPlayhead(int frame) {
    const int f = clampFrame(frame);
    if (f == playhead_) return;
    playhead_ = f;
    // Keep the playhead in view while playing.
    if (playhead_ < viewFirst_ || playhead_ > viewLast_) {
        const double span = viewLast_ - viewFirst_;
        viewFirst_ = playhead_ - 0.1 * span;
        viewLast_ = viewFirst_ + span;
        clampView();
    }
    update();
}

void TimelineView::setSelectedAction(int action) {
    if (action == selectedAction_) return;
    selectedAction_ = action;
    update();
}

void TimelineView::frameAll() {
    showFrames(0, std::max(1, data_.frameCount - 1));
}

void TimelineView::showFrames(double first, double last) {
    viewFirst_ = first;
    viewLast_ = last;
    viewSet_ = true;
    clampView();
    update();
}

TimelineView::Rows TimelineView::rows() const {
    const int h = height();
    Rows r{};
    r.ruler0 = 0;
    r.ruler1 = 18;
    const int band = std::max(12, h / 10);
    r.right1 = h - kMargin;
    r.right0 = r.right1 - band;
    r.left1 = r.right0 - 2;
    r.left0 = r.left1 - band;
    r.actions1 = r.left0 - 4;
    r.actions0 = r.actions1 - std::max(18, h / 7);
    r.curve0 = r.ruler1 + 2;
    r.curve1 = std::max(r.curve0 + 10, r.actions0 - 4);
    return r;
}

int TimelineView::xOfFrame(double frame) const {
    const double span = std::max(1e-9, viewLast_ - viewFirst_);
    const double w = std::max(1, width() - 2 * kMargin);
    return kMargin + static_cast<int>(std::lround((frame - viewFirst_) / span * w));
}

double TimelineView::frameAtX(int x) const {
    const double span = viewLast_ - viewFirst_;
    const double w = std::max(1, width() - 2 * kMargin);
    return viewFirst_ + (x - kMargin) / w * span;
}

int TimelineView::rulerY() const { return (rows().ruler0 + rows().ruler1) / 2; }
int TimelineView::curveY() const { return (rows().curve0 + rows().curve1) / 2; }
int TimelineView::actionsY() const { return (rows().actions0 + rows().actions1) / 2; }
int TimelineView::footY(int foot) const {
    const Rows r = rows();
    return foot == 0 ? (r.left0 + r.left1) / 2 : (r.right0 + r.right1) / 2;
}

int TimelineView::clampFrame(double frame) const {
    if (data_.frameCount <= 0) return 0;
    return std::clamp(static_cast<int>(std::lround(frame)), 0, data_.frameCount - 1);
}

int TimelineView::cutNear(int x) const {
    int best = -1, bestDist = kCutGrabPixels + 1;
    for (std::size_t i = 0; i < data_.cuts.size(); ++i) {
        const int d = std::abs(xOfFrame(data_.cuts[i]) - x);
        if (d < bestDist) {
            bestDist = d;
            best = static_cast<int>(i);
        }
    }
    return best;
}

int TimelineView::footAt(int y) const {
    const Rows r = rows();
    if (y >= r.left0 && y < r.left1) return 0;
    if (y >= r.right0 && y < r.right1) return 1;
    return -1;
}

void TimelineView::clampView() {
    const double maxFrame = std::max(1, data_.frameCount - 1);
    double span = std::clamp(viewLast_ - viewFirst_, 10.0, maxFrame);
    if (data_.frameCount < 10) span = maxFrame;
    viewFirst_ = std::clamp(viewFirst_, 0.0, std::max(0.0, maxFrame - span));
    viewLast_ = viewFirst_ + span;
}

void TimelineView::zoomAround(double frame, double factor) {
    const double first = frame - (frame - viewFirst_) * factor;
    const double last = frame + (viewLast_ - frame) * factor;
    viewFirst_ = first;
    viewLast_ = last;
    clampView();
    update();
}

void TimelineView::requestPlayhead(int frame) {
    const int f = clampFrame(frame);
    setPlayhead(f);
    Q_EMIT playheadRequested(f);
}

void TimelineView::resizeEvent(QResizeEvent*) { update(); }

void TimelineView::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), QColor(38, 40, 44));
    const Rows r = rows();
    if (data_.frameCount <= 0) {
        p.setPen(QColor(170, 170, 170));
        p.drawText(rect(), Qt::AlignCenter, "Select a motion to see its timeline");
        return;
    }
    const int x0 = kMargin, x1 = width() - kMargin;
    const double fps = data_.fps > 0 ? data_.fps : 60.0;

    // Ruler: ticks at a round number of seconds for the zoom.
    p.fillRect(QRect(0, r.ruler0, width(), r.ruler1 - r.ruler0), QColor(52, 55, 60));
    const double secondsShown = (viewLast_ - viewFirst_) / fps;
    double step = 0.1;
    for (double s : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 60.0, 120.0, 300.0}) {
        step = s;
        if (secondsShown / s <= std::max(2.0, (x1 - x0) / 70.0)) break;
    }
    p.setPen(QColor(150, 150, 150));
    QFont small = font();
    small.setPointSizeF(std::max(6.5, small.pointSizeF() * 0.8));
    p.setFont(small);
    for (double s = std::ceil(viewFirst_ / fps / step) * step; s * fps <= viewLast_; s += step) {
        const int x = xOfFrame(s * fps);
        p.drawLine(x, r.ruler1 - 5, x, r.ruler1);
        p.drawText(x + 2, r.ruler1 - 6, QString::number(s, 'f', step < 1 ? 1 : 0) + "s");
    }

    // Acceleration: high-acceleration bands behind, the curve, the threshold.
    const QRect curveRect(x0, r.curve0, x1 - x0, r.curve1 - r.curve0);
    p.fillRect(curveRect, QColor(30, 31, 34));
    const auto frameRange = [&](int px) {
        const int a = clampFrame(std::floor(frameAtX(px)));
        const int b = clampFrame(std::ceil(frameAtX(px + 1)));
        return std::pair{a, std::max(a, b)};
    };
    if (!data_.highAccel.empty()) {
        for (int px = x0; px < x1; ++px) {
            auto [a, b] = frameRange(px);
            bool high = false;
            for (int f = a; f <= b && f < static_cast<int>(data_.highAccel.size()); ++f) high = high || data_.highAccel[f];
            if (high) p.fillRect(QRect(px, r.curve0, 1, r.curve1 - r.curve0), QColor(110, 52, 52));
        }
    }
    const auto yOf = [&](double v) {
        const double t = std::clamp(v / static_cast<double>(curveMax_), 0.0, 1.0);
        return r.curve1 - static_cast<int>(t * (r.curve1 - r.curve0 - 2));
    };
    if (!data_.acceleration.empty()) {
        p.setPen(QColor(120, 220, 140));
        const int n = static_cast<int>(data_.acceleration.size());
        for (int px = x0; px < x1; ++px) {
            auto [a, b] = frameRange(px);
            if (a >= n) break;
            float lo = data_.acceleration[a], hi = lo;
            for (int f = a; f <= b && f < n; ++f) {
                lo = std::min(lo, data_.acceleration[f]);
                hi = std::max(hi, data_.acceleration[f]);
            }
            p.drawLine(px, yOf(lo), px, yOf(hi));
        }
    }
    if (data_.threshold > 0) {
        p.setPen(QPen(QColor(230, 120, 90), 1, Qt::DashLine));
        const int y = yOf(data_.threshold);
        p.drawLine(x0, y, x1, y);
    }

    // Action blocks between the cuts.
    const int actionCount = static_cast<int>(data_.cuts.size()) + 1;
    for (int a = 0; a < actionCount; ++a) {
        const int first = a == 0 ? 0 : data_.cuts[static_cast<std::size_t>(a - 1)];
        const int last = a + 1 < actionCount ? data_.cuts[static_cast<std::size_t>(a)] : data_.frameCount;
        if (last < viewFirst_ || first > viewLast_) continue;
        const int bx0 = std::max(x0, xOfFrame(first)), bx1 = std::min(x1, xOfFrame(last));
        const QRect block(bx0, r.actions0, std::max(1, bx1 - bx0), r.actions1 - r.actions0);
        QString name = a < static_cast<int>(data_.actionNames.size()) ? data_.actionNames[static_cast<std::size_t>(a)] : QString();
        const bool proposal = name.endsWith('?');
        QColor fill = blockColour(a, a == selectedAction_);
        if (proposal && a != selectedAction_) fill = fill.lighter(125);
        p.fillRect(block, fill);
        p.setPen(QColor(20, 20, 20));
        QFont f = small;
        f.setItalic(proposal);
        p.setFont(f);
        if (block.width() > 14)
            p.drawText(block.adjusted(3, 0, -2, 0), Qt::AlignVCenter | Qt::AlignLeft,
                       p.fontMetrics().elidedText(name, Qt::ElideRight, block.width() - 5));
    }
    p.setFont(small);

    // Foot contacts: a band per foot, supported frames filled; user labels as
    // a thin strip on top of the band (white: supporting, black: free).
    const auto drawFoot = [&](const std::vector<std::uint8_t>& contact, int y0, int y1, QColor colour, const char* tag,
                              bool left) {
        p.fillRect(QRect(x0, y0, x1 - x0, y1 - y0), QColor(30, 31, 34));
        const int n = static_cast<int>(contact.size());
        for (int px = x0; px < x1; ++px) {
            auto [a, b] = frameRange(px);
            int on = 0, total = 0;
            for (int f = a; f <= b && f < n; ++f, ++total) on += contact[f] ? 1 : 0;
            if (total > 0 && on * 2 >= total) p.fillRect(QRect(px, y0, 1, y1 - y0), colour);
        }
        for (const TimelineContactLabel& l : data_.labels) {
            const std::optional<bool>& v = left ? l.left : l.right;
            if (!v) continue;
            const int lx0 = std::max(x0, xOfFrame(l.first)), lx1 = std::min(x1, xOfFrame(l.last + 1));
            if (lx1 <= lx0) continue;
            p.fillRect(QRect(lx0, y0, lx1 - lx0, 3), *v ? QColor(245, 245, 245) : QColor(0, 0, 0));
        }
        p.setPen(QColor(200, 200, 200));
        p.drawText(x0 + 2, y1 - 2, tag);
    };
    drawFoot(data_.contactLeft, r.left0, r.left1, QColor(90, 150, 230), "L", true);
    drawFoot(data_.contactRight, r.right0, r.right1, QColor(230, 150, 90), "R", false);

    // The label being dragged.
    if (drag_ == Drag::Label && dragFoot_ >= 0) {
        const int a = std::min(dragLabelStart_, dragLabelEnd_), b = std::max(dragLabelStart_, dragLabelEnd_);
        const int y0 = dragFoot_ == 0 ? r.left0 : r.right0, y1 = dragFoot_ == 0 ? r.left1 : r.right1;
        p.fillRect(QRect(xOfFrame(a), y0, std::max(1, xOfFrame(b + 1) - xOfFrame(a)), y1 - y0),
                   dragLabelSupported_ ? QColor(255, 255, 255, 90) : QColor(0, 0, 0, 120));
    }

    // Cut markers across every row, with a handle in the ruler.
    for (int cut : data_.cuts) {
        if (cut < viewFirst_ || cut > viewLast_) continue;
        const int x = xOfFrame(cut);
        // Faint over the curve and the feet, solid across the action row.
        p.setPen(QPen(QColor(240, 240, 240, 70), 1));
        p.drawLine(x, r.ruler0, x, r.right1);
        p.setPen(QPen(QColor(20, 20, 20), 2));
        p.drawLine(x, r.actions0, x, r.actions1);
        QPainterPath handle;
        handle.moveTo(x - 4, r.ruler0);
        handle.lineTo(x + 4, r.ruler0);
        handle.lineTo(x, r.ruler0 + 7);
        handle.closeSubpath();
        p.fillPath(handle, QColor(240, 240, 240));
    }

    // Playhead.
    const int px = xOfFrame(playhead_);
    p.setPen(QPen(QColor(255, 80, 80), 2));
    p.drawLine(px, r.ruler0, px, r.right1);
    p.setPen(QColor(255, 140, 140));
    p.drawText(px + 3, r.curve0 + 11, QString("%1 (%2 s)").arg(playhead_).arg(playhead_ / fps, 0, 'f', 2));

    if (hasFocus()) {
        p.setPen(QColor(90, 140, 220));
        p.drawRect(rect().adjusted(0, 0, -1, -1));
    }
}

void TimelineView::mousePressEvent(QMouseEvent* event) {
    if (data_.frameCount <= 0) return;
    const QPoint pos = event->position().toPoint();
    const Rows r = rows();
    if (event->button() == Qt::MiddleButton) {
        drag_ = Drag::Pan;
        panStartX_ = pos.x();
        panStartFirst_ = viewFirst_;
        return;
    }
    const int foot = footAt(pos.y());
    if (foot >= 0 && (event->button() == Qt::LeftButton || event->button() == Qt::RightButton)) {
        drag_ = Drag::Label;
        dragFoot_ = foot;
        dragLabelStart_ = dragLabelEnd_ = clampFrame(frameAtX(pos.x()));
        dragLabelSupported_ = event->button() == Qt::LeftButton;
        update();
        return;
    }
    if (event->button() != Qt::LeftButton) return;
    const int cut = cutNear(pos.x());
    if (cut >= 0 && pos.y() <= r.actions1) {
        drag_ = Drag::Cut;
        dragCutFrom_ = dragCutLast_ = data_.cuts[static_cast<std::size_t>(cut)];
        setCursor(Qt::SizeHorCursor);
        return;
    }
    if (pos.y() >= r.actions0 && pos.y() < r.actions1) {
        const int frame = clampFrame(frameAtX(pos.x()));
        int action = 0;
        while (action < static_cast<int>(data_.cuts.size()) && data_.cuts[static_cast<std::size_t>(action)] <= frame) ++action;
        setSelectedAction(action);
        Q_EMIT actionSelected(action);
    }
    drag_ = Drag::Scrub;
    requestPlayhead(static_cast<int>(std::lround(frameAtX(pos.x()))));
}

void TimelineView::mouseMoveEvent(QMouseEvent* event) {
    const QPoint pos = event->position().toPoint();
    switch (drag_) {
    case Drag::None:
        setCursor(cutNear(pos.x()) >= 0 && pos.y() <= rows().actions1 ? Qt::SizeHorCursor : Qt::ArrowCursor);
        return;
    case Drag::Scrub:
        requestPlayhead(static_cast<int>(std::lround(frameAtX(pos.x()))));
        return;
    case Drag::Pan: {
        const double framesPerPixel = (viewLast_ - viewFirst_) / std::max(1, width() - 2 * kMargin);
        const double span = viewLast_ - viewFirst_;
        viewFirst_ = panStartFirst_ - (pos.x() - panStartX_) * framesPerPixel;
        viewLast_ = viewFirst_ + span;
        clampView();
        update();
        return;
    }
    case Drag::Label:
        dragLabelEnd_ = clampFrame(frameAtX(pos.x()));
        update();
        return;
    case Drag::Cut: {
        // Stay strictly between the neighbouring cuts (the document checks too).
        int lo = 1, hi = data_.frameCount - 1;
        for (int c : data_.cuts) {
            if (c < dragCutLast_) lo = std::max(lo, c + 1);
            if (c > dragCutLast_) hi = std::min(hi, c - 1);
        }
        const int frame = std::clamp(static_cast<int>(std::lround(frameAtX(pos.x()))), lo, hi);
        if (frame != dragCutLast_) {
            dragCutLast_ = frame;
            Q_EMIT cutDragged(dragCutFrom_, frame, false);
        }
        return;
    }
    }
}

void TimelineView::mouseReleaseEvent(QMouseEvent* event) {
    const Drag was = drag_;
    drag_ = Drag::None;
    unsetCursor();
    if (was == Drag::Cut && event->button() == Qt::LeftButton) {
        Q_EMIT cutDragged(dragCutFrom_, dragCutLast_, true);
    } else if (was == Drag::Label) {
        const int a = std::min(dragLabelStart_, dragLabelEnd_), b = std::max(dragLabelStart_, dragLabelEnd_);
        Q_EMIT contactLabelRequested(dragFoot_, a, b, dragLabelSupported_);
        dragFoot_ = -1;
        update();
    }
}

void TimelineView::mouseDoubleClickEvent(QMouseEvent* event) {
    if (data_.frameCount <= 0 || event->button() != Qt::LeftButton) return;
    const QPoint pos = event->position().toPoint();
    if (footAt(pos.y()) >= 0 || cutNear(pos.x()) >= 0) return;
    const int frame = clampFrame(frameAtX(pos.x()));
    if (frame > 0) Q_EMIT cutAddRequested(frame);
}

void TimelineView::wheelEvent(QWheelEvent* event) {
    if (data_.frameCount <= 0) return;
    const double steps = event->angleDelta().y() / 120.0;
    if (steps == 0) return;
    if (event->modifiers() & Qt::ShiftModifier) {
        const double span = viewLast_ - viewFirst_;
        viewFirst_ -= steps * 0.1 * span;
        viewLast_ = viewFirst_ + span;
        clampView();
        update();
    } else {
        zoomAround(frameAtX(static_cast<int>(event->position().x())), std::pow(0.8, steps));
    }
    event->accept();
}

void TimelineView::keyPressEvent(QKeyEvent* event) {
    switch (event->key()) {
    case Qt::Key_Space: Q_EMIT playToggled(); return;
    case Qt::Key_Left: requestPlayhead(playhead_ - 1); return;
    case Qt::Key_Right: requestPlayhead(playhead_ + 1); return;
    case Qt::Key_Down: requestPlayhead(playhead_ - 10); return;
    case Qt::Key_Up: requestPlayhead(playhead_ + 10); return;
    case Qt::Key_Home:
        frameAll();
        requestPlayhead(0);
        return;
    case Qt::Key_Delete:
    case Qt::Key_Backspace:
        for (int c : data_.cuts)
            if (std::abs(c - playhead_) <= 1) {
                Q_EMIT cutRemoveRequested(c);
                return;
            }
        return;
    default: QWidget::keyPressEvent(event);
    }
}

void TimelineView::contextMenuEvent(QContextMenuEvent* event) {
    if (data_.frameCount <= 0 || footAt(event->pos().y()) >= 0) return;
    const int frame = clampFrame(frameAtX(event->pos().x()));
    const int cut = cutNear(event->pos().x());
    int action = 0;
    while (action < static_cast<int>(data_.cuts.size()) && data_.cuts[static_cast<std::size_t>(action)] <= frame) ++action;
    QMenu menu(this);
    QAction* add = menu.addAction(QString("Split here (frame %1)").arg(frame));
    add->setEnabled(cut < 0 && frame > 0);
    QAction* remove = menu.addAction("Delete this cut");
    remove->setEnabled(cut >= 0);
    QAction* merge = menu.addAction("Merge with the next action");
    merge->setEnabled(action < static_cast<int>(data_.cuts.size()));
    QAction* chosen = menu.exec(event->globalPos());
    if (chosen == add) Q_EMIT cutAddRequested(frame);
    else if (chosen == remove) Q_EMIT cutRemoveRequested(data_.cuts[static_cast<std::size_t>(cut)]);
    else if (chosen == merge) Q_EMIT mergeRequested(action);
}

}  // namespace fray::editor
