#include "viewport.h"

#include <QMouseEvent>
#include <QPlatformSurfaceEvent>
#include <QVulkanInstance>
#include <QWheelEvent>
#include <cmath>

#include "floor_tools.h"

namespace fray::editor {

Viewport::Viewport(std::shared_ptr<render::VulkanDevice> device, QVulkanInstance* instance)
    : device_(std::move(device)), instance_(instance) {
    setSurfaceType(QSurface::VulkanSurface);
    setVulkanInstance(instance_);
    frame_.camera.yaw = 0.5f;
    frame_.camera.pitch = 0.35f;
}

Viewport::~Viewport() { releaseSurface(); }

Status Viewport::init(render::Quality quality) {
    render::RendererOptions o;
    o.width = std::max(1, static_cast<int>(width() * devicePixelRatio()));
    o.height = std::max(1, static_cast<int>(height() * devicePixelRatio()));
    o.quality = quality;
    auto r = render::Renderer::create(device_, o);
    if (!r) return r.error();
    renderer_ = std::move(*r);
    return {};
}

float Viewport::aspect() const { return height() > 0 ? static_cast<float>(width()) / static_cast<float>(height()) : 1.0f; }

Status Viewport::ensurePresenter() {
    if (presenter_) return {};
    VkSurfaceKHR surface = QVulkanInstance::surfaceForWindow(this);
    if (!surface) return makeError("Qt gave no Vulkan surface for the viewport window");
    if (Status s = device_->attachSurface(surface, false); !s) return s;  // Qt owns the surface
    auto p = render::Presenter::create(device_, static_cast<int>(width() * devicePixelRatio()),
                                       static_cast<int>(height() * devicePixelRatio()));
    if (!p) return p.error();
    presenter_ = std::move(*p);
    return {};
}

void Viewport::releaseSurface() {
    if (presenter_) {
        presenter_.reset();
        device_->detachSurface();
    }
}

Result<bool> Viewport::renderNow() {
    if (!isExposed() || !renderer_ || width() <= 0 || height() <= 0) return false;
    if (Status s = ensurePresenter(); !s) return s.error();
    presenter_->resize(static_cast<int>(width() * devicePixelRatio()), static_cast<int>(height() * devicePixelRatio()));
    const int before = presenter_->framesPresented();
    if (Status s = presenter_->present(*renderer_, frame_); !s) return s.error();
    const bool drawn = presenter_->framesPresented() > before;
    presented_ += drawn ? 1 : 0;
    return drawn;
}

void Viewport::exposeEvent(QExposeEvent*) { requestUpdate(); }

bool Viewport::event(QEvent* event) {
    // The swapchain must go before Qt destroys the window's surface.
    if (event->type() == QEvent::PlatformSurface &&
        static_cast<QPlatformSurfaceEvent*>(event)->surfaceEventType() == QPlatformSurfaceEvent::SurfaceAboutToBeDestroyed)
        releaseSurface();
    return QWindow::event(event);
}

void Viewport::setActiveTool(FloorTool* tool) {
    if (tool_ == tool) return;
    if (tool_) tool_->deactivate();
    tool_ = tool;
    toolDrag_ = false;
    if (tool_) {
        tool_->activate();
        setCursor(tool_->cursor());
    } else {
        unsetCursor();
    }
}

void Viewport::mousePressEvent(QMouseEvent* event) {
    if (tool_ && event->button() == Qt::LeftButton) {
        if (auto floor = pickFloor(frame_.camera, aspect(), event->position(), QSizeF(size()))) {
            toolDrag_ = true;
            tool_->mousePressed(*floor, event);
        }
        return;
    }
    dragButton_ = event->button();
    lastPos_ = event->position();
}

void Viewport::mouseMoveEvent(QMouseEvent* event) {
    if (toolDrag_ && tool_) {
        if (auto floor = pickFloor(frame_.camera, aspect(), event->position(), QSizeF(size()))) tool_->mouseMoved(*floor, event);
        return;
    }
    if (dragButton_ == Qt::NoButton) return;
    const QPointF d = event->position() - lastPos_;
    lastPos_ = event->position();
    if (dragButton_ == Qt::LeftButton)
        frame_.camera.orbit(static_cast<float>(-d.x() * 0.008), static_cast<float>(d.y() * 0.008));
    else
        frame_.camera.pan(static_cast<float>(d.x()), static_cast<float>(d.y()), static_cast<float>(height()));
}

void Viewport::mouseReleaseEvent(QMouseEvent* event) {
    if (toolDrag_ && tool_ && event->button() == Qt::LeftButton) {
        toolDrag_ = false;
        if (auto floor = pickFloor(frame_.camera, aspect(), event->position(), QSizeF(size()))) tool_->mouseReleased(*floor, event);
        return;
    }
    dragButton_ = Qt::NoButton;
}

void Viewport::mouseDoubleClickEvent(QMouseEvent* event) {
    if (tool_ && event->button() == Qt::LeftButton) {
        if (auto floor = pickFloor(frame_.camera, aspect(), event->position(), QSizeF(size()))) tool_->mouseDoubleClicked(*floor, event);
        return;
    }
    QWindow::mouseDoubleClickEvent(event);
}

void Viewport::wheelEvent(QWheelEvent* event) {
    frame_.camera.zoom(static_cast<float>(std::pow(0.88, event->angleDelta().y() / 120.0)));
}

void Viewport::keyPressEvent(QKeyEvent* event) {
    if (tool_ && tool_->keyPressed(event)) return;
    if (event->key() == Qt::Key_F) Q_EMIT frameAllRequested();
    else QWindow::keyPressEvent(event);
}

}  // namespace fray::editor
