#include "duel.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <thread>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "duel_script.h"
#include "fray/core/atomic_file.h"
#include "fray/core/kinematics.h"
#include "fray/igraph/igraph.h"
#include "fray/igraph/runtime.h"
#include "fray/pipeline/sim_session.h"
#include "fray/sim/scene.h"
#include "scene_stage.h"

namespace fray::player {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using igraph::Command;

// A command key held down is sent again this often (s), so holding "forward" keeps walking.
constexpr double kRepeat = 0.3;
// Character 0 is the user's.
constexpr int kUser = 0;

// Which file sits at the graph's place.
enum class GraphFileKind { Missing, Graph, Other };
GraphFileKind graphFileKind(const fs::path& file) {
    std::error_code ec;
    if (!fs::exists(file, ec)) return GraphFileKind::Missing;
    auto head = readWholeFile(file, "the interaction graph");
    if (!head || head->size() < 8 || std::memcmp(head->data(), "FRAYIGPH", 8) != 0) return GraphFileKind::Other;
    return GraphFileKind::Graph;
}

std::vector<std::string> actionTags(const sim::LibraryAction& a) {
    static constexpr std::pair<std::uint32_t, const char*> kTags[] = {
        {sim::kPunch, "punch"}, {sim::kKick, "kick"},   {sim::kBlock, "block"}, {sim::kAvoid, "avoid"}, {sim::kPushed, "pushed"},
        {sim::kFalling, "falling"}, {sim::kStep, "step"}, {sim::kIdle, "idle"}, {sim::kWalk, "walk"},   {sim::kRun, "run"},
        {sim::kTurn, "turn"},   {sim::kTransition, "transition"}, {sim::kTackle, "tackle"}};
    std::vector<std::string> out;
    for (const auto& [flag, name] : kTags) {
        if (a.is(flag)) out.emplace_back(name);
    }
    return out;
}

// The style whose weights these are ("" when none).
std::string styleOf(const igraph::RewardWeights& w) {
    for (const auto& name : igraph::styleNames()) {
        if (auto p = igraph::stylePreset(name); p && *p == w) return name;
    }
    return {};
}

struct Bindings {
    Command command;
    std::array<int, 2> keys;
};
constexpr Bindings kKeys[] = {
    {Command::Forward, {GLFW_KEY_W, GLFW_KEY_UP}},          {Command::Back, {GLFW_KEY_S, GLFW_KEY_DOWN}},
    {Command::TurnLeft, {GLFW_KEY_A, GLFW_KEY_LEFT}},       {Command::TurnRight, {GLFW_KEY_D, GLFW_KEY_RIGHT}},
    {Command::Punch, {GLFW_KEY_J, GLFW_KEY_UNKNOWN}},       {Command::Kick, {GLFW_KEY_K, GLFW_KEY_UNKNOWN}},
    {Command::Dodge, {GLFW_KEY_L, GLFW_KEY_UNKNOWN}},       {Command::Avoid, {GLFW_KEY_I, GLFW_KEY_UNKNOWN}},
};
constexpr int kCommandCount = 9;  // Command::None .. Command::Avoid
bool moves(Command c) { return c == Command::Forward || c == Command::Back || c == Command::TurnLeft || c == Command::TurnRight; }

// Edge detection of buttons and keys: true on the frame it goes down.
struct Edges {
    std::array<bool, 64> was{};
    bool pressed(int slot, bool down) {
        const bool p = down && !was[static_cast<std::size_t>(slot)];
        was[static_cast<std::size_t>(slot)] = down;
        return p;
    }
};

}  // namespace

struct Duel::Impl {
    DuelOptions opt;
    fs::path graphFile;
    std::unique_ptr<pipeline::SimSession> session;
    std::shared_ptr<const igraph::Rules> rules;
    std::shared_ptr<const igraph::Graph> graph;
    std::shared_ptr<const igraph::Policy> userPolicy;
    std::unique_ptr<igraph::PolicyService> service;
    std::shared_ptr<const igraph::Policy> applied;  // the opponents' policy in play
    std::vector<ScriptEvent> script;
    std::size_t nextEvent = 0;

