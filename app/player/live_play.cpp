#include "live_play.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include <unistd.h>

#include "fray/core/atomic_file.h"
#include "fray/core/kinematics.h"
#include "fray/igraph/carry.h"
#include "fray/igraph/igraph.h"
#include "scene_stage.h"

namespace fray::player {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

GraphAtPlace graphAtPlace(const fs::path& file) {
    std::error_code ec;
    if (!fs::exists(file, ec)) return GraphAtPlace::Missing;
    auto head = readWholeFile(file, "the graph");
    if (!head || head->size() < 8) return GraphAtPlace::Other;
    const std::string_view h(head->data(), 8);
    if (h == igraph::kGraphMagic) return GraphAtPlace::Duel;
    if (h == igraph::kCarryGraphMagic) return GraphAtPlace::Carry;
    return GraphAtPlace::Other;
}

ProgressFn terminalProgress(bool quiet) {
    if (quiet || !isatty(2)) return {};
    return [last = -1](double f, std::string_view stage) mutable {
        const int pct = static_cast<int>(f * 100);
        if (pct / 10 != last / 10) std::fprintf(stderr, "fray-play: %.*s %d%%\n", static_cast<int>(stage.size()), stage.data(), pct), last = pct;
        return true;
    };
}

// ---- GraphBuild ----------------------------------------------------------------------------

ProgressFn GraphBuild::progress() {
    return [this](double f, std::string_view s) {
        {
            std::lock_guard lock(mutex_);
            fraction_ = f;
            stage_ = std::string(s);
        }
        return !cancel.load();
    };
}

void GraphBuild::stage(std::string s) {
    std::lock_guard lock(mutex_);
    stage_ = std::move(s);
}

void GraphBuild::note(std::string n) {
    std::lock_guard lock(mutex_);
    notes_.push_back(std::move(n));
}

void GraphBuild::start(bool foreground, bool quiet, std::function<std::string()> work) {
    {
        std::lock_guard lock(mutex_);
        for (const auto& n : notes_) {
            if (!quiet) std::fprintf(stderr, "fray-play: %s\n", n.c_str());
        }
    }
    auto run = [this, work = std::move(work)] {
        std::string error = work();
        std::lock_guard lock(mutex_);
        error_ = std::move(error);
        done_ = true;
    };
    if (foreground) run();
    else worker_ = std::thread(std::move(run));
}

Status GraphBuild::finish() {
    if (worker_.joinable()) worker_.join();
    if (!error_.empty()) return makeError(error_);
    return {};
}

void GraphBuild::stop() {
    cancel = true;
    if (worker_.joinable()) worker_.join();
}

void GraphBuild::panel(const char* what) {
    std::lock_guard lock(mutex_);
    ImGui::TextWrapped("Building %s (%s)", what, stage_.c_str());
    ImGui::ProgressBar(static_cast<float>(fraction_), ImVec2(-1, 0));
    for (const auto& n : notes_) ImGui::TextWrapped("%s", n.c_str());
}

// ---- InputReader ---------------------------------------------------------------------------

InputReader::InputReader(std::vector<Hold> holds, std::vector<int> keys, double repeat)
    : holds_(std::move(holds)), keys_(std::move(keys)), repeat_(repeat) {
    holds_.resize(std::min(holds_.size(), kMaxHolds));
    keys_.resize(std::min(keys_.size(), kMaxKeys));
}

Controls InputReader::read(GLFWwindow* window, bool keyboard) {
    Controls c;
    if (keyboard && window) {
        auto key = [&](int k) { return k != GLFW_KEY_UNKNOWN && glfwGetKey(window, k) == GLFW_PRESS; };
        for (std::size_t i = 0; i < holds_.size(); ++i) {
            if (key(holds_[i].key) || key(holds_[i].otherKey)) c.down[i] = true, c.from[i] = "keyboard";
        }
        for (std::size_t i = 0; i < keys_.size(); ++i) c.keys[i] = keyEdges_.pressed(i, key(keys_[i]));
        c.depthUp = keyEdges_.pressed(kMaxKeys, key(GLFW_KEY_EQUAL) || key(GLFW_KEY_KP_ADD));
        c.depthDown = keyEdges_.pressed(kMaxKeys + 1, key(GLFW_KEY_MINUS) || key(GLFW_KEY_KP_SUBTRACT));
        c.pause = keyEdges_.pressed(kMaxKeys + 2, key(GLFW_KEY_P));
        c.restart = keyEdges_.pressed(kMaxKeys + 3, key(GLFW_KEY_R));
    }
    // The first joystick with a gamepad mapping.
    gamepad_.clear();
    for (int j = GLFW_JOYSTICK_1; j <= GLFW_JOYSTICK_LAST; ++j) {
        GLFWgamepadstate gp;
        if (!glfwJoystickIsGamepad(j) || !glfwGetGamepadState(j, &gp)) continue;
        const char* name = glfwGetGamepadName(j);
        gamepad_ = name ? name : "gamepad";
        const float x = gp.axes[GLFW_GAMEPAD_AXIS_LEFT_X], y = gp.axes[GLFW_GAMEPAD_AXIS_LEFT_Y];
        auto btn = [&](int b) { return gp.buttons[b] == GLFW_PRESS; };
        auto on = [&](Pad p) {
            switch (p) {
                case Pad::Up: return y < -0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_UP);
                case Pad::Down: return y > 0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_DOWN);
                case Pad::Left: return x < -0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_LEFT);
                case Pad::Right: return x > 0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_RIGHT);
                case Pad::A: return btn(GLFW_GAMEPAD_BUTTON_A);
                case Pad::B: return btn(GLFW_GAMEPAD_BUTTON_B);
                case Pad::X: return btn(GLFW_GAMEPAD_BUTTON_X);
                case Pad::Y: return btn(GLFW_GAMEPAD_BUTTON_Y);
            }
            return false;
        };
        for (std::size_t i = 0; i < holds_.size(); ++i) {
            if (on(holds_[i].pad) && !c.from[i]) c.down[i] = true, c.from[i] = "gamepad";
        }
        c.next = padEdges_.pressed(0, btn(GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER));
        c.prev = padEdges_.pressed(1, btn(GLFW_GAMEPAD_BUTTON_LEFT_BUMPER));
        c.depthUp = padEdges_.pressed(2, gp.axes[GLFW_GAMEPAD_AXIS_RIGHT_TRIGGER] > 0.5f) || c.depthUp;
        c.depthDown = padEdges_.pressed(3, gp.axes[GLFW_GAMEPAD_AXIS_LEFT_TRIGGER] > 0.5f) || c.depthDown;
        c.pause = padEdges_.pressed(4, btn(GLFW_GAMEPAD_BUTTON_START)) || c.pause;
        c.restart = padEdges_.pressed(5, btn(GLFW_GAMEPAD_BUTTON_BACK)) || c.restart;
        break;
    }
    return c;
}

