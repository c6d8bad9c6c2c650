// Matches driven by the Interaction Graph (SPEC 3.5): table look-up per
// decision, user commands, two teams each fighting its closest enemy.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_map>

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include "fray/igraph/enemy_index.h"
#include "fray/igraph/runtime.h"
#include "game.h"

namespace fray::igraph {

using detail::Body;
using sim::ActionLibrary;

namespace {

struct CommandName {
    Command c;
    const char* name;
};
constexpr CommandName kCommands[] = {{Command::Forward, "forward"},     {Command::Back, "back"},   {Command::TurnLeft, "turn-left"},
                                     {Command::TurnRight, "turn-right"}, {Command::Punch, "punch"}, {Command::Kick, "kick"},
                                     {Command::Dodge, "dodge"},         {Command::Avoid, "avoid"}};

constexpr float kStrikeReach = 2.5f;  // m pelvis to pelvis: farther bodies cannot land a blow

}  // namespace

Result<Command> parseCommand(std::string_view name) {
    for (const auto& c : kCommands) {
        if (name == c.name) return c.c;
    }
    return makeError("'" + std::string(name) + "' is not a command (forward, back, turn-left, turn-right, punch, kick, dodge, avoid)");
}

const char* commandName(Command c) {
    for (const auto& k : kCommands) {
        if (k.c == c) return k.name;
    }
    return "none";
}

bool fulfils(const ActionLibrary& lib, int action, const InteractionState& s, Command c) {
    const auto& a = lib.action(action);
    const bool moving = !a.is(sim::kAttack | sim::kDefence | sim::kReactive);
    switch (c) {
        case Command::Punch: return a.is(sim::kPunch);
        case Command::Kick: return a.is(sim::kKick);
        case Command::Dodge: return a.has("dodge") || (a.is(sim::kAvoid) && !a.has("avoid"));
        case Command::Avoid: return a.has("avoid") || a.is(sim::kBlock);
        case Command::Forward:
        case Command::Back: {
            const double along = static_cast<double>(glm::dot(a.end.pos, sim::headingVector(s.thetaA)));
            return moving && (c == Command::Forward ? along >= 0.15 : along <= -0.15);
        }
        case Command::TurnLeft: return moving && a.end.heading >= 0.3;
        case Command::TurnRight: return moving && a.end.heading <= -0.3;
        case Command::None: return false;
    }
    return false;
}

Result<std::vector<TimedCommand>> parseCommands(std::string_view text, std::string_view fileName) {
    const std::string name(fileName);
    const auto j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return makeError(name + ": not a JSON object");
    if (!j.contains("version") || !j["version"].is_number_integer() || j["version"].get<int>() != 1) {
        return makeError(name + ": /version: must be 1");
    }
    if (!j.contains("commands") || !j["commands"].is_array()) return makeError(name + ": /commands: missing or not an array");
    std::vector<TimedCommand> out;
    for (std::size_t k = 0; k < j["commands"].size(); ++k) {
        const auto& e = j["commands"][k];
        const std::string path = name + ": /commands/" + std::to_string(k);
        if (!e.is_object()) return makeError(path + ": must be an object");
        TimedCommand c;
        if (!e.contains("time") || !e["time"].is_number() || !std::isfinite(e["time"].get<double>()) || e["time"].get<double>() < 0) {
            return makeError(path + "/time: must be a finite number of seconds >= 0");
        }
        c.time = e["time"].get<double>();
        if (!e.contains("command") || !e["command"].is_string()) return makeError(path + "/command: must be a string");
        auto cmd = parseCommand(e["command"].get<std::string>());
        if (!cmd) return makeError(path + "/command: " + cmd.error().message);
        c.command = *cmd;
        if (e.contains("character")) {
            if (!e["character"].is_number_integer() || e["character"].get<std::int64_t>() < 0 || e["character"].get<std::int64_t>() > 100000) {
                return makeError(path + "/character: must be a character index >= 0");
            }
            c.character = e["character"].get<int>();
        }
        out.push_back(c);
    }
    std::stable_sort(out.begin(), out.end(), [](const TimedCommand& a, const TimedCommand& b) { return a.time < b.time; });
    return out;
}

std::vector<sim::RootXf> duelStarts(double dist, std::uint64_t seed, double jitter) {
    detail::Rng rng{seed * 0x2545F4914F6CDD1Dull + 7};
    const double r = dist + rng.uniform(-jitter, jitter);
    const double a0 = rng.uniform(-jitter, jitter) * 20 * std::numbers::pi / 180, a1 = rng.uniform(-jitter, jitter) * 20 * std::numbers::pi / 180;
    return {{{0.0f, 0.0f}, sim::wrapAngle(std::numbers::pi / 2 + a0)}, {{static_cast<float>(r), 0.0f}, sim::wrapAngle(-std::numbers::pi / 2 + a1)}};
}

std::vector<sim::RootXf> teamStarts(int n, std::uint64_t seed, double jitter) {
    detail::Rng rng{seed * 0x2545F4914F6CDD1Dull + 11};
    std::vector<sim::RootXf> out;
    const int perTeam = (n + 1) / 2;
    const int cols = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(perTeam)))));
    for (int i = 0; i < n; ++i) {
        const int side = i % 2, k = i / 2;
        const int row = k / cols, col = k % cols;
        const float x = static_cast<float>(1.6 * col + rng.uniform(-jitter, jitter));
        const float z = static_cast<float>((0.7 + 1.6 * row + rng.uniform(-jitter, jitter)) * (side == 0 ? -1 : 1));
        const double h = (side == 0 ? 0.0 : std::numbers::pi) + rng.uniform(-jitter, jitter) * 20 * std::numbers::pi / 180;
        out.push_back({{x, z}, sim::wrapAngle(h)});
    }
    return out;
}