    // Building the graph in the background.
    std::thread builder;
    std::atomic<bool> cancel{false}, built{false};
    std::mutex progressMutex;
    double fraction = 0;
    std::string stage = "starting";
    std::string buildError;
    std::vector<std::string> notes;  // shown in the panel
    std::unique_ptr<igraph::Graph> builtGraph;
    std::shared_ptr<const igraph::Policy> builtUser, builtOpponent;

    // The match.
    std::unique_ptr<igraph::Match> match;
    std::unique_ptr<sim::ScenePoser> poser;
    std::vector<glm::vec3> tints;
    std::vector<Pose> poses;
    std::vector<std::vector<glm::vec3>> positions;
    std::vector<std::vector<glm::quat>> rotations;
    std::vector<std::string> labels;
    std::vector<render::CharacterInstance> shown;
    FollowCentre follow;
    double carry = 0;  // s of match time not yet stepped
    bool paused = false;
    int restarts = 0;
    UpdateClock clock;

    // The opponents' style and depth as asked for (the policy in play may be older).
    std::string style;
    int depth = 3;
    struct PolicyRecord {
        double time, seconds;
        std::string style;
        int depth;
    };
    std::vector<PolicyRecord> policies;
    struct LoggedEvent {
        double time;
        std::string source, what;
        int character;
        std::string value;
    };
    std::vector<LoggedEvent> events;

    // Input state.
    Edges edges;
    std::array<double, kCommandCount> heldFor{};
    std::string gamepadName;

    const sim::ActionLibrary& lib() const { return session->library; }
    int size() const { return match ? match->size() : opt.characters; }

    std::string nameOf(int c) const {
        if (opt.characters == 2) return c == kUser ? "you" : "opponent";
        if (c == kUser) return "you (red 1)";
        return std::string(c % 2 == 0 ? "red " : "blue ") + std::to_string(c / 2 + 1);
    }

    Status acquireGraph() {
        graphFile = opt.graph.empty() ? fs::path(opt.project + ".igraph") : fs::path(opt.graph);
        const auto kind = graphFileKind(graphFile);
        if (kind == GraphFileKind::Other) {
            return makeError(graphFile.string() + ": exists and is not an interaction graph file: not overwriting it (name another file with --graph)");
        }
        if (kind == GraphFileKind::Graph) {
            auto g = igraph::loadGraph(graphFile, *rules);
            if (g) {
                graph = std::make_shared<const igraph::Graph>(std::move(*g));
                return computeFirstPolicies(*graph, style, depth, userPolicy, applied);
            }
            if (g.error().isCancelled()) return g.error();
            notes.push_back(g.error().message + "; building it again");
        } else {
            notes.push_back(graphFile.string() + ": no graph yet; building it (" + std::to_string(opt.graphStates) + " states at most)");
        }
        for (const auto& n : notes) {
            if (!opt.quiet) std::fprintf(stderr, "fray-play: %s\n", n.c_str());
        }
        if (opt.foreground) {
            build(style, depth);
            if (!buildError.empty()) return makeError(buildError);
            return takeBuilt();
        }
        builder = std::thread([this, s = style, d = depth] { build(s, d); });
        return {};
    }

    // The user's boxer ranks its commands by a general policy; the opponents play `firstStyle`.
    Status computeFirstPolicies(const igraph::Graph& g, const std::string& firstStyle, int firstDepth,
                                std::shared_ptr<const igraph::Policy>& user, std::shared_ptr<const igraph::Policy>& opponent) const {
        auto pu = igraph::computePolicy(g, igraph::RewardWeights{}, firstDepth, cancelWhen(cancel));
        if (!pu) return pu.error();
        auto w = igraph::stylePreset(firstStyle);
        if (!w) return w.error();
        auto po = igraph::computePolicy(g, *w, firstDepth, cancelWhen(cancel));
        if (!po) return po.error();
        user = std::make_shared<const igraph::Policy>(std::move(*pu));
        opponent = std::make_shared<const igraph::Policy>(std::move(*po));
        return {};
    }

