#include "carry_play.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/igraph/carry.h"
#include "fray/sim/geometry.h"
#include "fray/sim/scene.h"
#include "live_play.h"
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

// The policy direction k in words: k * 45 degrees left of carrier A's forward.
std::string directionName(int k) {
    static const char* kNames[] = {"ahead", "45 deg left", "left", "135 deg left", "behind", "135 deg right", "right", "45 deg right"};
    return k < 0 || k > 7 ? std::string("holding") : std::to_string(k) + " (" + kNames[k] + " of A)";
}

// Held down: go, back, turn left, turn right (repeats), stop.
const std::vector<Hold> kHolds = {{GLFW_KEY_W, GLFW_KEY_UP, Pad::Up, false},
                                  {GLFW_KEY_S, GLFW_KEY_DOWN, Pad::Down, false},
                                  {GLFW_KEY_A, GLFW_KEY_LEFT, Pad::Left, true},
                                  {GLFW_KEY_D, GLFW_KEY_RIGHT, Pad::Right, true},
                                  {GLFW_KEY_H, GLFW_KEY_SPACE, Pad::A, false}};
constexpr Kind kHoldKinds[] = {Kind::Forward, Kind::Back, Kind::TurnLeft, Kind::TurnRight, Kind::Stop};

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

struct CarryPlay::Impl final : LiveCore {
    // ] and [: w_v up and down.
    Impl() : LiveCore(InputReader(kHolds, {GLFW_KEY_RIGHT_BRACKET, GLFW_KEY_LEFT_BRACKET}, kRepeat)) {}

    CarryPlayOptions opt;
    std::optional<igraph::CarryPath> path;
    std::shared_ptr<const igraph::CarryGraph> graph;
    std::shared_ptr<const igraph::CarryPolicySet> applied;  // the policies in play
    std::unique_ptr<igraph::CarryPolicyService> service;
    TimedEvents<CarryEvent> script;
    double graphReadSeconds = -1, graphBuildSeconds = -1;

    // What the worker built.
    std::unique_ptr<igraph::CarryGraph> builtGraph;
    std::shared_ptr<const igraph::CarryPolicySet> builtPolicies;

    // The run.
    std::unique_ptr<igraph::CarryDriver> driver;
    std::vector<glm::vec3> pathPoints, arrowPoints;
    std::vector<render::Polyline> lines;

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

    Status acquireGraph() {
        graphFile = opt.graph.empty() ? fs::path(opt.project + ".carry.igraph") : fs::path(opt.graph);
        const auto kind = graphAtPlace(graphFile);
        if (kind == GraphAtPlace::Duel)
            return makeError(graphFile.string() + ": a duel's interaction graph, not a carry graph: not overwriting it (name another file with --graph)");
        if (kind == GraphAtPlace::Other)
            return makeError(graphFile.string() + ": exists and is not a carry graph file: not overwriting it (name another file with --graph)");
        if (kind == GraphAtPlace::Carry) {
            const auto t0 = Clock::now();
            auto g = igraph::loadCarryGraph(graphFile, lib());
            if (g) {
                graphReadSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
                graph = std::make_shared<const igraph::CarryGraph>(std::move(*g));
                auto p = igraph::computeCarryPolicies(*graph, weights, depth, cancelWhen(build.cancel));
                if (!p) return p.error();
                applied = std::make_shared<const igraph::CarryPolicySet>(std::move(*p));
                return {};
            }
            build.note(g.error().message + "; building it again");
        } else {
            build.note(graphFile.string() + ": no carry graph yet; building it (" + std::to_string(opt.graphStates) + " states at most)");
        }
        build.start(opt.foreground, opt.quiet, [this] { return buildGraph(); });
        return opt.foreground ? takeBuilt() : Status{};
    }

    // The worker: build, save as the cache, the policies; returns the error ("": none).
    std::string buildGraph() {
        igraph::CarryOptions co;
        co.seed = opt.seed;
        co.maxSamples = opt.graphStates;
        const ProgressFn progress = build.progress();
        auto g = igraph::buildCarryGraph(lib(), co, progress);
        if (!g) return opt.project + ": " + g.error().message;
        if (Status s = igraph::saveCarryGraph(*g, graphFile); !s)
            build.note("the carry graph could not be kept: " + s.error().message);
        else
            build.note("built " + std::to_string(g->states.size()) + " states, " + std::to_string(g->edges.size()) + " edges; kept in " +
                       graphFile.string());
        build.stage("policies");
        std::string error;
        auto p = igraph::computeCarryPolicies(*g, weights, depth, progress);
        if (!p) error = p.error().message;
        else builtPolicies = std::make_shared<const igraph::CarryPolicySet>(std::move(*p));
        graphBuildSeconds = g->seconds;
        builtGraph = std::make_unique<igraph::CarryGraph>(std::move(*g));
        return error;
    }

    bool hasGraph() const override { return graph != nullptr; }

    Status takeBuilt() override {
        if (Status s = build.finish(); !s) return s;
        graph = std::shared_ptr<const igraph::CarryGraph>(std::move(builtGraph));
        applied = builtPolicies;
        return {};
    }

