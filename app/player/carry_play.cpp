#include "carry_play.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <numbers>
#include <optional>
#include <thread>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/core/kinematics.h"
#include "fray/igraph/carry.h"
#include "fray/pipeline/sim_session.h"
#include "fray/sim/geometry.h"
#include "fray/sim/scene.h"
#include "scene_stage.h"
#include "script_lines.h"

namespace fray::player {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;
constexpr int kMaxDepth = 10;
constexpr double kRepeat = 0.5;  // a turn key held down turns again this often (s)
using Kind = CarryEvent::Kind;

const char* kindName(Kind k) {
    switch (k) {
        case Kind::Forward: return "forward";
        case Kind::Back: return "back";
        case Kind::Stop: return "stop";
        case Kind::TurnLeft: return "turn-left";
        case Kind::TurnRight: return "turn-right";
        case Kind::Heading: return "heading";
        case Kind::Set: return "set";
        case Kind::Depth: return "depth";
    }
    return "?";
}

// Which file sits at the graph's place.
enum class FileKind { Missing, Carry, Duel, Other };
FileKind fileKind(const fs::path& file) {
    std::error_code ec;
    if (!fs::exists(file, ec)) return FileKind::Missing;
    auto head = readWholeFile(file, "the carry graph");
    if (!head || head->size() < 8) return FileKind::Other;
    const std::string_view h(head->data(), 8);
    if (h == igraph::kCarryGraphMagic) return FileKind::Carry;
    if (h == "FRAYIGPH") return FileKind::Duel;
    return FileKind::Other;
}

// The policy direction k in words: k * 45 degrees left of carrier A's forward.
std::string directionName(int k) {
    static const char* kNames[] = {"ahead", "45 deg left", "left", "135 deg left", "behind", "135 deg right", "right", "45 deg right"};
    return k < 0 || k > 7 ? std::string("holding") : std::to_string(k) + " (" + kNames[k] + " of A)";
}

struct Edges {
    std::array<bool, 32> was{};
    bool pressed(int slot, bool down) {
        const bool p = down && !was[static_cast<std::size_t>(slot)];
        was[static_cast<std::size_t>(slot)] = down;
        return p;
    }
};

}  // namespace

Result<std::vector<CarryEvent>> parseCarryScript(std::string_view text, std::string_view fileName) {
    std::vector<CarryEvent> out;
    const Status read = forEachScriptLine(text, fileName, "expected SECONDS COMMAND", [&](const ScriptLine& l) -> Status {
        const auto& w = l.words;
        const std::string& where = l.where;
        CarryEvent e;
        e.line = l.number;
        e.time = l.time;
        const std::string_view c = w[1];
        const std::size_t want = c == "heading" || c == "set" || c == "depth" ? 3 : 2;
        if (c == "forward") e.kind = Kind::Forward;
        else if (c == "back") e.kind = Kind::Back;
        else if (c == "stop") e.kind = Kind::Stop;
        else if (c == "turn-left") e.kind = Kind::TurnLeft;
        else if (c == "turn-right") e.kind = Kind::TurnRight;
        else if (c == "heading") e.kind = Kind::Heading;
        else if (c == "set") e.kind = Kind::Set;
        else if (c == "depth") e.kind = Kind::Depth;
        else
            return makeError(where + "'" + std::string(c) +
                             "' is not a carry command (forward, back, stop, turn-left, turn-right, heading DEGREES, set NAME=VALUE, depth D)");
        if (w.size() != want) return makeError(where + "'" + std::string(c) + "' takes " + (want == 2 ? "no argument" : "one argument"));
        if (e.kind == Kind::Heading && (!scriptNumber(w[2], e.degrees) || !std::isfinite(e.degrees)))
            return makeError(where + "heading '" + std::string(w[2]) + "' is not a number of degrees");
        if (e.kind == Kind::Depth) {
            double d = 0;
            if (!scriptNumber(w[2], d) || d != std::floor(d) || d < 1 || d > kMaxDepth)
                return makeError(where + "depth '" + std::string(w[2]) + "' is not a whole number from 1 to " + std::to_string(kMaxDepth));
            e.depth = static_cast<int>(d);
        }
        if (e.kind == Kind::Set) {
            e.edit = std::string(w[2]);
            igraph::CarryWeights probe;
            if (auto st = igraph::applyCarryEdit(probe, e.edit); !st) return makeError(where + st.error().message);
        }
        out.push_back(std::move(e));
        return {};
    });
    if (!read) return read.error();
    std::stable_sort(out.begin(), out.end(), [](const CarryEvent& a, const CarryEvent& b) { return a.time < b.time; });
    return out;
}