    // The worker: build, save as the cache, the first policies.
    void build(const std::string& firstStyle, int firstDepth) {
        igraph::BuildOptions bo;
        bo.seed = opt.seed;
        bo.maxSamples = opt.graphStates;
        bo.coverageDepth = 0;  // the coverage measurement (fray-cli igraph build) is not needed to play
        const ProgressFn progress = [this](double f, std::string_view s) {
            {
                std::lock_guard lock(progressMutex);
                fraction = f;
                stage = std::string(s);
            }
            return !cancel.load();
        };
        auto g = igraph::buildGraph(*rules, bo, progress);
        std::string error;
        if (!g) {
            error = opt.project + ": " + g.error().message;
        } else {
            if (Status s = igraph::saveGraph(*g, graphFile); !s) {
                std::lock_guard lock(progressMutex);
                notes.push_back("the graph could not be kept: " + s.error().message);
            } else {
                std::lock_guard lock(progressMutex);
                notes.push_back("built " + std::to_string(g->stateCount()) + " states, " + std::to_string(g->edgeCount()) + " edges; kept in " +
                                graphFile.string());
            }
            {
                std::lock_guard lock(progressMutex);
                stage = "policies";
            }
            std::shared_ptr<const igraph::Policy> u, o;
            if (Status s = computeFirstPolicies(*g, firstStyle, firstDepth, u, o); !s) error = s.error().message;
            builtGraph = std::make_unique<igraph::Graph>(std::move(*g));
            builtUser = u;
            builtOpponent = o;
        }
        std::lock_guard lock(progressMutex);
        buildError = error;
        built = true;
    }

    Status takeBuilt() {
        if (builder.joinable()) builder.join();
        if (!buildError.empty()) return makeError(buildError);
        graph = std::shared_ptr<const igraph::Graph>(std::move(builtGraph));
        userPolicy = builtUser;
        applied = builtOpponent;
        return {};
    }

    void startMatch() {
        service = std::make_unique<igraph::PolicyService>(graph, applied);
        const int n = opt.characters;
        const std::uint64_t seed = opt.seed + static_cast<std::uint64_t>(restarts);
        const auto starts = n == 2 ? igraph::duelStarts(1.3, seed, 0.3) : igraph::teamStarts(n, seed, 0.2);
        std::vector<igraph::FighterSpec> fighters;
        for (int c = 0; c < n; ++c) {
            igraph::FighterSpec f;
            f.name = nameOf(c);
            f.side = c % 2;
            // The user's boxer idles and guards unless steered; its commands
            // are ranked by its own (general) policy.
            f.mind = c == kUser ? igraph::Mind::Static : igraph::Mind::Graph;
            f.policy = f.side == 0 ? userPolicy : applied;
            f.style = f.side == 0 ? "general" : style;
            f.start = starts[static_cast<std::size_t>(c)];
            fighters.push_back(std::move(f));
        }
        igraph::MatchOptions mo;
        mo.duration = sim::kMaxSceneSeconds;
        mo.seed = seed;
        mo.record = "fray-play " + std::string(n == 2 ? "duel" : "team fight");
        match = std::make_unique<igraph::Match>(rules, graph, std::move(fighters), mo);
        poser = std::make_unique<sim::ScenePoser>(match->scene(), lib());
        tints.clear();
        for (int c = 0; c < n; ++c) tints.push_back(cli::characterTint(match->scene(), c));
        poses.assign(static_cast<std::size_t>(n), {});
        positions.assign(static_cast<std::size_t>(n), {});
        rotations.assign(static_cast<std::size_t>(n), {});
        labels.assign(static_cast<std::size_t>(n), {});
        nextEvent = 0;
        carry = 0;
        follow.reset();
        policies.push_back({0.0, applied->seconds, styleOf(applied->weights), applied->depth});
        // Asked for another while the graph was being built: recompute now.
        if (styleOf(applied->weights) != style || applied->depth != depth) {
            if (auto w = igraph::stylePreset(style)) (void)service->request(*w, depth);
        }
        pose();
    }

