// fray: the Qt editor. With no argument it opens the demo project: its
// takes play in the Vulkan viewport and the panels (library, timeline,
// inspector, motion graph, combination table) fill in once the project is
// analysed in the background. A scene (planned or composed) plays with its
// characters listed; motion files play side by side.
//
//   fray [SCENE.frayscene | PROJECT.frayproj | MOTION...] [--rig FILE] [--quit-after N] [--screenshot out.png]
//        [--wait-analysis] [--fresh-layout] [--describe-ui] [--posture kinematic|physics]
//
// --rig FILE draws the characters as a skinned rig (glTF/GLB, FBX, ...)
// instead of capsules (app/cli/rig_setup.h, shared with fray-play).
#include <xcb/xcb.h>

#include <CLI/CLI.hpp>
#include <QApplication>
#include <QMessageBox>
#include <QVulkanInstance>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fray/render/vulkan_device.h"
#include "main_window.h"
#include "rig_setup.h"
#include "fray/pipeline/sim_session.h"
#include "scene_stage.h"
#include "takes.h"
#include "viewport.h"

namespace {

int fail(const std::string& message, int code = 1) {
    std::fprintf(stderr, "fray: %s\n", message.c_str());
    return code;
}

// Qt aborts when it cannot reach a display; say why instead, before it tries.
std::string displayProblem() {
    const char* platform = std::getenv("QT_QPA_PLATFORM");
    const std::string p = platform ? platform : "";
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    const bool hasX = display && *display;
    const bool hasWayland = wayland && *wayland;
    if (p.empty() && !hasX && !hasWayland)
        return "no display: neither DISPLAY nor WAYLAND_DISPLAY is set; run it in a desktop session, or headless "
               "under Xvfb (xvfb-run -a fray ...)";
    if ((p.empty() && !hasWayland) || p.rfind("xcb", 0) == 0) {
        if (!hasX) return "no display: DISPLAY is not set (QT_QPA_PLATFORM=" + p + "); headless: xvfb-run -a fray ...";
        xcb_connection_t* c = xcb_connect(nullptr, nullptr);
        const bool bad = xcb_connection_has_error(c) != 0;
        xcb_disconnect(c);
        if (bad)
            return std::string("cannot connect to the X server at DISPLAY=") + display +
                   "; is it running? headless: xvfb-run -a fray ...";
    }
    return {};
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> inputs;
    int quitAfter = 0;
    std::string screenshot, viewportShot, quality = "auto", rig, generateSpec, postureName = "kinematic";
    bool validate = false, describeUi = false, waitAnalysis = false, freshLayout = false;
    {
        CLI::App cli{"fray: the Fray editor"};
        cli.add_option("inputs", inputs,
                       "A .frayscene, a .frayproj or motion files (default: the demo scene, else the demo project)");
        cli.add_option("--quit-after", quitAfter, "Quit after this many frames were shown (for tests)");
        cli.add_option("--screenshot", screenshot, "Before quitting, write the window to this PNG");
        cli.add_option("--viewport-screenshot", viewportShot, "Before quitting, write the viewport alone to this PNG");
        cli.add_option("--rig", rig,
                       "Draw the characters as this skinned rig (glTF/GLB, FBX, ...) instead of capsules; bones are "
                       "matched to the motion's joints by name");
        cli.add_option("--quality", quality, "auto, fast or high (auto: fast on a CPU Vulkan device)")->capture_default_str();
        cli.add_flag("--validate", validate, "Vulkan validation layers on; any message makes the exit code 3");
        cli.add_flag("--describe-ui", describeUi,
                     "Print the main window's docks, menus and actions as JSON and exit (no display or Vulkan needed)");
        cli.add_flag("--wait-analysis", waitAnalysis,
                     "With --quit-after: quit only once the project's analysis (contacts, profiles, graph) has finished");
        cli.add_option("--generate", generateSpec,
                       "With a project: generate this scene spec (JSON) at start and play it; with --quit-after, "
                       "quit only once it plays");
        cli.add_option("--posture", postureName,
                       "The viewport's posture mode at start: kinematic (the captured clips) or physics (the posture "
                       "solver, solved in the background; View > Posture changes it)")
            ->capture_default_str();
        cli.add_flag("--fresh-layout", freshLayout, "Start with the default panel layout, not the one saved by the last run");
        CLI11_PARSE(cli, argc, argv);
    }
    if (quitAfter < 0) return fail("--quit-after must be >= 0", 2);
    const auto postureMode = fray::posture::parseMode(postureName);
    if (!postureMode) return fail("--posture: '" + postureName + "' is not kinematic or physics", 2);
    if ((!screenshot.empty() || !viewportShot.empty()) && quitAfter == 0) quitAfter = 10;
    fray::render::Quality q = fray::render::Quality::Auto;
    if (quality == "fast") q = fray::render::Quality::Fast;
    else if (quality == "high") q = fray::render::Quality::High;
    else if (quality != "auto") return fail("--quality " + quality + ": expected auto, fast or high", 2);

    if (describeUi) {
        // The window's structure only: offscreen, no Vulkan, no data.
        if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
        QApplication app(argc, argv);
        QApplication::setApplicationName("fray");
        fray::editor::EditorOptions options;
        options.restoreLayout = false;
        fray::editor::MainWindow window(nullptr, {}, nullptr, {}, "describe-ui", options);
        const QByteArray json = window.describeUi();
        std::fwrite(json.constData(), 1, static_cast<std::size_t>(json.size()), stdout);
        return 0;
    }
    if (inputs.empty()) {
        // The demo project, in the editor.
        auto demo = fray::app::findDemoProject(argc > 0 ? argv[0] : nullptr);
        if (!demo)
            return fail("no input given and no demo project found (build the project first; it writes "
                        "build/demo-library/demo.frayproj, or set FRAY_DEMO_LIBRARY)",
                        2);
        inputs.push_back(demo->string());
    }
    // A scene, or takes side by side.
    std::unique_ptr<fray::cli::SceneStage> scene;
    std::vector<fray::app::LoadedTake> takes;
    if (inputs.size() == 1 && std::filesystem::path(inputs[0]).extension() == ".frayscene") {
        auto loaded = fray::pipeline::openScene(inputs[0], {}, [](std::string_view note) {
            std::fprintf(stderr, "fray: %.*s\n", static_cast<int>(note.size()), note.data());
        });
        if (!loaded) return fail(loaded.error().message);
        scene = std::make_unique<fray::cli::SceneStage>(std::move(*loaded));
    } else {
        auto loadedTakes = fray::app::loadTakes(inputs);
        if (!loadedTakes) return fail(loadedTakes.error().message);
        takes = std::move(*loadedTakes);
    }
    // The rig, bound to every skeleton on show, before any window opens.
    fray::cli::SkeletonRigs rigs;
    if (!rig.empty()) {
        std::vector<const fray::Skeleton*> skeletons = scene ? scene->skeletons() : std::vector<const fray::Skeleton*>{};
        for (const fray::app::LoadedTake& take : takes) skeletons.push_back(&take.motion->skeleton());
        auto loaded = fray::cli::loadRigs(rig, skeletons);
        if (!loaded) return fail(loaded.error().message);
        for (const std::string& w : loaded->warnings) std::fprintf(stderr, "fray: warning: %s\n", w.c_str());
        rigs = std::move(*loaded);
    }
    const std::string title = std::filesystem::path(inputs.front()).filename().string() +
                              (inputs.size() > 1 ? " (+" + std::to_string(inputs.size() - 1) + ")" : "");

    if (const std::string problem = displayProblem(); !problem.empty()) return fail(problem);
    QApplication app(argc, argv);
    QApplication::setApplicationName("fray");
    const QString platform = QGuiApplication::platformName();

    // Fray's Vulkan instance, adopted by Qt for the viewport's surface.
    fray::render::DeviceOptions dopt;
    dopt.applicationName = "fray";
    dopt.validation = validate;
    dopt.swapchain = true;
    dopt.instanceExtensions = {"VK_KHR_surface"};
    if (platform == "xcb") dopt.instanceExtensions.emplace_back("VK_KHR_xcb_surface");
    else if (platform == "wayland") dopt.instanceExtensions.emplace_back("VK_KHR_wayland_surface");
    else return fail("the Qt platform '" + platform.toStdString() + "' has no Vulkan window surface; run on X11 or Wayland "
                     "(headless: xvfb-run -a fray ...)");
    auto device = fray::render::VulkanDevice::create(dopt);
    if (!device) {
        const int code = fail(device.error().message);
        if (quitAfter == 0) QMessageBox::critical(nullptr, "Fray", QString::fromStdString(device.error().message));
        return code;
    }
    const auto log = (*device)->validationLog();
    int code = 0;
    {
        QVulkanInstance qvi;
        qvi.setVkInstance((*device)->instance());
        if (!qvi.create()) return fail("Qt could not adopt the Vulkan instance");
        auto* viewport = new fray::editor::Viewport(*device, &qvi);  // owned by its window container
        if (fray::Status s = viewport->init(q); !s) {
            delete viewport;
            return fail(s.error().message);
        }
        if (fray::Status s = fray::cli::applyRigs(rigs, *viewport->renderer()); !s) {
            delete viewport;
            return fail(s.error().message);
        }
        fray::editor::EditorOptions options;
        options.quitAfter = quitAfter;
        options.screenshot = QString::fromStdString(screenshot);
        options.viewportScreenshot = QString::fromStdString(viewportShot);
        {
            options.waitForAnalysis = waitAnalysis;
            options.generateSpec = QString::fromStdString(generateSpec);
            options.restoreLayout = !freshLayout;
            const QString projectFile = inputs.size() == 1 && std::filesystem::path(inputs[0]).extension() == ".frayproj"
                                            ? QString::fromStdString(inputs[0])
                                            : QString();
            fray::editor::MainWindow window(viewport, std::move(takes), std::move(scene), projectFile,
                                            QString::fromStdString(title), options);
            window.show();
            window.setPostureMode(*postureMode);
            code = QApplication::exec();
            if (code == 0) code = window.exitCode();
        }
        qvi.destroy();
    }
    device->reset();
    if (code == 0 && validate && (log->errors() > 0 || log->warnings() > 0))
        code = fail(std::to_string(log->errors()) + " Vulkan validation errors and " + std::to_string(log->warnings()) +
                        " warnings (printed above)",
                    3);
    return code;
}