struct CarryPlay::Impl {
    CarryPlayOptions opt;
    fs::path graphFile;
    std::unique_ptr<pipeline::SimSession> session;
    std::optional<igraph::CarryPath> path;
    std::shared_ptr<const igraph::CarryGraph> graph;
    std::shared_ptr<const igraph::CarryPolicySet> applied;  // the policies in play
    std::unique_ptr<igraph::CarryPolicyService> service;
    std::vector<CarryEvent> script;
    std::size_t nextEvent = 0;
    double graphReadSeconds = -1, graphBuildSeconds = -1;

    // Building the graph in the background.
    std::thread builder;
    std::atomic<bool> cancel{false}, built{false};
    std::mutex progressMutex;
    double fraction = 0;
    std::string stage = "starting";
    std::string buildError;
    std::vector<std::string> notes;
    std::unique_ptr<igraph::CarryGraph> builtGraph;
    std::shared_ptr<const igraph::CarryPolicySet> builtPolicies;

    // The run.
    std::unique_ptr<igraph::CarryDriver> driver;
    std::unique_ptr<sim::ScenePoser> poser;
    std::vector<glm::vec3> tints;
    std::vector<Pose> poses;
    std::vector<std::vector<glm::vec3>> positions;
    std::vector<std::vector<glm::quat>> rotations;
    std::vector<std::string> labels;
    std::vector<render::CharacterInstance> shown;
    std::vector<glm::vec3> pathPoints, arrowPoints;
    std::vector<render::Polyline> lines;
    FollowCentre follow;
    double carry = 0;
    bool paused = false;
    int restarts = 0;
    UpdateClock clock;

    // What the user asked for (the policies in play may be older).
    igraph::CarryWeights weights;
    int depth = 3;
    struct PolicyRecord {
        double time, seconds;
        igraph::CarryWeights weights;
        int depth;
    };
    std::vector<PolicyRecord> policies;
    struct LoggedEvent {
        double time;
        std::string source, what, value;
    };
    std::vector<LoggedEvent> events;
    struct Decision {
        double time;
        int direction;
        double heading, desired;
        bool moving, offGraph;
        glm::vec2 box;
        std::string actionA, actionB;
    };
    std::vector<Decision> decisions;
    std::string lastNote;

    Edges edges;
    std::array<double, 5> heldFor{};
    std::string gamepadName;

    const sim::ActionLibrary& lib() const { return session->library; }

    Status acquireGraph() {
        graphFile = opt.graph.empty() ? fs::path(opt.project + ".carry.igraph") : fs::path(opt.graph);
        const auto kind = fileKind(graphFile);
        if (kind == FileKind::Duel)
            return makeError(graphFile.string() + ": a duel's interaction graph, not a carry graph: not overwriting it (name another file with --graph)");
        if (kind == FileKind::Other)
            return makeError(graphFile.string() + ": exists and is not a carry graph file: not overwriting it (name another file with --graph)");
        if (kind == FileKind::Carry) {
            const auto t0 = Clock::now();
            auto g = igraph::loadCarryGraph(graphFile, lib());
            if (g) {
                graphReadSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
                graph = std::make_shared<const igraph::CarryGraph>(std::move(*g));
                auto p = igraph::computeCarryPolicies(*graph, weights, depth, cancelWhen(cancel));
                if (!p) return p.error();
                applied = std::make_shared<const igraph::CarryPolicySet>(std::move(*p));
                return {};
            }
            notes.push_back(g.error().message + "; building it again");
        } else {
            notes.push_back(graphFile.string() + ": no carry graph yet; building it (" + std::to_string(opt.graphStates) + " states at most)");
        }
        for (const auto& n : notes)
            if (!opt.quiet) std::fprintf(stderr, "fray-play: %s\n", n.c_str());
        if (opt.foreground) {
            build();
            if (!buildError.empty()) return makeError(buildError);
            return takeBuilt();
        }
        builder = std::thread([this] { build(); });
        return {};
    }