    void requestPolicy(const std::string& newStyle, int newDepth, const std::string& source) {
        auto w = igraph::stylePreset(newStyle);
        if (!w) return;
        newDepth = std::clamp(newDepth, 1, kMaxPolicyDepth);
        if (newStyle != style) events.push_back({match ? match->time() : 0.0, source, "style", -1, newStyle});
        if (newDepth != depth) events.push_back({match ? match->time() : 0.0, source, "depth", -1, std::to_string(newDepth)});
        style = newStyle;
        depth = newDepth;
        if (service) (void)service->request(*w, depth);  // the weights are a preset's: valid
    }

    void command(int c, Command cmd, const std::string& source) {
        if (!match) return;
        match->command(c, cmd);
        events.push_back({match->time(), source, "command", c, igraph::commandName(cmd)});
    }

    // A policy recomputed in the background replaces the opponents' at their next decisions.
    void swapPolicy() {
        if (!service) return;
        auto p = service->current();
        if (p == applied) return;
        applied = p;
        for (int c = 0; c < match->size(); ++c) {
            if (c % 2 == 1) match->setPolicy(c, p);
        }
        policies.push_back({match->time(), p->seconds, styleOf(p->weights), p->depth});
    }

    void readInput(GLFWwindow* window, bool keyboard, double dt) {
        std::array<bool, kCommandCount> down{};
        std::array<const char*, kCommandCount> from{};
        bool styleNext = false, stylePrev = false, depthUp = false, depthDown = false, pause = false, restart = false;
        int styleKey = -1;
        if (keyboard && window) {
            auto key = [&](int k) { return k != GLFW_KEY_UNKNOWN && glfwGetKey(window, k) == GLFW_PRESS; };
            for (const auto& b : kKeys) {
                if (key(b.keys[0]) || key(b.keys[1])) down[static_cast<std::size_t>(b.command)] = true, from[static_cast<std::size_t>(b.command)] = "keyboard";
            }
            for (int s = 0; s < 3; ++s) {
                if (edges.pressed(20 + s, key(GLFW_KEY_1 + s))) styleKey = s;
            }
            depthUp = edges.pressed(23, key(GLFW_KEY_EQUAL) || key(GLFW_KEY_KP_ADD));
            depthDown = edges.pressed(24, key(GLFW_KEY_MINUS) || key(GLFW_KEY_KP_SUBTRACT));
            pause = edges.pressed(25, key(GLFW_KEY_P));
            restart = edges.pressed(26, key(GLFW_KEY_R));
        }
        // The first joystick with a gamepad mapping.
        gamepadName.clear();
        for (int j = GLFW_JOYSTICK_1; j <= GLFW_JOYSTICK_LAST; ++j) {
            GLFWgamepadstate gp;
            if (!glfwJoystickIsGamepad(j) || !glfwGetGamepadState(j, &gp)) continue;
            const char* name = glfwGetGamepadName(j);
            gamepadName = name ? name : "gamepad";
            const float x = gp.axes[GLFW_GAMEPAD_AXIS_LEFT_X], y = gp.axes[GLFW_GAMEPAD_AXIS_LEFT_Y];
            auto btn = [&](int b) { return gp.buttons[b] == GLFW_PRESS; };
            auto set = [&](Command c, bool on) {
                if (on) down[static_cast<std::size_t>(c)] = true, from[static_cast<std::size_t>(c)] = from[static_cast<std::size_t>(c)] ? from[static_cast<std::size_t>(c)] : "gamepad";
            };
            set(Command::Forward, y < -0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_UP));
            set(Command::Back, y > 0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_DOWN));
            set(Command::TurnLeft, x < -0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_LEFT));
            set(Command::TurnRight, x > 0.5f || btn(GLFW_GAMEPAD_BUTTON_DPAD_RIGHT));
            set(Command::Punch, btn(GLFW_GAMEPAD_BUTTON_A));
            set(Command::Kick, btn(GLFW_GAMEPAD_BUTTON_B));
            set(Command::Dodge, btn(GLFW_GAMEPAD_BUTTON_X));
            set(Command::Avoid, btn(GLFW_GAMEPAD_BUTTON_Y));
            styleNext = edges.pressed(30, btn(GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER));
            stylePrev = edges.pressed(31, btn(GLFW_GAMEPAD_BUTTON_LEFT_BUMPER));
            depthUp = edges.pressed(32, gp.axes[GLFW_GAMEPAD_AXIS_RIGHT_TRIGGER] > 0.5f) || depthUp;
            depthDown = edges.pressed(33, gp.axes[GLFW_GAMEPAD_AXIS_LEFT_TRIGGER] > 0.5f) || depthDown;
            pause = edges.pressed(34, btn(GLFW_GAMEPAD_BUTTON_START)) || pause;
            restart = edges.pressed(35, btn(GLFW_GAMEPAD_BUTTON_BACK)) || restart;
            break;
        }
        if (!match) return;
        for (int k = 1; k < kCommandCount; ++k) {
            const auto c = static_cast<Command>(k);
            const bool fresh = edges.pressed(k, down[static_cast<std::size_t>(k)]);
            double& held = heldFor[static_cast<std::size_t>(k)];
            if (!down[static_cast<std::size_t>(k)]) {
                held = 0;
                continue;
            }
            held += dt;
            if (fresh || (moves(c) && held >= kRepeat)) {
                if (!fresh) held = 0;
                command(kUser, c, from[static_cast<std::size_t>(k)]);
            }
        }
        const auto& names = igraph::styleNames();
        const int at = static_cast<int>(std::find(names.begin(), names.end(), style) - names.begin());
        const int count = static_cast<int>(names.size());
        if (styleKey >= 0 && styleKey < count) requestPolicy(names[static_cast<std::size_t>(styleKey)], depth, "keyboard");
        if (styleNext) requestPolicy(names[static_cast<std::size_t>((at + 1) % count)], depth, "gamepad");
        if (stylePrev) requestPolicy(names[static_cast<std::size_t>((at + count - 1) % count)], depth, "gamepad");
        if (depthUp) requestPolicy(style, depth + 1, "input");
        if (depthDown) requestPolicy(style, depth - 1, "input");
        if (pause) paused = !paused;
        if (restart) {
            ++restarts;
            startMatch();
        }
    }

    void applyScript() {
        while (nextEvent < script.size() && script[nextEvent].time <= match->time() + 1e-9) {
            const auto& e = script[nextEvent++];
            switch (e.kind) {
                case ScriptEvent::Kind::Command: command(e.character, e.command, "script"); break;
                case ScriptEvent::Kind::Style: requestPolicy(e.style, depth, "script"); break;
                case ScriptEvent::Kind::Depth: requestPolicy(style, e.depth, "script"); break;
            }
        }
    }

    void advance(double dt) {
        constexpr double kStep = 1.0 / 60.0;  // MatchOptions::step
        carry += std::min(dt, 0.25);          // a stalled frame does not fast-forward the fight
        auto steps = static_cast<int>(std::floor((carry + 1e-9) / kStep));
        carry -= steps * kStep;
        while (steps-- > 0 && !match->finished()) {
            swapPolicy();
            applyScript();
            match->step();
        }
        swapPolicy();
    }

    void pose() {
        const double t = match->time();
        const auto& scene = match->scene();
        shown.clear();
        const int n = match->size();
        for (int c = 0; c < n; ++c) {
            const auto k = static_cast<std::size_t>(c);
            poser->pose(c, t, poses[k]);
            positions[k].resize(poses[k].translations.size());
            rotations[k].resize(poses[k].translations.size());
            forwardKinematics(poser->skeleton(c), poses[k].translations, poses[k].rotations, positions[k], rotations[k]);
            labels[k].clear();
            if (n <= cli::SceneStage::kAutoLabels || c == kUser) {
                const int i = scene.instanceAt(c, t);
                if (i >= 0) {
                    const auto& inst = scene.characters[k].track[static_cast<std::size_t>(i)];
                    labels[k] = scene.characters[k].name + ": " + lib().action(inst.action).label() + (inst.forced ? " (hit)" : "");
                }
            }
            // Not drawn selected: the highlight would shift its colour off its swatch; the label names it.
            shown.push_back({&poser->skeleton(c), positions[k], rotations[k], tints[k], labels[k], false});
        }
        follow.to(render::characterBounds(shown));
    }

    std::array<int, 2> landedBySide() const {
        std::array<int, 2> out{};
        const auto landed = match->landed();
        for (std::size_t c = 0; c < landed.size(); ++c) out[c % 2] += landed[c];
        return out;
    }
    std::array<int, 2> blockedBySide() const {
        std::array<int, 2> out{};
        for (const auto& h : match->scene().hits) {
            if (h.blocked) ++out[static_cast<std::size_t>(h.attacker % 2)];
        }
        return out;
    }
};