struct Match::Impl {
    std::shared_ptr<const Rules> rules;
    std::shared_ptr<const Graph> graph;
    std::vector<FighterSpec> fighters;
    std::vector<Body> bodies;
    std::vector<int> opponent;
    std::vector<Command> pending;
    std::vector<double> pendingUntil;
    sim::Scene scene;
    MatchStats stats;
    double t = 0;
    EnemyIndex index;        // the "here" positions, for the closest-enemy and blow searches
    std::vector<int> sides;  // each body's side
    std::vector<int> launches;  // launches of each body since the index was built
    double window = 0;          // s: decisions this step are at most this far from the index's time
    int maxLaunches = 0;
    bool refine = false;        // MatchOptions::refine
    bool measure = false;       // MatchOptions::measure
    double vmax = -1, jump = 0;  // the library's fastest pelvis (m/s), largest step between actions (m)

    const ActionLibrary& lib() const { return rules->library(); }
    glm::vec2 pos(int c, double at) const { return bodies[static_cast<std::size_t>(c)].placement(lib(), at).pos; }

    std::vector<glm::vec2> here;  // every pelvis at the step's start
    std::vector<std::pair<double, int>> due;  // decisions of this step

    // How fast any pelvis can move: its placement is a heading-rotated
    // polyline through the action's samples (speed <= the longest segment
    // times the sample rate), and a launch may step by the gap between the
    // old action's last sample and its end placement plus the new one's first sample.
    void measureLibrary() {
        double v = 0, j = 0;
        for (int a = 0; a < lib().size(); ++a) {
            const auto& act = lib().action(a);
            glm::vec2 prev = lib().rootAt(a, 0.0).pos;
            for (int s = 1; s < act.sampleCount; ++s) {
                const glm::vec2 q = lib().rootAt(a, static_cast<double>(s) / sim::kSampleRate).pos;
                v = std::max(v, static_cast<double>(glm::length(q - prev)) * sim::kSampleRate);
                prev = q;
            }
            j = std::max(j, static_cast<double>(glm::length(lib().rootAt(a, 0.0).pos)) +
                                static_cast<double>(glm::length(act.end.pos - lib().rootAt(a, 1e9).pos)));
        }
        vmax = v * 1.01 + 1e-3, jump = j * 1.01 + 1e-4;
    }