    void build() {
        igraph::CarryOptions co;
        co.seed = opt.seed;
        co.maxSamples = opt.graphStates;
        const ProgressFn progress = [this](double f, std::string_view s) {
            {
                std::lock_guard lock(progressMutex);
                fraction = f;
                stage = std::string(s);
            }
            return !cancel.load();
        };
        auto g = igraph::buildCarryGraph(lib(), co, progress);
        std::string error;
        if (!g) {
            error = opt.project + ": " + g.error().message;
        } else {
            {
                std::lock_guard lock(progressMutex);
                if (Status s = igraph::saveCarryGraph(*g, graphFile); !s)
                    notes.push_back("the carry graph could not be kept: " + s.error().message);
                else
                    notes.push_back("built " + std::to_string(g->states.size()) + " states, " + std::to_string(g->edges.size()) + " edges; kept in " +
                                    graphFile.string());
                stage = "policies";
            }
            auto p = igraph::computeCarryPolicies(*g, weights, depth, progress);
            if (!p) error = p.error().message;
            else builtPolicies = std::make_shared<const igraph::CarryPolicySet>(std::move(*p));
            graphBuildSeconds = g->seconds;
            builtGraph = std::make_unique<igraph::CarryGraph>(std::move(*g));
        }
        std::lock_guard lock(progressMutex);
        buildError = error;
        built = true;
    }

    Status takeBuilt() {
        if (builder.joinable()) builder.join();
        if (!buildError.empty()) return makeError(buildError);
        graph = std::shared_ptr<const igraph::CarryGraph>(std::move(builtGraph));
        applied = builtPolicies;
        return {};
    }

    Status startRun() {
        if (!service) service = std::make_unique<igraph::CarryPolicyService>(graph, applied);
        auto d = igraph::CarryDriver::make(lib(), graph, applied, path);
        if (!d) return d.error();
        driver = std::move(*d);
        poser = std::make_unique<sim::ScenePoser>(driver->scene(), lib());
        const int n = static_cast<int>(driver->scene().characters.size());
        tints.clear();
        for (int c = 0; c < n; ++c) tints.push_back(cli::characterTint(driver->scene(), c));
        poses.assign(static_cast<std::size_t>(n), {});
        positions.assign(static_cast<std::size_t>(n), {});
        rotations.assign(static_cast<std::size_t>(n), {});
        labels.assign(static_cast<std::size_t>(n), {});
        pathPoints.clear();
        if (path) {
            for (const auto& p : path->points) pathPoints.emplace_back(p.x, 0.01f, p.y);
            if (path->loop) pathPoints.push_back(pathPoints.front());
        }
        nextEvent = 0;
        carry = 0;
        follow.reset();
        decisions.clear();
        policies.push_back({0.0, applied->seconds, applied->weights, applied->depth});
        if (applied->depth != depth || !sameWeights(applied->weights, weights)) (void)service->request(weights, depth);
        noteDecision();
        pose();
        return {};
    }

    static bool sameWeights(const igraph::CarryWeights& a, const igraph::CarryWeights& b) {
        return a.wTheta == b.wTheta && a.wD == b.wD && a.wV == b.wV && a.speed == b.speed && a.gamma == b.gamma;
    }

    double now() const { return driver ? driver->time() : 0.0; }

    void requestPolicy(const igraph::CarryWeights& w, int d, const std::string& source, const std::string& what, const std::string& value) {
        d = std::clamp(d, 1, kMaxDepth);
        if (auto st = igraph::validate(w); !st) {
            lastNote = st.error().message;
            return;
        }
        events.push_back({now(), source, what, value});
        weights = w;
        depth = d;
        if (service) (void)service->request(weights, depth);
    }

    void edit(const std::string& e, const std::string& source) {
        igraph::CarryWeights w = weights;
        if (auto st = igraph::applyCarryEdit(w, e); !st) {
            lastNote = st.error().message;
            return;
        }
        requestPolicy(w, depth, source, "set", e);
    }

    void command(Kind k, double degrees, const std::string& source) {
        if (!driver) return;
        double a = driver->desiredAngle();
        bool go = driver->moving();
        switch (k) {
            case Kind::Forward: go = true; break;
            case Kind::Back: a += kPi, go = true; break;
            case Kind::Stop: go = false; break;
            case Kind::TurnLeft: a += kPi / 4; break;
            case Kind::TurnRight: a -= kPi / 4; break;
            case Kind::Heading: a = degrees * kPi / 180.0; break;
            default: return;
        }
        driver->steer(a, go);
        char value[64];
        std::snprintf(value, sizeof value, "%.1f", degrees);
        events.push_back({now(), source, k == Kind::Heading ? "heading" : "command", k == Kind::Heading ? value : kindName(k)});
    }

    void swapPolicies() {
        if (!service || !driver) return;
        auto p = service->current();
        if (p == applied) return;
        if (!driver->setPolicies(p)) return;
        applied = p;
        policies.push_back({driver->time(), p->seconds, p->weights, p->depth});
    }

