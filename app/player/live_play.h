#pragma once
// What fray-play's live modes (the duel and team fight, duel.h; the two
// carriers, carry_play.h) share: the graph file at its place, read or built
// in the background with progress; the keyboard and gamepad; a script of
// timed events; the fixed-step clock; the characters posed for drawing; and
// one frame of play. Each mode's Impl derives from LiveCore and says what is
// its own (its graph, its match or run, its controls' meaning).
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/pipeline/sim_session.h"
#include "fray/render/frame.h"
#include "fray/sim/scene.h"
#include "play_mode.h"

struct GLFWwindow;

namespace fray::player {

// Which file sits at a graph's place, by its first 8 bytes (igraph::kGraphMagic,
// igraph::kCarryGraphMagic); Other: anything else, or unreadable.
enum class GraphAtPlace { Missing, Duel, Carry, Other };
GraphAtPlace graphAtPlace(const std::filesystem::path& file);

// Progress on a terminal only (stderr, every 10 %): a scripted run's output
// stays its result and errors. None when quiet.
ProgressFn terminalProgress(bool quiet);

// Building a graph (and its first policies): on a worker thread, with its
// progress, stage and notes for the panel, or before returning (scripted runs).
class GraphBuild {
public:
    GraphBuild() = default;
    GraphBuild(const GraphBuild&) = delete;
    GraphBuild& operator=(const GraphBuild&) = delete;
    ~GraphBuild() { stop(); }

    std::atomic<bool> cancel{false};
    // Records the fraction and stage for the panel; false once cancelled.
    ProgressFn progress();
    void stage(std::string s);
    void note(std::string n);
    // Says the notes so far on stderr ("fray-play: NOTE", unless quiet), then
    // runs `work` here (foreground) or on the worker; `work` returns its error
    // ("": none).
    void start(bool foreground, bool quiet, std::function<std::string()> work);
    bool done() const { return done_.load(); }
    // Waits for the worker; the work's error.
    Status finish();
    // Cancels and waits: before what the work uses goes away.
    void stop();
    // The panel while it builds: "Building WHAT (stage)", a bar, the notes.
    void panel(const char* what);

private:
    std::thread worker_;
    std::atomic<bool> done_{false};
    std::mutex mutex_;
    double fraction_ = 0;
    std::string stage_ = "starting";
    std::string error_;
    std::vector<std::string> notes_;
};

// A control held down: two keys (GLFW_KEY_UNKNOWN: only one) or a gamepad
// input; `repeats`: held down, it is sent again every InputReader::repeat s.
enum class Pad { Up, Down, Left, Right, A, B, X, Y };
struct Hold {
    int key = 0, otherKey = 0;
    Pad pad = Pad::A;
    bool repeats = false;
};
inline constexpr std::size_t kMaxHolds = 8, kMaxKeys = 4;

// One frame of the keyboard and the first gamepad with a mapping.
struct Controls {
    std::array<bool, kMaxHolds> down{};          // each Hold: held now
    std::array<const char*, kMaxHolds> from{};   // by "keyboard" or "gamepad"
    std::array<bool, kMaxKeys> keys{};           // the mode's own keys, pressed this frame
    bool next = false, prev = false;             // the gamepad's right and left bumpers
    bool depthUp = false, depthDown = false;     // +/- keys, right and left triggers
    bool pause = false, restart = false;         // P, R; Start, Back
};

class InputReader {
public:
    InputReader(std::vector<Hold> holds, std::vector<int> keys, double repeat);
    // The keyboard when `keyboard` (the UI does not want it) and a window; the gamepad.
    Controls read(GLFWwindow* window, bool keyboard);
    // Calls send(i, from) for each Hold pressed this frame or, when it
    // repeats, held down for `repeat` s since it was last sent.
    void send(const Controls& c, double dt, const std::function<void(std::size_t, const char*)>& send);
    const std::string& gamepad() const { return gamepad_; }

private:
    // Edge detection: true on the frame a key or button goes down.
    struct Edges {
        std::array<bool, 16> was{};
        bool pressed(std::size_t slot, bool down) {
            const bool p = down && !was[slot];
            was[slot] = down;
            return p;
        }
    };
    std::vector<Hold> holds_;
    std::vector<int> keys_;
    double repeat_;
    Edges keyEdges_, padEdges_, holdEdges_;
    std::array<double, kMaxHolds> heldFor_{};
    std::string gamepad_;
};

// A script's events (each with a time), handed out as play time reaches them.
template <class Event>
struct TimedEvents {
    std::vector<Event> events;
    std::size_t next = 0;
    template <class Apply>
    void due(double now, Apply&& apply) {
        while (next < events.size() && events[next].time <= now + 1e-9) apply(events[next++]);
    }
};

// Play time in fixed steps: what a frame's dt adds up to, at most 0.25 s a
// frame (a stalled frame does not fast-forward the play).
class FixedSteps {
public:
    static constexpr double kStep = 1.0 / 60.0;  // MatchOptions::step
    int take(double dt) {
        carry_ += std::min(dt, 0.25);
        const auto steps = static_cast<int>(std::floor((carry_ + 1e-9) / kStep));
        carry_ -= steps * kStep;
        return steps;
    }
    void reset() { carry_ = 0; }

private:
    double carry_ = 0;  // s not yet stepped
};

// A scene's characters posed for drawing, with their tints and labels.
class PosedCast {
public:
    void reset(const sim::Scene& scene, const sim::ActionLibrary& lib, int characters);
    // Poses every character at t with label(c) above its head.
    void pose(double t, const std::function<std::string(int)>& label);
    std::span<const render::CharacterInstance> shown() const { return shown_; }
    const std::vector<glm::vec3>& tints() const { return tints_; }

private:
    std::unique_ptr<sim::ScenePoser> poser_;
    std::vector<glm::vec3> tints_;
    std::vector<Pose> poses_;
    std::vector<std::vector<glm::vec3>> positions_;
    std::vector<std::vector<glm::quat>> rotations_;
    std::vector<std::string> labels_;
    std::vector<render::CharacterInstance> shown_;
};

// What a live mode's Impl shares; PlayMode::update is frame().
struct LiveCore {
    explicit LiveCore(InputReader reader) : input(std::move(reader)) {}
    virtual ~LiveCore() = default;