    void updateSlack() {
        // A body not launched since the build is within vmax * window of "here"; each launch adds
        // another window of motion and a jump.
        const double w = window + 1e-6;
        index.setSlack((1 + maxLaunches) * vmax * w + maxLaunches * jump + 1e-4);
    }

    void rebuildGrid() {
        if (vmax < 0) measureLibrary();
        const auto n = bodies.size();
        here.resize(n);
        sides.resize(n);
        for (std::size_t c = 0; c < n; ++c) here[c] = pos(static_cast<int>(c), t), sides[c] = fighters[c].side;
        index.build(&here, &sides);
        launches.assign(n, 0);
        maxLaunches = 0;
        window = 0;
        for (const auto& b : bodies) {
            if (b.end <= t + 1e-9) window = std::max(window, std::fabs(t - b.end));
        }
        updateSlack();
    }

    // The closest enemy (ties: the lower index): see enemy_index.h for the rule.
    int closestEnemy(int c, double at) const {
        return index.closest(pos(c, at), fighters[static_cast<std::size_t>(c)].side, [&](int o) { return pos(o, at); });
    }

    // A static target stays where it is: the idle action of its Next set
    // that moves it least (else a block, else anything but an attack).
    int staticChoice(int set) const {
        const auto& next = rules->nextSet(set);
        int best = -1;
        double bestMove = std::numeric_limits<double>::infinity();
        for (int pass = 0; pass < 3 && best < 0; ++pass) {
            for (int a : next) {
                const auto& la = lib().action(a);
                if (la.is(sim::kAttack) || (pass == 0 && !la.is(sim::kIdle)) || (pass == 1 && !la.is(sim::kBlock))) continue;
                const double move = static_cast<double>(glm::length(la.end.pos)) + std::fabs(la.end.heading);
                if (move < bestMove) bestMove = move, best = a;
            }
        }
        return best >= 0 ? best : next.front();
    }

    // One edge's action launched from the real bodies of c (against opp) at
    // `at` and played until the next decision: the bodies then, the blows,
    // who decides next and the graph state that decision falls in (-1: off
    // the graph unless `nearest`).
    struct EdgeRun {
        std::array<Body, 2> bodies;
        detail::Outcome outcome;
        double end = 0;
        int chooser = 0;
        int to = -1;
    };
    EdgeRun runEdge(int c, int opp, double at, int action, bool nearest) const {
        EdgeRun r;
        r.bodies = {bodies[static_cast<std::size_t>(c)], bodies[static_cast<std::size_t>(opp)]};
        detail::launch(lib(), r.bodies[0], action, at);
        r.end = detail::advanceDuel(*rules, r.bodies, at, r.outcome);
        r.chooser = detail::chooser(r.bodies);
        const auto un = static_cast<std::size_t>(r.chooser);
        r.to = graph->find(detail::stateOf(*rules, r.bodies[un], r.bodies[1 - un], r.end), nearest);
        return r;
    }

    // MatchOptions::refine: the edges of the state found, each simulated from
    // the real bodies to the next decision (as the graph's edges were from the
    // state's mean), scored by the policy's reward with the real blows and
    // geometry plus gamma V below of the state that decision falls in.
    int refinedChoice(int c, int opp, double at, int state, const Policy& policy) {
        const auto& w = policy.weights;
        int bestAction = -1;
        double bestValue = -std::numeric_limits<double>::infinity();
        for (const Edge* e = graph->edgesBegin(state); e != graph->edgesEnd(state); ++e) {
            const EdgeRun run = runEdge(c, opp, at, e->action(), false);
            const auto& b = run.bodies;
            const auto& oc = run.outcome;
            const int nc = run.chooser, to = run.to;
            const double t1 = run.end;
            if (to < 0) continue;
            const InteractionState mine = detail::stateOf(*rules, b[0], b[1], t1);
            const double d = mine.r - w.dP;
            const auto ut = static_cast<std::size_t>(to);
            const double below = nc == 0 ? (policy.mineBelow.empty() ? 0.0 : policy.mineBelow[ut]) : (policy.theirsBelow.empty() ? 0.0 : policy.theirsBelow[ut]);
            const double v = -w.wTheta * mine.thetaA * mine.thetaA - w.wD * d * d + w.wA * static_cast<double>(oc.given[0]) -
                             w.wR * static_cast<double>(oc.received[0]) +
                             w.discount(static_cast<int>(std::lround(std::min(t1 - at, 8.5) * sim::kSampleRate))) * below;
            if (v > bestValue) bestValue = v, bestAction = e->action();
        }
        return bestAction;
    }