    void applyScript() {
        while (nextEvent < script.size() && script[nextEvent].time <= driver->time() + 1e-9) {
            const auto& e = script[nextEvent++];
            switch (e.kind) {
                case Kind::Set: edit(e.edit, "script"); break;
                case Kind::Depth: requestPolicy(weights, e.depth, "script", "depth", std::to_string(e.depth)); break;
                default: command(e.kind, e.degrees, "script"); break;
            }
        }
    }

    void noteDecision() {
        const auto& track = driver->scene().characters[0].track;
        if (!decisions.empty() && decisions.size() >= track.size()) return;
        const auto& n = driver->now();
        const auto& b = driver->scene().characters[1].track.back();
        decisions.push_back({track.back().start, n.direction, n.heading, driver->desiredAngle(), driver->moving(), n.offGraph, n.boxMiddle,
                             lib().action(track.back().action).name, lib().action(b.action).name});
    }

    void advance(double dt) {
        constexpr double kStep = 1.0 / 60.0;
        carry += std::min(dt, 0.25);
        auto steps = static_cast<int>(std::floor((carry + 1e-9) / kStep));
        carry -= steps * kStep;
        while (steps-- > 0 && driver->time() < sim::kMaxSceneSeconds - 1) {
            swapPolicies();
            applyScript();
            driver->advance(kStep);
            noteDecision();
        }
        swapPolicies();
    }

