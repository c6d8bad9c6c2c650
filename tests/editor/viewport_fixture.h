#pragma once
// The editor's main window with its real Vulkan viewport (lavapipe), the way
// `fray P.frayproj` opens it, for tests that drive the floor tools with mouse
// events on the viewport. Needs an X display: the tests run under Xvfb
// (xvfb-run -a, see tests/editor/CMakeLists.txt).
#include <gtest/gtest.h>

#include <QGuiApplication>
#include <QMouseEvent>
#include <QTest>
#include <QVulkanInstance>
#include <memory>
#include <vector>

#include "editor_fixture.h"
#include "fray/authoring/project_document.h"
#include "fray/render/vulkan_device.h"
#include "main_window.h"
#include "takes.h"
#include "viewport.h"

namespace fray::test {

struct VulkanEditor {
    std::shared_ptr<render::VulkanDevice> device;
    std::unique_ptr<QVulkanInstance> instance;
    std::unique_ptr<editor::MainWindow> window;
    editor::Viewport* viewport = nullptr;  // owned by the window's container

    // Opens `project`; false (with a test failure) when it cannot.
    bool open(const QString& project) {
        if (QGuiApplication::platformName() != "xcb") {
            ADD_FAILURE() << "these tests need an X display (run them under xvfb-run -a), platform is "
                          << QGuiApplication::platformName().toStdString();
            return false;
        }
        render::DeviceOptions o;
        o.applicationName = "fray-tests";
        o.swapchain = true;
        o.instanceExtensions = {"VK_KHR_surface", "VK_KHR_xcb_surface"};
        auto d = render::VulkanDevice::create(o);
        if (!d) {
            ADD_FAILURE() << d.error().message;
            return false;
        }
        device = std::move(*d);
        instance = std::make_unique<QVulkanInstance>();
        instance->setVkInstance(device->instance());
        if (!instance->create()) {
            ADD_FAILURE() << "Qt could not adopt the Vulkan instance";
            return false;
        }
        auto takes = app::loadTakes({project.toStdString()});
        if (!takes) {
            ADD_FAILURE() << takes.error().message;
            return false;
        }
        viewport = new editor::Viewport(device, instance.get());
        viewport->resize(800, 500);
        if (Status s = viewport->init(render::Quality::Fast); !s) {
            ADD_FAILURE() << s.error().message;
            delete viewport;
            return false;
        }
        editor::EditorOptions options;
        options.restoreLayout = false;
        options.autosaveSeconds = 0;
        options.recovery = editor::EditorOptions::Recovery::Discard;
        options.noDialogs = true;
        window = std::make_unique<editor::MainWindow>(viewport, std::move(*takes), nullptr, project, "test", options);
        window->resize(1400, 880);
        window->show();
        return true;
    }

    ~VulkanEditor() {
        window.reset();  // the viewport and its swapchain first
        if (instance) instance->destroy();
        device.reset();
    }
};

// The viewport looking down on the floor around `centre` from `distance`.
inline void lookDown(editor::Viewport* v, glm::vec2 centre, float distance) {
    auto& cam = v->frame().camera;
    cam.target = glm::vec3(centre.x, 0.0f, centre.y);
    cam.yaw = 0.0f;
    cam.pitch = 1.3f;
    cam.distance = distance;
}

// The viewport pixel that shows a floor point (a test failure when none does).
inline QPoint pixelOf(editor::Viewport* v, glm::vec2 floor) {
    auto p = editor::floorToPixel(v->frame().camera, v->aspect(), floor, QSizeF(v->size()));
    EXPECT_TRUE(p.has_value());
    return p ? p->toPoint() : QPoint();
}

// The mouse moved over a floor point with the left button held.
inline void moveTo(editor::Viewport* v, glm::vec2 floor) {
    const QPointF px(pixelOf(v, floor));
    QMouseEvent move(QEvent::MouseMove, px, v->mapToGlobal(px), Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
    QGuiApplication::sendEvent(v, &move);
}

// A left-button drag on the viewport window through floor points.
inline void dragOnFloor(editor::Viewport* v, const std::vector<glm::vec2>& path) {
    QTest::mousePress(v, Qt::LeftButton, Qt::NoModifier, pixelOf(v, path.front()));
    for (std::size_t i = 1; i < path.size(); ++i) moveTo(v, path[i]);
    QTest::mouseRelease(v, Qt::LeftButton, Qt::NoModifier, pixelOf(v, path.back()));
}

inline void clickOnFloor(editor::Viewport* v, glm::vec2 p) { QTest::mouseClick(v, Qt::LeftButton, Qt::NoModifier, pixelOf(v, p)); }

// A test with the demo project open in the editor on its Vulkan viewport,
// the project analysed (motion graph, library) before the test starts.
struct EditorOnFloor : ::testing::Test {
    void SetUp() override {
        ASSERT_TRUE(editor.open(demo.project));
        w = editor.window.get();
        ASSERT_TRUE(QTest::qWaitForWindowExposed(w));
        ASSERT_TRUE(QTest::qWaitFor([&] { return w->analysis() != nullptr; }, 120000));
        doc = w->document();
        ASSERT_NE(doc, nullptr);
    }
    DemoCopy demo;
    VulkanEditor editor;
    editor::MainWindow* w = nullptr;
    authoring::ProjectDocument* doc = nullptr;
};

}  // namespace fray::test