Duel::Duel() : impl_(std::make_unique<Impl>()) {}

Duel::~Duel() {
    impl_->cancel = true;
    if (impl_->builder.joinable()) impl_->builder.join();
}

Result<std::unique_ptr<Duel>> Duel::open(const DuelOptions& options) {
    std::unique_ptr<Duel> d(new Duel());
    Impl& m = *d->impl_;
    m.opt = options;
    if (options.characters < 2 || options.characters > 1000) return makeError("--teams: between 2 and 1000 characters");
    if (options.depth < 1 || options.depth > kMaxPolicyDepth) {
        return makeError("--depth: " + std::to_string(options.depth) + " is not from 1 to " + std::to_string(kMaxPolicyDepth));
    }
    if (auto w = igraph::stylePreset(options.style); !w) return makeError("--style: " + w.error().message);
    if (options.graphStates < 100) return makeError("--graph-states: at least 100");
    m.style = options.style;
    m.depth = options.depth;
    if (!options.input.empty()) {
        auto s = loadScript(options.input);
        if (!s) return s.error();
        if (Status st = checkCharacters(*s, options.characters, options.input); !st) return st.error();
        m.script = std::move(*s);
    }
    // Progress on a terminal only: a scripted run's output stays its result and errors.
    const ProgressFn progress = options.quiet || !isatty(2) ? ProgressFn{} : ProgressFn([last = -1](double f, std::string_view stage) mutable {
        const int pct = static_cast<int>(f * 100);
        if (pct / 10 != last / 10) std::fprintf(stderr, "fray-play: %.*s %d%%\n", static_cast<int>(stage.size()), stage.data(), pct), last = pct;
        return true;
    });
    auto ss = pipeline::openSimSession(options.project, progress);
    if (!ss) return ss.error();
    m.session = std::move(*ss);
    auto rules = igraph::Rules::make(m.session->library);
    if (!rules) return makeError(options.project + ": " + rules.error().message);
    m.rules = *rules;
    if (Status st = m.acquireGraph(); !st) return st.error();
    if (m.graph) m.startMatch();
    return d;
}