    void readInput(GLFWwindow* window, bool keyboard, double dt) {
        // 0 forward, 1 back, 2 turn left, 3 turn right, 4 stop
        std::array<bool, 5> down{};
        std::array<const char*, 5> from{};
        bool wUp = false, wDown = false, dUp = false, dDown = false, pause = false, restart = false;
        if (keyboard && window) {
            auto key = [&](int k) { return glfwGetKey(window, k) == GLFW_PRESS; };
            const int keys[5][2] = {{GLFW_KEY_W, GLFW_KEY_UP}, {GLFW_KEY_S, GLFW_KEY_DOWN}, {GLFW_KEY_A, GLFW_KEY_LEFT}, {GLFW_KEY_D, GLFW_KEY_RIGHT},
                                    {GLFW_KEY_H, GLFW_KEY_SPACE}};
            for (int i = 0; i < 5; ++i)
                if (key(keys[i][0]) || key(keys[i][1])) down[static_cast<std::size_t>(i)] = true, from[static_cast<std::size_t>(i)] = "keyboard";
            wUp = edges.pressed(10, key(GLFW_KEY_RIGHT_BRACKET));
            wDown = edges.pressed(11, key(GLFW_KEY_LEFT_BRACKET));
            dUp = edges.pressed(12, key(GLFW_KEY_EQUAL) || key(GLFW_KEY_KP_ADD));
            dDown = edges.pressed(13, key(GLFW_KEY_MINUS) || key(GLFW_KEY_KP_SUBTRACT));
            pause = edges.pressed(14, key(GLFW_KEY_P));
            restart = edges.pressed(15, key(GLFW_KEY_R));
        }
        gamepadName.clear();
        for (int j = GLFW_JOYSTICK_1; j <= GLFW_JOYSTICK_LAST; ++j) {
            GLFWgamepadstate gp;
            if (!glfwJoystickIsGamepad(j) || !glfwGetGamepadState(j, &gp)) continue;
            const char* name = glfwGetGamepadName(j);
            gamepadName = name ? name : "gamepad";
            const float x = gp.axes[GLFW_GAMEPAD_AXIS_LEFT_X], y = gp.axes[GLFW_GAMEPAD_AXIS_LEFT_Y];
            auto btn = [&](int b) { return gp.buttons[b] == GLFW_PRESS; };
            auto set = [&](int i, bool on) {
                if (on && !from[static_cast<std::size_t>(i)]) down[static_cast<std::size_t>(i)] = true, from[static_cast<std::size_t>(i)] = "gamepad";
            };
            set(0, y < -0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_UP));
            set(1, y > 0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_DOWN));
            set(2, x < -0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_LEFT));
            set(3, x > 0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_RIGHT));
            set(4, btn(GLFW_GAMEPAD_BUTTON_A));
            wUp = edges.pressed(20, btn(GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER)) || wUp;
            wDown = edges.pressed(21, btn(GLFW_GAMEPAD_BUTTON_LEFT_BUMPER)) || wDown;
            dUp = edges.pressed(22, gp.axes[GLFW_GAMEPAD_AXIS_RIGHT_TRIGGER] > 0.5f) || dUp;
            dDown = edges.pressed(23, gp.axes[GLFW_GAMEPAD_AXIS_LEFT_TRIGGER] > 0.5f) || dDown;
            pause = edges.pressed(24, btn(GLFW_GAMEPAD_BUTTON_START)) || pause;
            restart = edges.pressed(25, btn(GLFW_GAMEPAD_BUTTON_BACK)) || restart;
            break;
        }
        if (!driver) return;
        const Kind kinds[5] = {Kind::Forward, Kind::Back, Kind::TurnLeft, Kind::TurnRight, Kind::Stop};
        for (int i = 0; i < 5; ++i) {
            const auto k = static_cast<std::size_t>(i);
            const bool fresh = edges.pressed(i, down[k]);
            if (!down[k]) {
                heldFor[k] = 0;
                continue;
            }
            heldFor[k] += dt;
            const bool turn = i == 2 || i == 3;
            if (fresh || (turn && heldFor[k] >= kRepeat)) {
                if (!fresh) heldFor[k] = 0;
                command(kinds[i], 0, from[k]);
            }
        }
        if (wUp || wDown) {
            igraph::CarryWeights w = weights;
            w.wV = std::max(0.0, w.wV + (wUp ? 2.0 : -2.0));
            char v[64];
            std::snprintf(v, sizeof v, "w_v=%g", w.wV);
            requestPolicy(w, depth, "input", "set", v);
        }
        if (dUp) requestPolicy(weights, depth + 1, "input", "depth", std::to_string(std::min(depth + 1, kMaxDepth)));
        if (dDown) requestPolicy(weights, depth - 1, "input", "depth", std::to_string(std::max(depth - 1, 1)));
        if (pause) paused = !paused;
        if (restart) {
            ++restarts;
            (void)startRun();
        }
    }

    void pose() {
        const double t = driver->time();
        const auto& scene = driver->scene();
        shown.clear();
        const int n = static_cast<int>(scene.characters.size());
        for (int c = 0; c < n; ++c) {
            const auto k = static_cast<std::size_t>(c);
            poser->pose(c, t, poses[k]);
            positions[k].resize(poses[k].translations.size());
            rotations[k].resize(poses[k].translations.size());
            forwardKinematics(poser->skeleton(c), poses[k].translations, poses[k].rotations, positions[k], rotations[k]);
            labels[k].clear();
            const int i = scene.instanceAt(c, t);
            if (c < 2 && i >= 0) labels[k] = scene.characters[k].name + ": " + lib().action(scene.characters[k].track[static_cast<std::size_t>(i)].action).label();
            shown.push_back({&poser->skeleton(c), positions[k], rotations[k], tints[k], labels[k], false});
        }
        // The desired direction (steered): an arrow from the box's middle.
        arrowPoints.clear();
        const glm::vec2 m = driver->now().boxMiddle;
        if (!driver->followsPath()) {
            const double a = driver->desiredAngle();
            const glm::vec2 d(static_cast<float>(std::sin(a)), static_cast<float>(std::cos(a)));
            const glm::vec2 side(d.y, -d.x);
            const glm::vec2 tip = m + 1.2f * d;
            for (const glm::vec2 p : {m, tip, tip - 0.25f * d + 0.15f * side, tip, tip - 0.25f * d - 0.15f * side})
                arrowPoints.emplace_back(p.x, 0.02f, p.y);
        }
        lines.clear();
        if (!pathPoints.empty()) lines.push_back({pathPoints, glm::vec4(0.97f, 0.97f, 0.97f, 0.9f), 0.08f});
        if (!arrowPoints.empty())
            lines.push_back({arrowPoints, driver->moving() ? glm::vec4(1.0f, 0.62f, 0.1f, 0.95f) : glm::vec4(0.6f, 0.6f, 0.6f, 0.8f), 0.07f});
        follow.to(render::characterBounds(shown));
    }
};

CarryPlay::CarryPlay() : impl_(std::make_unique<Impl>()) {}

CarryPlay::~CarryPlay() {
    impl_->cancel = true;
    if (impl_->builder.joinable()) impl_->builder.join();
}