    // MatchOptions::measure: the state's stored edges against the same
    // actions simulated from the real bodies.
    void measurePrediction(int c, int opp, double at, const InteractionState& s, int state, bool within, const Policy* policy) {
        auto& m = stats.prediction;
        if (graph->edgesBegin(state) == graph->edgesEnd(state)) return;
        ++m.lookups;
        const auto& st = graph->states[static_cast<std::size_t>(state)];
        if (within) {
            ++m.within;
            m.distanceSum += distance(s, st, graph->options.scale);
        }
        m.drSum += std::fabs(s.r - st.r);
        m.dThetaSum += std::fabs(sim::wrapAngle(s.thetaA - st.thetaA)) + std::fabs(sim::wrapAngle(s.thetaB - st.thetaB));
        const std::int32_t chosenEdge =
            policy && static_cast<std::size_t>(state) < policy->best.size() ? policy->best[static_cast<std::size_t>(state)] : -1;
        for (const Edge* e = graph->edgesBegin(state); e != graph->edgesEnd(state); ++e) {
            const EdgeRun run = runEdge(c, opp, at, e->action(), true);
            const auto& oc = run.outcome;
            const int nc = run.chooser, to = run.to;
            const bool gp = e->givenQ > 0, gr = oc.given[0] > 0.05f, rp = e->receivedQ > 0, rr = oc.received[0] > 0.05f;
            ++m.edges;
            m.givenPredicted += gp, m.givenReal += gr, m.givenBoth += gp && gr;
            m.receivedPredicted += rp, m.receivedReal += rr, m.receivedBoth += rp && rr;
            m.sameTarget += to == e->to && (nc == 0) == e->sameChooser();
            if (static_cast<std::int32_t>(e - graph->edges.data()) == chosenEdge) {
                ++m.chosen;
                m.chosenGivenPredicted += gp, m.chosenGivenReal += gr, m.chosenReceivedPredicted += rp, m.chosenReceivedReal += rr;
            }
        }
    }

    // Character c as tree expansion sees it at a decision: its body and its last six actions, newest first.
    sim::DuelSideState sideOf(int c) const {
        const auto uc = static_cast<std::size_t>(c);
        const Body& b = bodies[uc];
        sim::DuelSideState s;
        s.action = b.action, s.start = b.start, s.offset = b.offset, s.end = b.end, s.root = b.root;
        s.attackDone = b.spent, s.reacting = b.reacting;
        const auto& track = scene.characters[uc].track;
        for (auto it = track.rbegin(); it != track.rend() && s.recent.size() < 6; ++it) s.recent.push_back(it->action);
        return s;
    }
    // Character c's choice by tree expansion against `opp`, from the bodies as they are at `at`
    // (a planner error, which valid bodies do not give, counts as a fallback to standing).
    int treeChoice(int c, int opp, double at, int set) {
        auto a = fighters[static_cast<std::size_t>(c)].tree->decide(sideOf(c), sideOf(opp), at, &stats.tree);
        if (a) return *a;
        ++stats.fallbacks;
        ++scene.stats.fallbacks;
        ++scene.characters[static_cast<std::size_t>(c)].fallbacks;
        return staticChoice(set);
    }