Status Duel::update(double dt, GLFWwindow* window, bool keyboard) {
    Impl& m = *impl_;
    if (!m.graph) {
        if (!m.built) {
            m.readInput(window, keyboard, dt);
            return {};
        }
        if (Status s = m.takeBuilt(); !s) return s;
        m.startMatch();
    }
    m.readInput(window, keyboard, dt);
    const auto t0 = Clock::now();
    if (!m.paused) m.advance(dt);
    m.pose();
    m.clock.add(std::chrono::duration<double>(Clock::now() - t0).count());
    return {};
}


std::span<const render::CharacterInstance> Duel::shown() const { return impl_->shown; }
render::Bounds Duel::framing() const {
    const render::Bounds b = render::characterBounds(impl_->shown);
    return b.empty() ? framingPlaceholder() : b;
}
glm::vec3 Duel::moved() const { return impl_->follow.moved(); }
const char* Duel::frameButton() const { return "Frame the fight"; }
std::string Duel::summary() const {
    char line[160];
    std::snprintf(line, sizeof line, "match at %.3f s; match steps and posing %.2f ms a frame (worst %.2f ms)", time(),
                  1e3 * impl_->clock.mean(), 1e3 * impl_->clock.worst());
    return line;
}
bool Duel::ready() const { return impl_->match != nullptr; }
double Duel::time() const { return impl_->match ? impl_->match->time() : 0.0; }