void InputReader::send(const Controls& c, double dt, const std::function<void(std::size_t, const char*)>& send) {
    for (std::size_t i = 0; i < holds_.size(); ++i) {
        const bool fresh = holdEdges_.pressed(i, c.down[i]);
        double& held = heldFor_[i];
        if (!c.down[i]) {
            held = 0;
            continue;
        }
        held += dt;
        if (fresh || (holds_[i].repeats && held >= repeat_)) {
            if (!fresh) held = 0;
            send(i, c.from[i]);
        }
    }
}

// ---- PosedCast -----------------------------------------------------------------------------

void PosedCast::reset(const sim::Scene& scene, const sim::ActionLibrary& lib, int characters) {
    poser_ = std::make_unique<sim::ScenePoser>(scene, lib);
    const auto n = static_cast<std::size_t>(characters);
    tints_.clear();
    for (int c = 0; c < characters; ++c) tints_.push_back(cli::characterTint(scene, c));
    poses_.assign(n, {});
    positions_.assign(n, {});
    rotations_.assign(n, {});
    labels_.assign(n, {});
    shown_.clear();
}

void PosedCast::pose(double t, const std::function<std::string(int)>& label) {
    shown_.clear();
    for (std::size_t k = 0; k < poses_.size(); ++k) {
        const int c = static_cast<int>(k);
        poser_->pose(c, t, poses_[k]);
        positions_[k].resize(poses_[k].translations.size());
        rotations_[k].resize(poses_[k].translations.size());
        forwardKinematics(poser_->skeleton(c), poses_[k].translations, poses_[k].rotations, positions_[k], rotations_[k]);
        labels_[k] = label(c);
        // Not drawn selected: the highlight would shift its colour off its swatch; the label names it.
        shown_.push_back({&poser_->skeleton(c), positions_[k], rotations_[k], tints_[k], labels_[k], false});
    }
}

// ---- LiveCore ------------------------------------------------------------------------------

Status LiveCore::openProject(const std::string& project, bool quiet) {
    auto ss = pipeline::openSimSession(project, terminalProgress(quiet));
    if (!ss) return ss.error();
    session = std::move(*ss);
    return {};
}

Status LiveCore::frame(double dt, GLFWwindow* window, bool keyboard) {
    if (!hasGraph()) {
        if (!build.done()) {
            readInput(window, keyboard, dt);
            return {};
        }
        if (Status s = takeBuilt(); !s) return s;
        if (Status s = start(); !s) return s;
    }
    readInput(window, keyboard, dt);
    const auto t0 = Clock::now();
    if (!paused) advance(dt);
    pose();
    clock.add(std::chrono::duration<double>(Clock::now() - t0).count());
    return {};
}

bool LiveCore::timeRow(const char* label, double t) {
    ImGui::Text("%s %.1f s%s", label, t, paused ? "  (paused)" : "");
    ImGui::SameLine();
    if (ImGui::SmallButton(paused ? "Resume" : "Pause")) paused = !paused;
    ImGui::SameLine();
    if (ImGui::SmallButton("Restart")) {
        restart();
        return true;
    }
    return false;
}

nlohmann::ordered_json LiveCore::logHead(const std::string& mode, const std::string& project) const {
    nlohmann::ordered_json j;
    j["format"] = "fray-play-log";
    j["version"] = 1;
    j["mode"] = mode;
    j["project"] = project;
    j["graph"] = graphFile.string();
    return j;
}

void characterRow(int c, glm::vec3 tint, const std::string& text) {
    ImGui::PushID(c);
    ImGui::ColorButton("##tint", ImVec4(tint.x, tint.y, tint.z, 1.0f), ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
    ImGui::SameLine();
    ImGui::Text("%s", text.c_str());
    ImGui::PopID();
}

}  // namespace fray::player
