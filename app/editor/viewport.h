#pragma once
// The Vulkan viewport of the editor: a QWindow with a Vulkan surface, embedded
// in the widget layout with QWidget::createWindowContainer. The renderer and
// the swapchain are Fray's own (fray_renderer); Qt only provides the surface.
// Mouse: left drag orbits, right or middle drag pans, the wheel zooms.
#include <QWindow>
#include <memory>

#include "fray/render/presenter.h"
#include "fray/render/renderer.h"

class QVulkanInstance;

namespace fray::editor {

class FloorTool;

class Viewport : public QWindow {
    Q_OBJECT
public:
    Viewport(std::shared_ptr<render::VulkanDevice> device, QVulkanInstance* instance);
    ~Viewport() override;

    // Creates the renderer (no surface needed yet).
    Status init(render::Quality quality);
    render::FrameDescription& frame() { return frame_; }
    render::Renderer* renderer() { return renderer_.get(); }
    // Draws and presents one frame when the window is exposed; returns whether it did.
    Result<bool> renderNow();
    int framesPresented() const { return presented_; }
    float aspect() const;
    // The active floor tool takes the left button, double-clicks and keys
    // first, at the floor point under the pointer (null: the camera only).
    void setActiveTool(FloorTool* tool);
    FloorTool* activeTool() const { return tool_; }

Q_SIGNALS:
    void frameAllRequested();

protected:
    void exposeEvent(QExposeEvent* event) override;
    bool event(QEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;
    void mouseDoubleClickEvent(QMouseEvent* event) override;

private:
    Status ensurePresenter();
    void releaseSurface();

    std::shared_ptr<render::VulkanDevice> device_;
    QVulkanInstance* instance_;
    std::unique_ptr<render::Renderer> renderer_;
    std::unique_ptr<render::Presenter> presenter_;
    render::FrameDescription frame_;
    int presented_ = 0;
    Qt::MouseButton dragButton_ = Qt::NoButton;
    QPointF lastPos_;
    FloorTool* tool_ = nullptr;
    bool toolDrag_ = false;
};

}  // namespace fray::editor