    // One decision of character c at time `at` (its action's end).
    int decide(int c, double at) {
        const auto uc = static_cast<std::size_t>(c);
        const Body& me = bodies[uc];
        const int set = rules->nextSetOf(me.action);
        const auto searchStart = std::chrono::steady_clock::now();
        const int opp = closestEnemy(c, at);
        stats.enemySeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - searchStart).count();
        opponent[uc] = opp;
        ++stats.decisions;
        const Command cmd = pending[uc] != Command::None && at <= pendingUntil[uc] ? pending[uc] : Command::None;
        if (opp < 0) return staticChoice(set);
        const InteractionState s = detail::stateOf(*rules, me, bodies[static_cast<std::size_t>(opp)], at);
        const auto& f = fighters[uc];
        int state = -1;
        const Policy* policy = f.policy.get();
        if (f.mind == Mind::Graph || cmd != Command::None) {
            ++stats.lookups;
            state = graph->find(s, true);
            const bool within = state >= 0;
            if (state < 0) ++stats.offGraph, state = graph->find(s, false);
            if (measure && f.mind == Mind::Graph && state >= 0) measurePrediction(c, opp, at, s, state, within, policy);
        }
        if (cmd != Command::None) {
            int bestAction = -1;
            double bestValue = -std::numeric_limits<double>::infinity();
            if (state >= 0) {
                for (const Edge* e = graph->edgesBegin(state); e != graph->edgesEnd(state); ++e) {
                    if (!fulfils(lib(), e->action(), s, cmd)) continue;
                    const double v = policy && !policy->mineBelow.empty() ? policy->edgeValue(*graph, *e) : edgeReward(*graph, *e, RewardWeights{}, true);
                    if (v > bestValue) bestValue = v, bestAction = e->action();
                }
            }
            if (bestAction < 0) {
                // Not in the graph from here: the first action of that kind the character can launch.
                for (int a : rules->nextSet(set)) {
                    if (fulfils(lib(), a, s, cmd)) {
                        bestAction = a;
                        break;
                    }
                }
            }
            if (bestAction >= 0) {
                pending[uc] = Command::None;
                ++stats.commandsTaken;
                return bestAction;
            }
            // None can start now (a punch from standing idle): a way into a
            // Next set that has one, the command kept for the decision after.
            for (int a : rules->nextSet(set)) {
                for (int b : rules->nextSet(rules->nextSetOf(a))) {
                    if (fulfils(lib(), b, s, cmd)) {
                        pendingUntil[uc] = std::max(pendingUntil[uc], at + lib().action(a).duration + 1e-9);
                        return a;
                    }
                }
            }
        }
        if (f.mind == Mind::Tree && f.tree) return treeChoice(c, opp, at, set);
        if (f.mind == Mind::Static || !policy) return staticChoice(set);
        if (state >= 0 && static_cast<std::size_t>(state) < policy->best.size() && policy->best[static_cast<std::size_t>(state)] >= 0) {
            if (refine) {
                if (const int a = refinedChoice(c, opp, at, state, *policy); a >= 0) return a;
            }
            const int a = graph->edges[static_cast<std::size_t>(policy->best[static_cast<std::size_t>(state)])].action();
            // The state found may belong to a neighbouring frame bucket: its Next set is the same by construction.
            return a;
        }
        ++stats.fallbacks;
        ++scene.stats.fallbacks;
        ++scene.characters[uc].fallbacks;
        return staticChoice(set);
    }

    void launchAt(int c, int action, double at) {
        auto& b = bodies[static_cast<std::size_t>(c)];
        detail::launch(lib(), b, action, at);
        if (static_cast<std::size_t>(c) < launches.size()) {
            maxLaunches = std::max(maxLaunches, ++launches[static_cast<std::size_t>(c)]);
            updateSlack();
        }
        scene.characters[static_cast<std::size_t>(c)].track.push_back({action, at, 0.0, b.end, b.root, false, false});
    }

    void step(double dt, double duration) {
        const double t1 = std::min(t + dt, duration);
        rebuildGrid();
        const auto start = std::chrono::steady_clock::now();
        // Decisions in time order (ties: character order), each at its action's end.
        // A queue of (end, index), earliest first: only the body just launched changes its end.
        auto later = [](const std::pair<double, int>& x, const std::pair<double, int>& y) { return x > y; };
        due.clear();
        for (int c = 0; c < static_cast<int>(bodies.size()); ++c) {
            if (bodies[static_cast<std::size_t>(c)].end <= t + 1e-9) due.emplace_back(bodies[static_cast<std::size_t>(c)].end, c);
        }
        std::make_heap(due.begin(), due.end(), later);
        while (!due.empty()) {
            std::pop_heap(due.begin(), due.end(), later);
            const auto [at, who] = due.back();
            due.pop_back();
            launchAt(who, decide(who, at), at);
            if (const double e = bodies[static_cast<std::size_t>(who)].end; e <= t + 1e-9) {
                due.emplace_back(e, who);
                std::push_heap(due.begin(), due.end(), later);
            }
        }
        stats.decideSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // Blows within [t, t1] between nearby enemies, earliest first: only
        // attackers whose clip is in its active window then, in parallel
        // (each attacker's list apart, joined in order).
        std::vector<int> attackers;
        for (int a = 0; a < static_cast<int>(bodies.size()); ++a) {
            const auto& ab = bodies[static_cast<std::size_t>(a)];
            const auto& act = lib().action(ab.action);
            if (ab.spent || !act.is(sim::kAttack) || act.effector < 0) continue;
            const double s0 = ab.clipTime(t) * sim::kSampleRate, s1 = ab.clipTime(t1) * sim::kSampleRate;
            if (s1 < act.activeBegin - 1 || s0 > act.activeEnd + 1) continue;
            attackers.push_back(a);
        }
        std::vector<std::vector<detail::Blow>> found(attackers.size());
        auto search = [&](std::size_t k) {
            const int a = attackers[k];
            const auto& ab = bodies[static_cast<std::size_t>(a)];
            const glm::vec2 p = here[static_cast<std::size_t>(a)];
            index.forNear(enemyCellOf(p.x), enemyCellOf(p.y), 1, [&](int d) {
                if (fighters[static_cast<std::size_t>(d)].side == fighters[static_cast<std::size_t>(a)].side) return;
                const glm::vec2 diff = here[static_cast<std::size_t>(d)] - p;
                if (glm::dot(diff, diff) > kStrikeReach * kStrikeReach) return;
                const auto& db = bodies[static_cast<std::size_t>(d)];
                const auto h = rules->engine().strike(ab.playing(), ab.spent, db.playing(), db.reacting, t, t1);
                if (h.time >= 0) found[k].push_back({h.time, a, d, h});
            });
        };
        if (attackers.size() > 16) {
            tbb::parallel_for(std::size_t{0}, attackers.size(), search);
        } else {
            for (std::size_t k = 0; k < attackers.size(); ++k) search(k);
        }
        std::vector<detail::Blow> blows;
        for (auto& f : found) blows.insert(blows.end(), f.begin(), f.end());
        std::sort(blows.begin(), blows.end(), [](const detail::Blow& x, const detail::Blow& y) {
            if (x.time != y.time) return x.time < y.time;
            if (x.attacker != y.attacker) return x.attacker < y.attacker;
            return x.defender < y.defender;
        });
        std::vector<char> changed(bodies.size(), 0);
        for (const auto& bl : blows) {
            const auto ua = static_cast<std::size_t>(bl.attacker), ud = static_cast<std::size_t>(bl.defender);
            // A body hit (or whose attack landed) earlier in this step is judged again next step.
            if (changed[ua] || changed[ud] || bodies[ua].spent || bodies[ud].reacting) continue;
            const auto reaction = detail::applyBlow(*rules, bodies[ua], bodies[ud], bl.hit, bl.time);
            const double impulse = sim::detail::InteractionEngine::impulse(bl.hit);
            scene.hits.push_back({bl.time, bl.attacker, bl.defender, bodies[ua].action, bl.hit.effector, bl.hit.target, bl.hit.speed,
                                  impulse, bl.hit.blocked});
            changed[ua] = 1;
            if (reaction.action >= 0) {
                sim::detail::cutIntoReaction(scene.characters[ud].track, bl.time, reaction);
                ++stats.forced;
                ++scene.stats.forced;
                changed[ud] = 1;
            }
        }
        t = t1;
    }
};