void Duel::overlay() {
    Impl& m = *impl_;
    const bool duel = m.opt.characters == 2;
    ImGui::Text("%s", duel ? "Duel against the Interaction Graph" : "Team fight on the Interaction Graph");
    if (!m.match) {
        std::lock_guard lock(m.progressMutex);
        ImGui::TextWrapped("Building the graph (%s)", m.stage.c_str());
        ImGui::ProgressBar(static_cast<float>(m.fraction), ImVec2(-1, 0));
        for (const auto& n : m.notes) ImGui::TextWrapped("%s", n.c_str());
        return;
    }
    const auto landed = m.landedBySide();
    const auto blocked = m.blockedBySide();
    const int score = landed[0] - landed[1];
    ImGui::Text("match %.1f s%s", m.match->time(), m.paused ? "  (paused)" : "");
    ImGui::SameLine();
    if (ImGui::SmallButton(m.paused ? "Resume" : "Pause")) m.paused = !m.paused;
    ImGui::SameLine();
    if (ImGui::SmallButton("Restart")) {
        ++m.restarts;
        m.startMatch();
        return;
    }
    const ImVec4 scoreColour = score > 0 ? ImVec4(0.45f, 0.9f, 0.45f, 1) : score < 0 ? ImVec4(1.0f, 0.45f, 0.4f, 1) : ImVec4(1, 1, 1, 1);
    ImGui::SetWindowFontScale(1.6f);
    ImGui::TextColored(scoreColour, "Score %+d", score);
    ImGui::SetWindowFontScale(1.0f);
    ImGui::Text("hits landed: %s %d, %s %d", duel ? "you" : "red", landed[0], duel ? "opponent" : "blue", landed[1]);
    ImGui::Text("blocked: %s %d, %s %d", duel ? "yours" : "red's", blocked[0], duel ? "opponent's" : "blue's", blocked[1]);
    ImGui::Separator();
    ImGui::Text("%s", duel ? "Opponent (graph policy)" : "Blue team (graph policy)");
    const auto& names = igraph::styleNames();
    int at = static_cast<int>(std::find(names.begin(), names.end(), m.style) - names.begin());
    if (ImGui::BeginCombo("style", m.style.c_str())) {
        for (int i = 0; i < static_cast<int>(names.size()); ++i) {
            if (ImGui::Selectable(names[static_cast<std::size_t>(i)].c_str(), i == at)) m.requestPolicy(names[static_cast<std::size_t>(i)], m.depth, "panel");
        }
        ImGui::EndCombo();
    }
    int depth = m.depth;
    if (ImGui::SliderInt("depth", &depth, 1, kMaxPolicyDepth) && depth != m.depth) m.requestPolicy(m.style, depth, "panel");
    const auto& p = *m.applied;
    const std::string playing = styleOf(p.weights);
    ImGui::Text("playing: %s, depth %d", playing.c_str(), p.depth);
    if (!m.policies.empty()) {
        const auto& last = m.policies.back();
        ImGui::Text("last recompute %.1f ms, in play at %.1f s", 1e3 * last.seconds, last.time);
    }
    if (m.service && m.service->busy()) ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1), "recomputing %s, depth %d ...", m.style.c_str(), m.depth);
    const auto& st = m.match->stats();
    ImGui::Text("decisions %lld, off the graph %.0f %%", static_cast<long long>(st.decisions),
                st.lookups > 0 ? 100.0 * static_cast<double>(st.offGraph) / static_cast<double>(st.lookups) : 0.0);
    ImGui::Text("graph: %zu states, %zu edges", m.graph->stateCount(), m.graph->edgeCount());
    if (!m.gamepadName.empty()) ImGui::Text("gamepad: %s", m.gamepadName.c_str());
    if (ImGui::CollapsingHeader("Controls")) {
        ImGui::TextWrapped("W/up forward, S/down back, A/left turn left, D/right turn right, J punch, K kick, L dodge, I avoid; "
                           "1/2/3 style general/infighter/outboxer, +/- depth, P pause, R restart. Gamepad: left stick or d-pad "
                           "moves, A punch, B kick, X dodge, Y avoid, bumpers style, triggers depth, Start pause, Back restart.");
    }
    ImGui::Separator();
    ImGui::Text("Characters");
    const auto& scene = m.match->scene();
    const int n = m.match->size();
    for (int c = 0; c < std::min(n, 64); ++c) {
        const glm::vec3 tint = m.tints[static_cast<std::size_t>(c)];
        ImGui::PushID(c);
        ImGui::ColorButton("##tint", ImVec4(tint.x, tint.y, tint.z, 1.0f), ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
        ImGui::SameLine();
        const auto l = m.match->landed()[static_cast<std::size_t>(c)];
        ImGui::Text("%s  (%d landed)", scene.characters[static_cast<std::size_t>(c)].name.c_str(), l);
        ImGui::PopID();
    }
    if (n > 64) ImGui::Text("... and %d more", n - 64);
}

