// fray-play: the real-time player (GLFW window, Vulkan, Dear ImGui overlay).
// Plays motion files or a project's takes side by side, or a planned or
// composed scene (*.frayscene); with no argument, the demo project the build
// writes.
//
//   fray-play [MOTION... | PROJECT.frayproj | SCENE.frayscene] [--frames N] [--screenshot out.png] [--rig FILE]
//             [--posture kinematic|physics]
//
// --posture physics plays a scene with the posture solver's poses
// (docs/POSTURE.md), simulated over the whole scene before the window opens.
//
// --rig FILE draws the characters as a skinned rig (glTF/GLB, FBX, ...) instead
// of capsules.
//
// --frames N draws N frames and exits 0 (CI runs it under xvfb-run).
//
//   fray-play --duel [PROJECT.frayproj] [--graph FILE] [--style S] [--depth D] [--input FILE] [--log FILE]
//   fray-play --teams N [PROJECT.frayproj] ...
//
// --duel: the user steers a boxer (keyboard, gamepad) against the Interaction
// Graph's policy; --teams N: N characters in two teams, each fighting its
// closest enemy, the user steering one (duel.h, docs/IGRAPH.md). --input
// FILE: timed commands (duel_script.h); --log FILE: what happened, as JSON.
//
//   fray-play --carry [PROJECT.frayproj] [--path circle:R|FILE] [--graph FILE] [--depth D] [--input FILE] [--log FILE]
//
// --carry: two carriers of one long box follow the direction the user steers
// (keyboard, gamepad) or a path, on the Interaction Graph's collaborative
// policies (carry_play.h, docs/IGRAPH.md).
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "duel.h"
#include "duel_script.h"
#include "carry_play.h"
#include "fray/render/presenter.h"
#include "fray/render/renderer.h"
#include "fray/pipeline/sim_session.h"
#include "rig_setup.h"
#include "scene_stage.h"
#include "takes.h"

namespace {

using namespace fray;
using Clock = std::chrono::steady_clock;

int fail(const std::string& message, int code = 1) {
    std::fprintf(stderr, "fray-play: %s\n", message.c_str());
    return code;
}

std::string glfwErrorText;
void onGlfwError(int, const char* text) { glfwErrorText = text ? text : ""; }

struct Args {
    std::vector<std::string> inputs;
    int frames = 0;
    std::string screenshot;
    std::string size = "1280x720";
    std::string quality = "auto";
    bool validate = false;
    bool noVsync = false;
    bool hidePanel = false;
    std::string rig;
    std::string posture;  // a scene's: kinematic | physics
    bool handPins = false;  // --hand-pins (with --posture physics)
    // The Interaction Graph duel and team fight.
    bool duel = false;
    bool carry = false;  // --carry: two carriers of a box
    std::string path;    // --carry --path circle:R | FILE
    int teams = 0;
    std::string graph, style = "general", input, log;
    int depth = 3;
    std::int64_t graphStates = 80000;
    std::uint64_t seed = 1;
    double frameTime = 1.0 / 60.0;
};

// Mouse: left drag orbits, right or middle drag pans, the wheel zooms.
struct Mouse {
    bool dragging = false;
    int button = -1;
    double x = 0, y = 0;
    double wheel = 0;
};
Mouse gMouse;

void onScroll(GLFWwindow*, double, double dy) { gMouse.wheel += dy; }

// Moving averages of the frame time for the stats panel.
struct FrameStats {
    std::array<float, 120> ms{};
    int count = 0;
    void add(float v) { ms[static_cast<std::size_t>(count++ % static_cast<int>(ms.size()))] = v; }
    float average() const {
        const int n = std::min(count, static_cast<int>(ms.size()));
        float s = 0;
        for (int i = 0; i < n; ++i) s += ms[static_cast<std::size_t>(i)];
        return n ? s / static_cast<float>(n) : 0.0f;
    }
};

void checkVk(VkResult r) {
    if (r != VK_SUCCESS) std::fprintf(stderr, "fray-play: ImGui Vulkan call failed: %s\n", render::vkResultName(r).c_str());
}

}  // namespace