Match::Match(std::shared_ptr<const Rules> rules, std::shared_ptr<const Graph> graph, std::vector<FighterSpec> fighters, MatchOptions options)
    : impl_(std::make_unique<Impl>()), options_(std::move(options)) {
    auto& m = *impl_;
    m.rules = std::move(rules);
    m.graph = std::move(graph);
    m.fighters = std::move(fighters);
    m.refine = options_.refine;
    m.measure = options_.measure;
    const auto& lib = m.rules->library();
    m.scene.duration = options_.duration;
    m.scene.seed = options_.seed;
    m.scene.spec = options_.record;
    detail::Rng rng{options_.seed ^ 0xB0C5ull};
    for (std::size_t c = 0; c < m.fighters.size(); ++c) {
        const auto& f = m.fighters[c];
        sim::SceneCharacter sc;
        sc.name = f.name;
        sc.side = f.side;
        sc.preset = f.style;
        sc.depth = f.mind == Mind::Tree && f.tree ? f.tree->depth() : f.policy ? f.policy->depth : 0;
        // Each starts in an idle action (seeded), at a seeded point of it, so the team does not move in step.
        const int idle = m.rules->idle()[rng.below(m.rules->idle().size())];
        const double clip = rng.uniform(0.0, 0.5 * lib.action(idle).duration);
        Body b = detail::bodyAt(lib, idle, clip, f.start, 0.0);
        sc.track.push_back({idle, 0.0, clip, b.end, b.root, false, false});
        m.scene.characters.push_back(std::move(sc));
        m.bodies.push_back(b);
    }
    m.opponent.assign(m.fighters.size(), -1);
    m.pending.assign(m.fighters.size(), Command::None);
    m.pendingUntil.assign(m.fighters.size(), 0.0);
}