    std::filesystem::path graphFile;
    std::unique_ptr<pipeline::SimSession> session;
    GraphBuild build;
    PosedCast cast;
    FollowCentre follow;
    FixedSteps steps;
    InputReader input;
    UpdateClock clock;
    bool paused = false;
    int restarts = 0;

    const sim::ActionLibrary& lib() const { return session->library; }
    // Opens the project (progress on a terminal).
    Status openProject(const std::string& project, bool quiet);
    // One frame: the input, then (once the graph is there) dt s of play and the poses.
    Status frame(double dt, GLFWwindow* window, bool keyboard);
    // The panel's first row: "LABEL T s", Pause/Resume and Restart (true when restarted).
    bool timeRow(const char* label, double t);
    void restart() {
        ++restarts;
        (void)start();
    }
    // The log's first fields: format, version, mode, project, graph.
    nlohmann::ordered_json logHead(const std::string& mode, const std::string& project) const;

    virtual bool hasGraph() const = 0;
    // Takes the graph the worker built (errors: the build's).
    virtual Status takeBuilt() = 0;
    // A new match or run on the graph.
    virtual Status start() = 0;
    virtual void readInput(GLFWwindow* window, bool keyboard, double dt) = 0;
    virtual void advance(double dt) = 0;
    virtual void pose() = 0;
};

// A row of the panel's character list: the tint's swatch, then text.
void characterRow(int c, glm::vec3 tint, const std::string& text);

}  // namespace fray::player