Result<std::unique_ptr<CarryPlay>> CarryPlay::open(const CarryPlayOptions& options) {
    std::unique_ptr<CarryPlay> p(new CarryPlay());
    Impl& m = *p->impl_;
    m.opt = options;
    if (options.depth < 1 || options.depth > kMaxDepth)
        return makeError("--depth: " + std::to_string(options.depth) + " is not from 1 to " + std::to_string(kMaxDepth));
    if (options.graphStates < 100) return makeError("--graph-states: at least 100");
    m.depth = options.depth;
    if (!options.path.empty()) {
        Result<igraph::CarryPath> path = makeError("");
        if (options.path.rfind("circle:", 0) == 0) {
            path = igraph::parseCarryPath(options.path);
        } else {
            auto text = readWholeFile(options.path, "the path file");
            if (!text) return text.error();
            path = igraph::carryPathFromJson(*text, options.path);
        }
        if (!path) return makeError("--path: " + path.error().message);
        m.path = std::move(*path);
    }
    if (!options.input.empty()) {
        auto text = readWholeFile(options.input, "the command file");
        if (!text) return text.error();
        auto s = parseCarryScript(*text, options.input);
        if (!s) return s.error();
        m.script = std::move(*s);
    }
    const ProgressFn progress = options.quiet || !isatty(2) ? ProgressFn{} : ProgressFn([last = -1](double f, std::string_view stage) mutable {
        const int pct = static_cast<int>(f * 100);
        if (pct / 10 != last / 10) std::fprintf(stderr, "fray-play: %.*s %d%%\n", static_cast<int>(stage.size()), stage.data(), pct), last = pct;
        return true;
    });
    auto ss = pipeline::openSimSession(options.project, progress);
    if (!ss) return ss.error();
    m.session = std::move(*ss);
    // No carry-end actions: said before any graph file is touched.
    const igraph::CarryOptions co;
    bool any = false;
    for (int a = 0; a < m.lib().size() && !any; ++a) any = m.lib().action(a).name.rfind(co.prefix, 0) == 0;
    if (!any) {
        return makeError(options.project + ": Interaction Graph (carrying): the project has no carry-end actions (names starting with '" + co.prefix +
                         "', e.g. the demo actor's carry set: fray-cli demo-library DIR --set carry)");
    }
    if (Status st = m.acquireGraph(); !st) return st.error();
    if (m.graph) {
        if (Status st = m.startRun(); !st) return st.error();
    }
    return p;
}

Status CarryPlay::update(double dt, GLFWwindow* window, bool keyboard) {
    Impl& m = *impl_;
    if (!m.graph) {
        if (!m.built) {
            m.readInput(window, keyboard, dt);
            return {};
        }
        if (Status s = m.takeBuilt(); !s) return s;
        if (Status s = m.startRun(); !s) return s;
    }
    m.readInput(window, keyboard, dt);
    const auto t0 = Clock::now();
    if (!m.paused) m.advance(dt);
    m.pose();
    m.clock.add(std::chrono::duration<double>(Clock::now() - t0).count());
    return {};
}

std::span<const render::CharacterInstance> CarryPlay::shown() const { return impl_->shown; }
std::span<const render::Polyline> CarryPlay::lines() const { return impl_->lines; }
render::Bounds CarryPlay::framing() const {
    render::Bounds b = render::characterBounds(impl_->shown);
    if (b.empty()) b = framingPlaceholder();
    b.add(b.min - glm::vec3(1.0f, 0.0f, 1.0f));  // room to walk into
    b.add(b.max + glm::vec3(1.0f, 0.0f, 1.0f));
    return b;
}
glm::vec3 CarryPlay::moved() const { return impl_->follow.moved(); }
const char* CarryPlay::frameButton() const { return "Frame the carriers"; }
std::string CarryPlay::summary() const {
    char line[160];
    std::snprintf(line, sizeof line, "carrying at %.3f s; steps and posing %.2f ms a frame (worst %.2f ms)", time(),
                  1e3 * impl_->clock.mean(), 1e3 * impl_->clock.worst());
    return line;
}
bool CarryPlay::ready() const { return impl_->driver != nullptr; }
double CarryPlay::time() const { return impl_->now(); }

