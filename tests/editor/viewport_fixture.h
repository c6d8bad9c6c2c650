#pragma once
// The editor's main window with its real Vulkan viewport (lavapipe), the way
// `fray P.frayproj` opens it, for tests that drive the floor tools with mouse
// events on the viewport. Needs an X display: the tests run under Xvfb
// (xvfb-run -a, see tests/editor/CMakeLists.txt).
#include <gtest/gtest.h>

#include <QGuiApplication>
#include <QVulkanInstance>
#include <memory>

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

}  // namespace fray::test