int main(int argc, char** argv) {
    Args args;
    CLI::App cli{"fray-play: play motions, a project's takes or a planned scene in real time"};
    cli.add_option("inputs", args.inputs, "Motion files, one .frayproj or one .frayscene (default: the demo project)");
    cli.add_option("--frames", args.frames, "Draw this many frames, then exit 0 (for tests)");
    cli.add_option("--screenshot", args.screenshot, "Write the last frame as shown (viewport and overlay) to this PNG");
    cli.add_option("--size", args.size, "Window size WIDTHxHEIGHT")->capture_default_str();
    cli.add_option("--quality", args.quality, "auto, fast or high (auto: fast on a CPU Vulkan device)")->capture_default_str();
    cli.add_flag("--validate", args.validate, "Vulkan validation layers on; any message makes the exit code 3");
    cli.add_flag("--no-vsync", args.noVsync, "Present as fast as possible");
    cli.add_flag("--hide-panel", args.hidePanel, "Start with the panel hidden (Tab shows and hides it)");
    cli.add_option("--rig", args.rig,
                   "Draw the characters as this skinned rig (glTF/GLB, FBX, ...) instead of capsules; bones are matched to "
                   "joints by name");
    cli.add_option("--posture", args.posture,
                   "A scene's posture mode: kinematic (the captured clips; default) or physics (the posture solver)");
    cli.add_flag("--hand-pins", args.handPins,
                 "With --posture physics: pin a porter's hands to the luggage it holds (off by default, docs/POSTURE.md)");
    cli.add_flag("--duel", args.duel,
                 "Fight the Interaction Graph's boxer: steer yours with the keyboard or a gamepad (the input: the project)");
    cli.add_flag("--carry", args.carry,
                 "Two carriers of one long box follow the direction you steer (keyboard, gamepad) or --path, on the Interaction Graph "
                 "(the input: a project with the carry set's actions)");
    cli.add_option("--path", args.path, "--carry: follow this path, circle:R or a JSON file {version: 1, loop, points: [[x, z], ...]}");
    cli.add_option("--teams", args.teams, "A team fight of N characters on the Interaction Graph, the user steering one");
    cli.add_option("--graph", args.graph, "--duel/--teams: the graph file (default PROJECT.igraph; built and kept there when missing or stale)");
    cli.add_option("--style", args.style, "--duel/--teams: the opponents' style: general, infighter or outboxer")->capture_default_str();
    cli.add_option("--depth", args.depth, "--duel/--teams: the opponents' policy depth (1-10)")->capture_default_str();
    cli.add_option("--input", args.input,
                   "--duel/--teams: timed commands, one a line: SECONDS COMMAND [CHARACTER] | SECONDS style NAME | SECONDS depth D "
                   "(or the runtime's .json)");
    cli.add_option("--log", args.log, "--duel/--teams: write the actions, commands, hits and policies as JSON to this file at exit");
    auto* graphStatesOption =
        cli.add_option("--graph-states", args.graphStates, "--duel/--teams: size of a graph built here (states at most; --carry: 20000)")
            ->capture_default_str();
    cli.add_option("--seed", args.seed, "--duel/--teams: the match's seed (start placements)")->capture_default_str();
    cli.add_option("--frame-time", args.frameTime, "With --frames: seconds of playback per frame")->capture_default_str();
    CLI11_PARSE(cli, argc, argv);
    if (args.frames < 0) return fail("--frames must be >= 0", 2);
    if (!(args.frameTime > 0 && args.frameTime <= 1)) return fail("--frame-time must be in (0, 1] s", 2);
    const bool duelMode = args.duel || args.teams > 0 || args.carry;
    if ((args.duel ? 1 : 0) + (args.teams > 0 ? 1 : 0) + (args.carry ? 1 : 0) > 1) return fail("--duel, --teams and --carry: choose one", 2);
    if (!duelMode && (!args.input.empty() || !args.log.empty() || !args.graph.empty()))
        return fail("--input, --log and --graph are for --duel, --teams or --carry", 2);
    if (!args.carry && !args.path.empty()) return fail("--path is for --carry", 2);
    if (duelMode && (args.inputs.size() > 1 || (args.inputs.size() == 1 && std::filesystem::path(args.inputs[0]).extension() != ".frayproj")))
        return fail(std::string(args.carry ? "--carry" : "--duel/--teams") + ": give one project (*.frayproj), or none for the demo project", 2);
    if (duelMode && !args.posture.empty()) return fail("--posture: only for a scene (.frayscene)", 2);
    const auto postureMode = fray::posture::parseMode(args.posture.empty() ? "kinematic" : args.posture);
    if (!postureMode) return fail("--posture: '" + args.posture + "' is not kinematic or physics", 2);
    if (args.handPins && *postureMode != fray::posture::Mode::Physics) return fail("--hand-pins: only with --posture physics", 2);
    int width = 1280, height = 720;
    if (std::sscanf(args.size.c_str(), "%dx%d", &width, &height) != 2 || width < 64 || height < 64)
        return fail("--size " + args.size + ": expected WIDTHxHEIGHT, at least 64x64", 2);
    render::Quality quality = render::Quality::Auto;
    if (args.quality == "fast") quality = render::Quality::Fast;
    else if (args.quality == "high") quality = render::Quality::High;
    else if (args.quality != "auto") return fail("--quality " + args.quality + ": expected auto, fast or high", 2);

    // What to play.
    if (args.inputs.empty()) {
        auto demo = app::findDemoProject(argc > 0 ? argv[0] : nullptr);
        if (!demo)
            return fail("no input given and no demo project found (build the project first; it writes "
                        "build/demo-library/demo.frayproj, or set FRAY_DEMO_LIBRARY)",
                        2);
        args.inputs.push_back(demo->string());
    }
    // A scene (planned or composed), or takes side by side.
    std::unique_ptr<cli::SceneStage> scene;
    std::unique_ptr<player::PlayMode> live;  // --duel, --teams or --carry
    std::vector<app::LoadedTake> takeList;
    if (args.carry) {
        player::CarryPlayOptions copt;
        copt.project = args.inputs[0];
        copt.graph = args.graph;
        copt.path = args.path;
        copt.depth = args.depth;
        copt.input = args.input;
        copt.log = args.log;
        if (graphStatesOption->count() > 0) copt.graphStates = args.graphStates;
        copt.seed = args.seed;
        copt.foreground = args.frames > 0;  // a counted run plays the same every time
        auto opened = player::CarryPlay::open(copt);
        if (!opened) return fail(opened.error().message);
        live = std::move(*opened);
    } else if (duelMode) {
        player::DuelOptions dopt;
        dopt.project = args.inputs[0];
        dopt.graph = args.graph;
        dopt.characters = args.duel ? 2 : args.teams;
        dopt.style = args.style;
        dopt.depth = args.depth;
        dopt.input = args.input;
        dopt.log = args.log;
        dopt.graphStates = args.graphStates;
        dopt.seed = args.seed;
        dopt.foreground = args.frames > 0;  // a counted run plays the same fight every time
        auto opened = player::Duel::open(dopt);
        if (!opened) return fail(opened.error().message);
        live = std::move(*opened);
    } else if (args.inputs.size() == 1 && std::filesystem::path(args.inputs[0]).extension() == ".frayscene") {
        auto loaded = pipeline::openScene(args.inputs[0], {}, [](std::string_view note) {
            std::fprintf(stderr, "fray-play: %.*s\n", static_cast<int>(note.size()), note.data());
        });
        if (!loaded) return fail(loaded.error().message);
        scene = std::make_unique<cli::SceneStage>(std::move(*loaded));
        if (*postureMode == fray::posture::Mode::Physics) {
            std::fprintf(stderr, "fray-play: posture solver over the scene...\n");
            fray::posture::Options postureOptions;
            postureOptions.handPins = args.handPins;
            if (Status st = scene->setPosture(*postureMode, {}, postureOptions); !st) return fail(st.error().message);
            for (const auto& n : scene->postureReport()->notes) std::fprintf(stderr, "fray-play: note: %s\n", n.c_str());
        }
    } else {
        if (!args.posture.empty()) return fail("--posture: only for a scene (.frayscene)", 2);
        auto takes = app::loadTakes(args.inputs);
        if (!takes) return fail(takes.error().message);
        takeList = std::move(*takes);
    }
    // The rig, bound to every skeleton on show, before any window opens.
    cli::SkeletonRigs rigs;
    if (!args.rig.empty()) {
        std::vector<const Skeleton*> skeletons = scene ? scene->skeletons() : std::vector<const Skeleton*>{};
        for (const app::LoadedTake& take : takeList) skeletons.push_back(&take.motion->skeleton());
        auto loaded = cli::loadRigs(args.rig, skeletons);
        if (!loaded) return fail(loaded.error().message);
        for (const std::string& w : loaded->warnings) std::fprintf(stderr, "fray-play: warning: %s\n", w.c_str());
        rigs = std::move(*loaded);
    }

    // Window.
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
        const char* display = std::getenv("DISPLAY");
        const char* wayland = std::getenv("WAYLAND_DISPLAY");
        if ((!display || !*display) && (!wayland || !*wayland))
            return fail("no display: DISPLAY is not set; run it in a desktop session, or headless under Xvfb "
                        "(xvfb-run -a fray-play ...)");
        return fail("cannot open a window: " + glfwErrorText + " (is the X server at DISPLAY=" +
                    std::string(display ? display : "") + " running? headless: xvfb-run -a fray-play ...)");
    }
    struct GlfwGuard {
        ~GlfwGuard() { glfwTerminate(); }
    } glfwGuard;
    if (!glfwVulkanSupported()) return fail("GLFW found no Vulkan loader; install libvulkan1 and mesa-vulkan-drivers");
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(width, height, "fray-play", nullptr, nullptr);
    if (!window) return fail("cannot create the window: " + glfwErrorText);
    glfwSetScrollCallback(window, onScroll);

    render::DeviceOptions dopt;
    dopt.applicationName = "fray-play";
    dopt.validation = args.validate;
    std::uint32_t extCount = 0;
    const char** exts = glfwGetRequiredInstanceExtensions(&extCount);
    for (std::uint32_t i = 0; i < extCount; ++i) dopt.instanceExtensions.emplace_back(exts[i]);
    dopt.createSurface = [window](VkInstance instance) -> Result<VkSurfaceKHR> {
        VkSurfaceKHR surface = VK_NULL_HANDLE;
        const VkResult r = glfwCreateWindowSurface(instance, window, nullptr, &surface);
        if (r != VK_SUCCESS) return render::vkError("glfwCreateWindowSurface", r);
        return surface;
    };
    auto device = render::VulkanDevice::create(dopt);
    if (!device) return fail(device.error().message);
    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(window, &fbw, &fbh);
    render::RendererOptions ropt;
    ropt.width = std::max(fbw, 1);
    ropt.height = std::max(fbh, 1);
    ropt.quality = quality;
    auto renderer = render::Renderer::create(*device, ropt);
    if (!renderer) return fail(renderer.error().message);
    if (Status s = cli::applyRigs(rigs, **renderer); !s) return fail(s.error().message);
    render::PresenterOptions popt;
    popt.vsync = !args.noVsync && args.frames == 0;
    auto presenter = render::Presenter::create(*device, fbw, fbh, popt);
    if (!presenter) return fail(presenter.error().message);

    // Dear ImGui on the presenter's UI pass.
    VkDescriptorPool imguiPool = VK_NULL_HANDLE;
    {
        const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16};
        VkDescriptorPoolCreateInfo ci{};
        ci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
        ci.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
        ci.maxSets = 16;
        ci.poolSizeCount = 1;
        ci.pPoolSizes = &size;
        if (const VkResult r = vkCreateDescriptorPool((*device)->device(), &ci, nullptr, &imguiPool); r != VK_SUCCESS)
            return fail(render::vkError("vkCreateDescriptorPool", r).message);
    }
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForVulkan(window, true);
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = (*device)->instance();
    info.PhysicalDevice = (*device)->physicalDevice();
    info.Device = (*device)->device();
    info.QueueFamily = (*device)->queueFamily();
    info.Queue = (*device)->queue();
    info.DescriptorPool = imguiPool;
    info.Subpass = 0;
    info.MinImageCount = (*presenter)->minImageCount();
    info.ImageCount = (*presenter)->imageCount();
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = checkVk;
    ImGui_ImplVulkan_Init(&info, (*presenter)->uiRenderPass());
    if (Status s = (*device)->runOnce([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); }); !s)
        return fail(s.error().message);
    ImGui_ImplVulkan_DestroyFontUploadObjects();

    // Stage, camera, playback.
    render::MotionStage stage;
    if (!scene && !live) app::stageTakes(takeList, stage);
    stage.pose(0.0);
    render::FrameDescription frame;
    frame.camera.yaw = 0.5f;
    frame.camera.pitch = 0.35f;
    const int characters = live ? 0 : scene ? scene->characterCount() : static_cast<int>(stage.actors().size());
    // The overlay panel's right edge in framebuffer pixels: framing centres
    // the characters in the part of the view right of it, so the panel does
    // not hide them in a small window. Until the first frame lays the panel
    // out, where it opens (10 px in, 330 px wide).
    float panelRight = 340.0f;
    auto frameSelection = [&](int selected) {
        render::Bounds b;
        if (live) {
            b = live->framing();
        } else if (scene) {
            // The selected character as it is now, or everyone over the whole scene.
            std::size_t k = 0;
            while (k < scene->shown().size() && scene->shownCharacter(k) != selected) ++k;
            b = k < scene->shown().size() ? render::characterBounds(scene->shown().subspan(k, 1)) : scene->bounds(0.0, scene->duration());
        } else {
            b = selected >= 0 ? render::characterBounds(stage.instances().subspan(static_cast<std::size_t>(selected), 1)) : stage.bounds();
        }
        b.add(b.min - glm::vec3(0.3f));
        b.add(b.max + glm::vec3(0.3f));
        const auto w = static_cast<float>(std::max(fbw, 1)), h = static_cast<float>(std::max(fbh, 1));
        if (w - panelRight >= 0.4f * w) {
            frame.camera.frame(b, (w - panelRight) / h);
            frame.camera.pan(0.5f * panelRight, 0.0f, h);  // the scene moves right by half the panel
        } else {
            frame.camera.frame(b, w / h);  // too narrow a window to keep anything beside the panel
        }
    };
    frameSelection(-1);
    int selected = -1;
    bool playing = true, loop = true;
    float speed = 1.0f;
    double t = 0.0;
    const double duration = scene ? scene->duration() : stage.duration();
    FrameStats frameMs, renderMs;
    auto last = Clock::now();
    int drawn = 0;
    const render::Presenter::UiRecorder ui = [](VkCommandBuffer cmd) {
        ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
    };
    std::string error;
    bool screenshotWritten = false;
    const std::string deviceName = (*device)->description();

    while (!glfwWindowShouldClose(window)) {
        glfwPollEvents();
        glfwGetFramebufferSize(window, &fbw, &fbh);
        if (fbw == 0 || fbh == 0) {  // minimised
            glfwWaitEvents();
            continue;
        }
        (*presenter)->resize(fbw, fbh);
        const auto now = Clock::now();
        // Fixed steps when counting frames, so test runs are reproducible.
        const double dt = args.frames > 0 ? args.frameTime : std::chrono::duration<double>(now - last).count();
        frameMs.add(static_cast<float>(std::chrono::duration<double, std::milli>(now - last).count()));
        last = now;
        if (playing) t += dt * static_cast<double>(speed);
        if (!loop && t > duration) {
            t = duration;
            playing = false;
        }
        if (live) {
            const bool wasReady = live->ready();
            if (Status s = live->update(dt, window, !ImGui::GetIO().WantCaptureKeyboard); !s) {
                error = s.error().message;
                break;
            }
            if (!wasReady && live->ready()) frameSelection(-1);
            frame.camera.target += live->moved();  // the camera follows the fight or the carriers
        } else if (scene) {
            scene->pose(loop && duration > 0.0 ? std::fmod(t, duration) : std::min(t, duration), cli::SceneStage::Labels::Auto, selected);
        } else {
            for (std::size_t i = 0; i < stage.actors().size(); ++i) stage.actors()[i].selected = static_cast<int>(i) == selected;
            stage.pose(t, loop);
        }

        // Camera from the mouse, unless ImGui uses it.
        ImGuiIO& io = ImGui::GetIO();
        double mx = 0, my = 0;
        glfwGetCursorPos(window, &mx, &my);
        if (!io.WantCaptureMouse) {
            int button = -1;
            for (int b : {GLFW_MOUSE_BUTTON_LEFT, GLFW_MOUSE_BUTTON_RIGHT, GLFW_MOUSE_BUTTON_MIDDLE})
                if (glfwGetMouseButton(window, b) == GLFW_PRESS) button = b;
            if (button >= 0 && gMouse.dragging && gMouse.button == button) {
                const auto dx = static_cast<float>(mx - gMouse.x), dy = static_cast<float>(my - gMouse.y);
                if (button == GLFW_MOUSE_BUTTON_LEFT) frame.camera.orbit(-dx * 0.008f, dy * 0.008f);
                else frame.camera.pan(dx, dy, static_cast<float>(fbh));
            }
            gMouse.dragging = button >= 0;
            gMouse.button = button;
            if (gMouse.wheel != 0.0) frame.camera.zoom(static_cast<float>(std::pow(0.88, gMouse.wheel)));
        }
        gMouse.wheel = 0.0;
        gMouse.x = mx;
        gMouse.y = my;
        if (!io.WantCaptureKeyboard) {
            if (!live && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Space))) playing = !playing;
            if (ImGui::IsKeyPressed(GLFW_KEY_F)) frameSelection(selected);
            if (ImGui::IsKeyPressed(GLFW_KEY_TAB)) args.hidePanel = !args.hidePanel;
        }

        // The overlay.
        ImGui_ImplVulkan_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        if (args.hidePanel) {
            panelRight = 0.0f;
        } else {  // the panel (Tab hides it)
            ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
            ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
            ImGui::Begin("fray-play");
            {
                int ww = 0, wh = 0;
                glfwGetWindowSize(window, &ww, &wh);
                const float scale = ww > 0 ? static_cast<float>(fbw) / static_cast<float>(ww) : 1.0f;
                panelRight = ImGui::IsWindowCollapsed() ? 0.0f : (ImGui::GetWindowPos().x + ImGui::GetWindowSize().x) * scale;
            }
            if (live) {
                live->overlay();
                if (ImGui::Button(live->frameButton())) frameSelection(-1);
            } else {
                if (ImGui::Button(playing ? "Pause" : "Play")) playing = !playing;
                ImGui::SameLine();
                if (ImGui::Button("|<")) t = 0.0;
                ImGui::SameLine();
                ImGui::Checkbox("Loop", &loop);
                auto time = static_cast<float>(loop && duration > 0.0 ? std::fmod(t, duration) : t);
                if (ImGui::SliderFloat("Time", &time, 0.0f, static_cast<float>(duration), "%.2f s")) t = time;
                ImGui::SliderFloat("Speed", &speed, 0.1f, 4.0f, "%.2fx");
                ImGui::Separator();
                ImGui::Text("Characters (click to select, F frames)");
                for (int i = 0; i < characters; ++i) {
                    const glm::vec3 tint = scene ? scene->tint(i) : stage.actors()[static_cast<std::size_t>(i)].tint;
                    const std::string& name = scene ? scene->scene().characters[static_cast<std::size_t>(i)].name
                                                    : stage.actors()[static_cast<std::size_t>(i)].name;
                    ImGui::PushID(i);
                    ImGui::ColorButton("##tint", ImVec4(tint.x, tint.y, tint.z, 1.0f), ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
                    ImGui::SameLine();
                    if (ImGui::Selectable(name.c_str(), selected == i)) selected = selected == i ? -1 : i;
                    ImGui::PopID();
                }
                if (scene && selected >= 0) {
                    const auto& sc = scene->scene().characters[static_cast<std::size_t>(selected)];
                    ImGui::Separator();
                    ImGui::Text("%s (side %d)", sc.name.c_str(), sc.side);
                    ImGui::Text("action: %s", scene->present(selected) ? scene->currentAction(selected).c_str() : "(not in the scene yet)");
                    int given = 0, received = 0;
                    for (const auto& h : scene->scene().hits) {
                        if (h.blocked) continue;
                        given += h.attacker == selected ? 1 : 0;
                        received += h.defender == selected ? 1 : 0;
                    }
                    ImGui::Text("hits given %d, received %d", given, received);
                    if (ImGui::Button("Frame selection")) frameSelection(selected);
                } else if (!scene && selected >= 0) {
                    const auto& a = stage.actors()[static_cast<std::size_t>(selected)];
                    const std::string_view action = stage.actionOf(selected);
                    ImGui::Separator();
                    ImGui::Text("%s  frame %d / %d", a.name.c_str(), stage.frameOf(selected), a.motion->frameCount() - 1);
                    ImGui::Text("action: %.*s", static_cast<int>(action.size()), action.empty() ? "(none)" : action.data());
                    if (ImGui::Button("Frame selection")) frameSelection(selected);
                } else if (ImGui::Button("Frame all")) {
                    frameSelection(-1);
                }
            }
            ImGui::Separator();
            const auto& st = (*renderer)->stats();
            const float avg = frameMs.average();
            ImGui::Text("frame %.1f ms (%.0f fps), render %.1f ms", static_cast<double>(avg),
                        avg > 0.0f ? 1000.0 / static_cast<double>(avg) : 0.0, static_cast<double>(renderMs.average()));
            ImGui::Text("%d characters, %llu triangles, %d draws", st.characters, static_cast<unsigned long long>(st.triangles),
                        st.drawCalls);
            ImGui::TextWrapped("%s, %s quality, %dx MSAA", deviceName.c_str(),
                               (*renderer)->quality() == render::Quality::Fast ? "fast" : "high", (*renderer)->msaaSamples());
            ImGui::End();
        }
        ImGui::Render();

        frame.characters = live ? live->shown() : scene ? scene->shown() : stage.instances();
        if (live) frame.trajectories = live->lines();
        if (scene) {
            frame.trajectories = scene->trajectories();
            frame.checkpoints = scene->checkpoints();
            frame.floorBitmap = scene->floorBitmap();
        }
        const bool lastFrame = args.frames > 0 && drawn + 1 >= args.frames;
        render::Image shown;
        const bool capturing = lastFrame && !args.screenshot.empty() && (*presenter)->captureNextFrame(&shown);
        const auto r0 = Clock::now();
        if (Status s = (*presenter)->present(**renderer, frame, &ui); !s) {
            error = s.error().message;
            break;
        }
        renderMs.add(static_cast<float>(std::chrono::duration<double, std::milli>(Clock::now() - r0).count()));
        if (capturing && !shown.empty()) {
            if (Status w = render::writePng(args.screenshot, shown); !w) {
                error = w.error().message;
                break;
            }
            screenshotWritten = true;
        }
        if (args.frames > 0 && ++drawn >= args.frames) break;
    }

    int code = 0;
    if (!error.empty()) code = fail(error);
    if (live) {
        if (Status s = live->writeLog(); !s && code == 0) code = fail(s.error().message);
    }
    if (code == 0 && !args.screenshot.empty() && !screenshotWritten) {
        // The window's images cannot be read back here (or the window closed
        // early): the scene alone, from the renderer.
        render::Image shot;
        if (Status s = (*renderer)->readback(shot); !s) code = fail(s.error().message);
        else if (Status w = render::writePng(args.screenshot, shot); !w) code = fail(w.error().message);
    }
    (void)(*device)->waitIdle();
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    vkDestroyDescriptorPool((*device)->device(), imguiPool, nullptr);
    presenter->reset();
    renderer->reset();
    const auto log = (*device)->validationLog();
    device->reset();  // reports leaked Vulkan objects when validating
    glfwDestroyWindow(window);
    if (code == 0 && args.validate && (log->errors() > 0 || log->warnings() > 0))
        code = fail(std::to_string(log->errors()) + " Vulkan validation errors and " + std::to_string(log->warnings()) +
                        " warnings (printed above)",
                    3);
    if (code == 0 && args.frames > 0 && live) std::printf("fray-play: %s\n", live->summary().c_str());
    if (code == 0 && args.frames > 0) std::printf("fray-play: drew %d frames on %s\n", drawn, deviceName.c_str());
    return code;
}