void CarryPlay::overlay() {
    Impl& m = *impl_;
    ImGui::Text("Two carriers, one box (Interaction Graph)");
    if (!m.driver) {
        std::lock_guard lock(m.progressMutex);
        ImGui::TextWrapped("Building the carry graph (%s)", m.stage.c_str());
        ImGui::ProgressBar(static_cast<float>(m.fraction), ImVec2(-1, 0));
        for (const auto& n : m.notes) ImGui::TextWrapped("%s", n.c_str());
        return;
    }
    const auto& d = *m.driver;
    const auto& now = d.now();
    const auto& st = d.stats();
    ImGui::Text("time %.1f s%s", d.time(), m.paused ? "  (paused)" : "");
    ImGui::SameLine();
    if (ImGui::SmallButton(m.paused ? "Resume" : "Pause")) m.paused = !m.paused;
    ImGui::SameLine();
    if (ImGui::SmallButton("Restart")) {
        ++m.restarts;
        (void)m.startRun();
        return;
    }
    ImGui::Separator();
    if (d.followsPath()) {
        ImGui::Text("following the path %s", m.opt.path.c_str());
        ImGui::SetWindowFontScale(1.4f);
        ImGui::Text("path error %.3f m", now.pathError);
        ImGui::SetWindowFontScale(1.0f);
        ImGui::Text("mean %.3f m, max %.3f m", st.pathErrorMean, st.pathErrorMax);
    } else {
        ImGui::Text("steered: heading %.0f deg, %s", std::remainder(d.desiredAngle() * 180.0 / kPi, 360.0), d.moving() ? "moving" : "holding");
        ImGui::Text("path error: none (steered; or --path)");
    }
    const double L = d.boxLength();
    const double off = 100.0 * (now.gripDistance - L) / L;
    const ImVec4 handColour = std::abs(off) <= 5.0 ? ImVec4(0.45f, 0.9f, 0.45f, 1) : ImVec4(1.0f, 0.45f, 0.4f, 1);
    ImGui::SetWindowFontScale(1.4f);
    ImGui::TextColored(handColour, "hands %.3f m (%+.1f %%)", now.gripDistance, off);
    ImGui::SetWindowFontScale(1.0f);
    ImGui::Text("apart, box %.2f m; worst so far %.2f %%", L, 100.0 * st.gripErrorMax);
    ImGui::Text("direction policy: %s", directionName(now.direction).c_str());
    ImGui::Text("decisions %lld, off the graph %lld", static_cast<long long>(st.decisions), static_cast<long long>(st.offGraph));
    ImGui::Separator();
    ImGui::Text("Collaborative reward (8 direction policies)");
    float wv = static_cast<float>(m.weights.wV), wd = static_cast<float>(m.weights.wD), sp = static_cast<float>(m.weights.speed);
    igraph::CarryWeights w = m.weights;
    char v[64];
    if (ImGui::SliderFloat("w_v", &wv, 0.0f, 40.0f, "%.1f", ImGuiSliderFlags_AlwaysClamp)) {
        w.wV = static_cast<double>(wv);
        std::snprintf(v, sizeof v, "w_v=%g", w.wV);
        m.requestPolicy(w, m.depth, "panel", "set", v);
    }
    if (ImGui::SliderFloat("w_d", &wd, 0.0f, 2000.0f, "%.0f", ImGuiSliderFlags_AlwaysClamp)) {
        w = m.weights, w.wD = static_cast<double>(wd);
        std::snprintf(v, sizeof v, "w_d=%g", w.wD);
        m.requestPolicy(w, m.depth, "panel", "set", v);
    }
    if (ImGui::SliderFloat("speed", &sp, 0.05f, 1.0f, "%.2f m/s", ImGuiSliderFlags_AlwaysClamp)) {
        w = m.weights, w.speed = static_cast<double>(sp);
        std::snprintf(v, sizeof v, "speed=%g", w.speed);
        m.requestPolicy(w, m.depth, "panel", "set", v);
    }
    int depth = m.depth;
    if (ImGui::SliderInt("depth", &depth, 1, kMaxDepth) && depth != m.depth) m.requestPolicy(m.weights, depth, "panel", "depth", std::to_string(depth));
    const auto& p = *m.applied;
    ImGui::Text("playing: depth %d, w_v %g, w_d %g,", p.depth, p.weights.wV, p.weights.wD);
    ImGui::Text("  speed %g m/s, w_theta %g, gamma %g", p.weights.speed, p.weights.wTheta, p.weights.gamma);
    if (!m.policies.empty()) {
        const auto& last = m.policies.back();
        ImGui::Text("last recompute %.1f ms, in play at %.1f s", 1e3 * last.seconds, last.time);
    }
    if (m.service && m.service->busy()) ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1), "recomputing in the background ...");
    if (!m.lastNote.empty()) ImGui::TextWrapped("%s", m.lastNote.c_str());
    ImGui::Text("graph: %zu states, %zu edges", d.graph().states.size(), d.graph().edges.size());
    if (m.graphReadSeconds >= 0) ImGui::Text("  read from its file in %.0f ms", 1e3 * m.graphReadSeconds);
    else ImGui::Text("  built here in %.1f s", m.graphBuildSeconds);
    if (!m.gamepadName.empty()) ImGui::Text("gamepad: %s", m.gamepadName.c_str());
    if (ImGui::CollapsingHeader("Controls")) {
        ImGui::TextWrapped("W/up go, S/down back (turn round and go), A/left and D/right turn the direction 45 deg, H/space stop; "
                           "[ and ] w_v -/+2, +/- depth, P pause, R restart. Gamepad: left stick or d-pad (up go, down back, "
                           "left/right turn), A stop, bumpers w_v, triggers depth, Start pause, Back restart.");
    }
    ImGui::Separator();
    ImGui::Text("Characters");
    for (int c = 0; c < static_cast<int>(d.scene().characters.size()); ++c) {
        const glm::vec3 tint = m.tints[static_cast<std::size_t>(c)];
        ImGui::PushID(c);
        ImGui::ColorButton("##tint", ImVec4(tint.x, tint.y, tint.z, 1.0f), ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
        ImGui::SameLine();
        ImGui::Text("%s", d.scene().characters[static_cast<std::size_t>(c)].name.c_str());
        ImGui::PopID();
    }
}

