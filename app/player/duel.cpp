#include "duel.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "duel_script.h"
#include "fray/core/atomic_file.h"
#include "fray/igraph/igraph.h"
#include "fray/igraph/runtime.h"
#include "fray/sim/scene.h"
#include "live_play.h"
#include "scene_stage.h"

namespace fray::player {
namespace {

namespace fs = std::filesystem;
using igraph::Command;

// A command key held down is sent again this often (s), so holding "forward" keeps walking.
constexpr double kRepeat = 0.3;
// Character 0 is the user's.
constexpr int kUser = 0;

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

// The user's commands, in Command's order from Forward: keys, gamepad; the moves repeat when held.
const std::vector<Hold> kHolds = {
    {GLFW_KEY_W, GLFW_KEY_UP, Pad::Up, true},          {GLFW_KEY_S, GLFW_KEY_DOWN, Pad::Down, true},
    {GLFW_KEY_A, GLFW_KEY_LEFT, Pad::Left, true},       {GLFW_KEY_D, GLFW_KEY_RIGHT, Pad::Right, true},
    {GLFW_KEY_J, GLFW_KEY_UNKNOWN, Pad::A, false},      {GLFW_KEY_K, GLFW_KEY_UNKNOWN, Pad::B, false},
    {GLFW_KEY_L, GLFW_KEY_UNKNOWN, Pad::X, false},      {GLFW_KEY_I, GLFW_KEY_UNKNOWN, Pad::Y, false},
};
Command commandOf(std::size_t hold) { return static_cast<Command>(hold + 1); }

}  // namespace

struct Duel::Impl final : LiveCore {
    // The number keys 1, 2, 3 pick a style.
    Impl() : LiveCore(InputReader(kHolds, {GLFW_KEY_1, GLFW_KEY_2, GLFW_KEY_3}, kRepeat)) {}

    DuelOptions opt;
    std::shared_ptr<const igraph::Rules> rules;
    std::shared_ptr<const igraph::Graph> graph;
    std::shared_ptr<const igraph::Policy> userPolicy;
    std::unique_ptr<igraph::PolicyService> service;
    std::shared_ptr<const igraph::Policy> applied;  // the opponents' policy in play
    TimedEvents<ScriptEvent> script;

    // What the worker built.
    std::unique_ptr<igraph::Graph> builtGraph;
    std::shared_ptr<const igraph::Policy> builtUser, builtOpponent;

    // The match.
    std::unique_ptr<igraph::Match> match;

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

    std::string nameOf(int c) const {
        if (opt.characters == 2) return c == kUser ? "you" : "opponent";
        if (c == kUser) return "you (red 1)";
        return std::string(c % 2 == 0 ? "red " : "blue ") + std::to_string(c / 2 + 1);
    }

    Status acquireGraph() {
        graphFile = opt.graph.empty() ? fs::path(opt.project + ".igraph") : fs::path(opt.graph);
        const auto kind = graphAtPlace(graphFile);
        if (kind == GraphAtPlace::Carry || kind == GraphAtPlace::Other) {
            return makeError(graphFile.string() + ": exists and is not an interaction graph file: not overwriting it (name another file with --graph)");
        }
        if (kind == GraphAtPlace::Duel) {
            auto g = igraph::loadGraph(graphFile, *rules);
            if (g) {
                graph = std::make_shared<const igraph::Graph>(std::move(*g));
                return computeFirstPolicies(*graph, style, depth, userPolicy, applied);
            }
            if (g.error().isCancelled()) return g.error();
            build.note(g.error().message + "; building it again");
        } else {
            build.note(graphFile.string() + ": no graph yet; building it (" + std::to_string(opt.graphStates) + " states at most)");
        }
        build.start(opt.foreground, opt.quiet, [this, s = style, d = depth] { return buildGraph(s, d); });
        return opt.foreground ? takeBuilt() : Status{};
    }

    // The user's boxer ranks its commands by a general policy; the opponents play `firstStyle`.
    Status computeFirstPolicies(const igraph::Graph& g, const std::string& firstStyle, int firstDepth,
                                std::shared_ptr<const igraph::Policy>& user, std::shared_ptr<const igraph::Policy>& opponent) const {
        auto pu = igraph::computePolicy(g, igraph::RewardWeights{}, firstDepth, cancelWhen(build.cancel));
        if (!pu) return pu.error();
        auto w = igraph::stylePreset(firstStyle);
        if (!w) return w.error();
        auto po = igraph::computePolicy(g, *w, firstDepth, cancelWhen(build.cancel));
        if (!po) return po.error();
        user = std::make_shared<const igraph::Policy>(std::move(*pu));
        opponent = std::make_shared<const igraph::Policy>(std::move(*po));
        return {};
    }

    // The worker: build, save as the cache, the first policies; returns the error ("": none).
    std::string buildGraph(const std::string& firstStyle, int firstDepth) {
        igraph::BuildOptions bo;
        bo.seed = opt.seed;
        bo.maxSamples = opt.graphStates;
        bo.coverageDepth = 0;  // the coverage measurement (fray-cli igraph build) is not needed to play
        auto g = igraph::buildGraph(*rules, bo, build.progress());
        if (!g) return opt.project + ": " + g.error().message;
        if (Status s = igraph::saveGraph(*g, graphFile); !s) {
            build.note("the graph could not be kept: " + s.error().message);
        } else {
            build.note("built " + std::to_string(g->stateCount()) + " states, " + std::to_string(g->edgeCount()) + " edges; kept in " +
                       graphFile.string());
        }
        build.stage("policies");
        std::string error;
        std::shared_ptr<const igraph::Policy> u, o;
        if (Status s = computeFirstPolicies(*g, firstStyle, firstDepth, u, o); !s) error = s.error().message;
        builtGraph = std::make_unique<igraph::Graph>(std::move(*g));
        builtUser = u;
        builtOpponent = o;
        return error;
    }