Match::~Match() = default;

int Match::size() const { return static_cast<int>(impl_->bodies.size()); }
double Match::time() const { return impl_->t; }
const sim::Scene& Match::scene() const { return impl_->scene; }
const MatchStats& Match::stats() const { return impl_->stats; }
int Match::opponent(int c) const { return impl_->opponent[static_cast<std::size_t>(c)]; }

void Match::command(int c, Command cmd) {
    if (c < 0 || c >= size()) return;
    impl_->pending[static_cast<std::size_t>(c)] = cmd;
    // Its next decision always sees it; later ones within commandHold too.
    impl_->pendingUntil[static_cast<std::size_t>(c)] = std::max(impl_->t + options_.commandHold, impl_->bodies[static_cast<std::size_t>(c)].end + 1e-9);
    ++impl_->stats.commands;
}

void Match::setPolicy(int c, std::shared_ptr<const Policy> policy) {
    if (c < 0 || c >= size() || !policy) return;
    impl_->fighters[static_cast<std::size_t>(c)].policy = std::move(policy);
    impl_->scene.characters[static_cast<std::size_t>(c)].depth = impl_->fighters[static_cast<std::size_t>(c)].policy->depth;
}

void Match::step() {
    if (!finished()) impl_->step(options_.step, options_.duration);
}

Status Match::run(const std::vector<TimedCommand>& commands, const ProgressFn& progress) {
    std::size_t next = 0;
    int steps = 0;
    while (!finished()) {
        while (next < commands.size() && commands[next].time <= time() + 1e-9) {
            if (commands[next].character >= size()) {
                return makeError("command " + std::to_string(next) + " is for character " + std::to_string(commands[next].character) +
                                 ", the match has " + std::to_string(size()));
            }
            command(commands[next].character, commands[next].command);
            ++next;
        }
        step();
        if (++steps % 60 == 0 && !reportProgress(progress, time() / options_.duration, "match")) return cancelled();
    }
    // Close every track at the end of the match.
    for (auto& c : impl_->scene.characters) {
        if (!c.track.empty()) c.track.back().end = std::min(c.track.back().end, std::max(options_.duration, c.track.back().start));
    }
    return {};
}

std::vector<int> Match::landed() const {
    std::vector<int> out(impl_->bodies.size(), 0);
    for (const auto& h : impl_->scene.hits) {
        if (!h.blocked) ++out[static_cast<std::size_t>(h.attacker)];
    }
    return out;
}

}  // namespace fray::igraph