Status CarryPlay::writeLog() const {
    const Impl& m = *impl_;
    if (m.opt.log.empty()) return {};
    nlohmann::ordered_json j;
    j["format"] = "fray-play-log";
    j["version"] = 1;
    j["mode"] = "carry";
    j["project"] = m.opt.project;
    j["graph"] = m.graphFile.string();
    j["graph_read_seconds"] = m.graphReadSeconds >= 0 ? nlohmann::ordered_json(m.graphReadSeconds) : nlohmann::ordered_json(nullptr);
    j["graph_build_seconds"] = m.graphBuildSeconds >= 0 ? nlohmann::ordered_json(m.graphBuildSeconds) : nlohmann::ordered_json(nullptr);
    j["path"] = m.opt.path;
    j["time"] = m.now();
    j["events"] = nlohmann::ordered_json::array();
    j["policies"] = nlohmann::ordered_json::array();
    j["decisions"] = nlohmann::ordered_json::array();
    j["box"] = nlohmann::ordered_json::array();
    for (const auto& e : m.events) j["events"].push_back({{"time", e.time}, {"source", e.source}, {e.what, e.value}});
    for (const auto& p : m.policies)
        j["policies"].push_back({{"time", p.time}, {"depth", p.depth}, {"w_theta", p.weights.wTheta}, {"w_d", p.weights.wD}, {"w_v", p.weights.wV},
                                 {"speed", p.weights.speed}, {"gamma", p.weights.gamma}, {"seconds", p.seconds}});
    for (const auto& d : m.decisions)
        j["decisions"].push_back({{"time", d.time}, {"direction", d.direction}, {"heading_a", d.heading}, {"desired", d.desired}, {"moving", d.moving},
                                  {"off_graph", d.offGraph}, {"box", {d.box.x, d.box.y}}, {"carrier_a", d.actionA}, {"carrier_b", d.actionB}});
    if (m.driver) {
        const auto& keys = m.driver->scene().characters[2].keys;
        const double L = m.driver->boxLength();
        // Every 0.1 s: the box's middle (half a box length from carrier A's grip, towards B's) and its heading.
        for (std::size_t k = 0; k < keys.size(); k += 3) {
            const auto& key = keys[k];
            const double h = key.at.heading;
            j["box"].push_back({{"time", key.time}, {"x", static_cast<double>(key.at.pos.x) + 0.5 * L * std::sin(h)}, {"z", static_cast<double>(key.at.pos.y) + 0.5 * L * std::cos(h)},
                                {"heading", h}});
        }
        const auto& st = m.driver->stats();
        j["stats"] = {{"decisions", st.decisions}, {"off_graph", st.offGraph}, {"holds", st.holds}, {"grip_error_max", st.gripErrorMax},
                      {"path_error_mean", m.driver->followsPath() ? nlohmann::ordered_json(st.pathErrorMean) : nlohmann::ordered_json(nullptr)},
                      {"path_error_max", m.driver->followsPath() ? nlohmann::ordered_json(st.pathErrorMax) : nlohmann::ordered_json(nullptr)}};
    }
    return writeFileAtomically(m.opt.log, j.dump(1) + "\n");
}

}  // namespace fray::player