    bool hasGraph() const override { return graph != nullptr; }

    Status takeBuilt() override {
        if (Status s = build.finish(); !s) return s;
        graph = std::shared_ptr<const igraph::Graph>(std::move(builtGraph));
        userPolicy = builtUser;
        applied = builtOpponent;
        return {};
    }

    Status start() override {
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
        cast.reset(match->scene(), lib(), n);
        script.next = 0;
        steps.reset();
        follow.reset();
        policies.push_back({0.0, applied->seconds, styleOf(applied->weights), applied->depth});
        // Asked for another while the graph was being built: recompute now.
        if (styleOf(applied->weights) != style || applied->depth != depth) {
            if (auto w = igraph::stylePreset(style)) (void)service->request(*w, depth);
        }
        pose();
        return {};
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

    void readInput(GLFWwindow* window, bool keyboard, double dt) override {
        const Controls in = input.read(window, keyboard);
        if (!match) return;
        input.send(in, dt, [&](std::size_t i, const char* from) { command(kUser, commandOf(i), from); });
        int styleKey = -1;
        for (int s = 0; s < 3; ++s) {
            if (in.keys[static_cast<std::size_t>(s)]) styleKey = s;
        }
        const auto& names = igraph::styleNames();
        const int at = static_cast<int>(std::find(names.begin(), names.end(), style) - names.begin());
        const int count = static_cast<int>(names.size());
        if (styleKey >= 0 && styleKey < count) requestPolicy(names[static_cast<std::size_t>(styleKey)], depth, "keyboard");
        if (in.next) requestPolicy(names[static_cast<std::size_t>((at + 1) % count)], depth, "gamepad");
        if (in.prev) requestPolicy(names[static_cast<std::size_t>((at + count - 1) % count)], depth, "gamepad");
        if (in.depthUp) requestPolicy(style, depth + 1, "input");
        if (in.depthDown) requestPolicy(style, depth - 1, "input");
        if (in.pause) paused = !paused;
        if (in.restart) restart();
    }

    void applyScript() {
        script.due(match->time(), [&](const ScriptEvent& e) {
            switch (e.kind) {
                case ScriptEvent::Kind::Command: command(e.character, e.command, "script"); break;
                case ScriptEvent::Kind::Style: requestPolicy(e.style, depth, "script"); break;
                case ScriptEvent::Kind::Depth: requestPolicy(style, e.depth, "script"); break;
            }
        });
    }

    void advance(double dt) override {
        for (int n = steps.take(dt); n > 0 && !match->finished(); --n) {
            swapPolicy();
            applyScript();
            match->step();
        }
        swapPolicy();
    }

    void pose() override {
        const double t = match->time();
        const auto& scene = match->scene();
        const int n = match->size();
        cast.pose(t, [&](int c) {
            if (n > cli::SceneStage::kAutoLabels && c != kUser) return std::string();
            const int i = scene.instanceAt(c, t);
            if (i < 0) return std::string();
            const auto& inst = scene.characters[static_cast<std::size_t>(c)].track[static_cast<std::size_t>(i)];
            return scene.characters[static_cast<std::size_t>(c)].name + ": " + lib().action(inst.action).label() + (inst.forced ? " (hit)" : "");
        });
        follow.to(render::characterBounds(cast.shown()));
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

Duel::~Duel() { impl_->build.stop(); }

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
        m.script.events = std::move(*s);
    }
    if (Status st = m.openProject(options.project, options.quiet); !st) return st.error();
    auto rules = igraph::Rules::make(m.session->library);
    if (!rules) return makeError(options.project + ": " + rules.error().message);
    m.rules = *rules;
    if (Status st = m.acquireGraph(); !st) return st.error();
    if (m.graph) (void)m.start();
    return d;
}

Status Duel::update(double dt, GLFWwindow* window, bool keyboard) { return impl_->frame(dt, window, keyboard); }

std::span<const render::CharacterInstance> Duel::shown() const { return impl_->cast.shown(); }
render::Bounds Duel::framing() const {
    const render::Bounds b = render::characterBounds(impl_->cast.shown());
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
        m.build.panel("the graph");
        return;
    }
    const auto landed = m.landedBySide();
    const auto blocked = m.blockedBySide();
    const int score = landed[0] - landed[1];
    if (m.timeRow("match", m.match->time())) return;
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
    if (!m.input.gamepad().empty()) ImGui::Text("gamepad: %s", m.input.gamepad().c_str());
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
        const auto l = m.match->landed()[static_cast<std::size_t>(c)];
        characterRow(c, m.cast.tints()[static_cast<std::size_t>(c)],
                     scene.characters[static_cast<std::size_t>(c)].name + "  (" + std::to_string(l) + " landed)");
    }
    if (n > 64) ImGui::Text("... and %d more", n - 64);
}

Status Duel::writeLog() const {
    const Impl& m = *impl_;
    if (m.opt.log.empty()) return {};
    nlohmann::ordered_json j = m.logHead(m.opt.characters == 2 ? "duel" : "teams", m.opt.project);
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
            const glm::vec3 t = m.cast.tints()[static_cast<std::size_t>(c)];
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