    Status start() override {
        if (!service) service = std::make_unique<igraph::CarryPolicyService>(graph, applied);
        auto d = igraph::CarryDriver::make(lib(), graph, applied, path);
        if (!d) return d.error();
        driver = std::move(*d);
        cast.reset(driver->scene(), lib(), static_cast<int>(driver->scene().characters.size()));
        pathPoints.clear();
        if (path) {
            for (const auto& p : path->points) pathPoints.emplace_back(p.x, 0.01f, p.y);
            if (path->loop) pathPoints.push_back(pathPoints.front());
        }
        script.next = 0;
        steps.reset();
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
        script.due(driver->time(), [&](const CarryEvent& e) {
            switch (e.kind) {
                case Kind::Set: edit(e.edit, "script"); break;
                case Kind::Depth: requestPolicy(weights, e.depth, "script", "depth", std::to_string(e.depth)); break;
                default: command(e.kind, e.degrees, "script"); break;
            }
        });
    }

    void noteDecision() {
        const auto& track = driver->scene().characters[0].track;
        if (!decisions.empty() && decisions.size() >= track.size()) return;
        const auto& n = driver->now();
        const auto& b = driver->scene().characters[1].track.back();
        decisions.push_back({track.back().start, n.direction, n.heading, driver->desiredAngle(), driver->moving(), n.offGraph, n.boxMiddle,
                             lib().action(track.back().action).name, lib().action(b.action).name});
    }

    void advance(double dt) override {
        for (int n = steps.take(dt); n > 0 && driver->time() < sim::kMaxSceneSeconds - 1; --n) {
            swapPolicies();
            applyScript();
            driver->advance(FixedSteps::kStep);
            noteDecision();
        }
        swapPolicies();
    }

    void readInput(GLFWwindow* window, bool keyboard, double dt) override {
        const Controls in = input.read(window, keyboard);
        if (!driver) return;
        input.send(in, dt, [&](std::size_t i, const char* from) { command(kHoldKinds[i], 0, from); });
        const bool wUp = in.keys[0] || in.next, wDown = in.keys[1] || in.prev;
        if (wUp || wDown) {
            igraph::CarryWeights w = weights;
            w.wV = std::max(0.0, w.wV + (wUp ? 2.0 : -2.0));
            char v[64];
            std::snprintf(v, sizeof v, "w_v=%g", w.wV);
            requestPolicy(w, depth, "input", "set", v);
        }
        if (in.depthUp) requestPolicy(weights, depth + 1, "input", "depth", std::to_string(std::min(depth + 1, kMaxDepth)));
        if (in.depthDown) requestPolicy(weights, depth - 1, "input", "depth", std::to_string(std::max(depth - 1, 1)));
        if (in.pause) paused = !paused;
        if (in.restart) restart();
    }

    void pose() override {
        const double t = driver->time();
        const auto& scene = driver->scene();
        cast.pose(t, [&](int c) {
            const auto k = static_cast<std::size_t>(c);
            const int i = scene.instanceAt(c, t);
            if (c < 2 && i >= 0) return scene.characters[k].name + ": " + lib().action(scene.characters[k].track[static_cast<std::size_t>(i)].action).label();
            return std::string();
        });
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
        follow.to(render::characterBounds(cast.shown()));
    }
};

CarryPlay::CarryPlay() : impl_(std::make_unique<Impl>()) {}

CarryPlay::~CarryPlay() { impl_->build.stop(); }

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
        m.script.events = std::move(*s);
    }
    if (Status st = m.openProject(options.project, options.quiet); !st) return st.error();
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
        if (Status st = m.start(); !st) return st.error();
    }
    return p;
}

Status CarryPlay::update(double dt, GLFWwindow* window, bool keyboard) { return impl_->frame(dt, window, keyboard); }

std::span<const render::CharacterInstance> CarryPlay::shown() const { return impl_->cast.shown(); }
std::span<const render::Polyline> CarryPlay::lines() const { return impl_->lines; }
render::Bounds CarryPlay::framing() const {
    render::Bounds b = render::characterBounds(impl_->cast.shown());
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
        m.build.panel("the carry graph");
        return;
    }
    const auto& d = *m.driver;
    const auto& now = d.now();
    const auto& st = d.stats();
    if (m.timeRow("time", d.time())) return;
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
    if (!m.input.gamepad().empty()) ImGui::Text("gamepad: %s", m.input.gamepad().c_str());
    if (ImGui::CollapsingHeader("Controls")) {
        ImGui::TextWrapped("W/up go, S/down back (turn round and go), A/left and D/right turn the direction 45 deg, H/space stop; "
                           "[ and ] w_v -/+2, +/- depth, P pause, R restart. Gamepad: left stick or d-pad (up go, down back, "
                           "left/right turn), A stop, bumpers w_v, triggers depth, Start pause, Back restart.");
    }
    ImGui::Separator();
    ImGui::Text("Characters");
    for (int c = 0; c < static_cast<int>(d.scene().characters.size()); ++c) {
        characterRow(c, m.cast.tints()[static_cast<std::size_t>(c)], d.scene().characters[static_cast<std::size_t>(c)].name);
    }
}

Status CarryPlay::writeLog() const {
    const Impl& m = *impl_;
    if (m.opt.log.empty()) return {};
    nlohmann::ordered_json j = m.logHead("carry", m.opt.project);
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