Status Duel::writeLog() const {
    const Impl& m = *impl_;
    if (m.opt.log.empty()) return {};
    nlohmann::ordered_json j;
    j["format"] = "fray-play-log";
    j["version"] = 1;
    j["mode"] = m.opt.characters == 2 ? "duel" : "teams";
    j["project"] = m.opt.project;
    j["graph"] = m.graphFile.string();
    j["time"] = m.match ? m.match->time() : 0.0;
    j["characters"] = nlohmann::ordered_json::array();
    j["events"] = nlohmann::ordered_json::array();
    j["policies"] = nlohmann::ordered_json::array();
    j["actions"] = nlohmann::ordered_json::array();
    j["hits"] = nlohmann::ordered_json::array();
    if (m.match) {
        const auto& scene = m.match->scene();
        const auto landed = m.match->landed();
        for (int c = 0; c < m.match->size(); ++c) {
            const auto& ch = scene.characters[static_cast<std::size_t>(c)];
            const glm::vec3 t = m.tints[static_cast<std::size_t>(c)];
            j["characters"].push_back({{"name", ch.name}, {"side", ch.side}, {"user", c == kUser}, {"tint", {t.x, t.y, t.z}},
                                       {"landed", landed[static_cast<std::size_t>(c)]}});
        }
        for (const auto& e : m.events) {
            nlohmann::ordered_json x{{"time", e.time}, {"source", e.source}};
            if (e.what == "command") x["character"] = e.character, x["command"] = e.value;
            else x[e.what] = e.what == "depth" ? nlohmann::ordered_json(std::stoi(e.value)) : nlohmann::ordered_json(e.value);
            j["events"].push_back(x);
        }
        for (const auto& p : m.policies) j["policies"].push_back({{"time", p.time}, {"style", p.style}, {"depth", p.depth}, {"seconds", p.seconds}});
        for (int c = 0; c < m.match->size(); ++c) {
            for (const auto& inst : scene.characters[static_cast<std::size_t>(c)].track) {
                if (inst.start > m.match->time()) continue;
                const auto& a = m.lib().action(inst.action);
                j["actions"].push_back({{"character", c}, {"start", inst.start}, {"end", std::min(inst.end, m.match->time())}, {"action", a.label()},
                                        {"tags", actionTags(a)}, {"forced", inst.forced}});
            }
        }
        for (const auto& h : scene.hits) {
            j["hits"].push_back({{"time", h.time}, {"attacker", h.attacker}, {"defender", h.defender}, {"attack", m.lib().action(h.attackAction).label()},
                                 {"speed", h.speed}, {"blocked", h.blocked}});
        }
    }
    return writeFileAtomically(m.opt.log, j.dump(1) + "\n");
}

}  // namespace fray::player
