// Take scripts: which actions a take chains, in what order. Every take first
// performs each action kind it owns once (a shuffled "deck"), then picks
// actions at random until its length is reached, steering the actor back
// toward the origin so takes stay in a capture-volume-sized area.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "actions.h"
#include "fray/demo/demo_actor.h"
#include "rig.h"

namespace fray::demo {

using detail::Builder;
using detail::Gait;
using detail::Mode;
using glm::dvec3;

std::string_view toString(Style style) {
    switch (style) {
        case Style::Energetic: return "energetic";
        case Style::Tired: return "tired";
        case Style::Neutral: break;
    }
    return "neutral";
}

std::string_view toString(TakeKind kind) {
    switch (kind) {
        case TakeKind::ShadowBoxing: return "shadow_boxing";
        case TakeKind::RunningAround: return "running_around";
        case TakeKind::Falls: return "falls";
        case TakeKind::Carrying: return "carrying";
        case TakeKind::Football: return "football";
        case TakeKind::CarryingEnd: return "carrying_end";
        case TakeKind::Walking: break;
    }
    return "walking";
}

const std::vector<std::string>& actionKinds() {
    static const std::vector<std::string> kinds = [] {
        std::vector<std::string> v;
        for (const auto& a : detail::actionTable()) v.emplace_back(a.name);
        return v;
    }();
    return kinds;
}

namespace {

struct DefaultTake {
    const char* name;
    TakeKind kind;
    Style style;
    double seconds;
};
constexpr DefaultTake kDefaultTakes[] = {
    {"shadowbox_energetic", TakeKind::ShadowBoxing, Style::Energetic, 120.0},
    {"shadowbox_tired", TakeKind::ShadowBoxing, Style::Tired, 120.0},
    {"running_around", TakeKind::RunningAround, Style::Neutral, 60.0},
    {"falls", TakeKind::Falls, Style::Energetic, 75.0},
    {"carrying", TakeKind::Carrying, Style::Neutral, 60.0},
    {"walking", TakeKind::Walking, Style::Neutral, 60.0},
};
// The football set: a runner cutting past imagined tacklers and diving into
// tackles, two takes so the cuts and dives come in several variants.
constexpr DefaultTake kFootballTakes[] = {
    {"football_1", TakeKind::Football, Style::Neutral, 90.0},
    {"football_2", TakeKind::Football, Style::Neutral, 90.0},
};
// The carry set: one end of a long box, two takes (two captures to pair).
constexpr DefaultTake kCarryTakes[] = {
    {"carry_end_1", TakeKind::CarryingEnd, Style::Neutral, 60.0},
    {"carry_end_2", TakeKind::CarryingEnd, Style::Neutral, 60.0},
};

// ---- helpers -----------------------------------------------------------------

double distanceFromOrigin(const Builder& b) { return glm::length(b.base(b.now())); }

// Angle from the actor's heading to the origin (positive: origin is to the left).
double bearingToOrigin(const Builder& b) {
    const double t = b.now();
    const dvec3 p = b.base(t);
    if (glm::length(p) < 1e-6) return 0.0;
    const double want = std::atan2(-p.x, -p.z);
    double d = want - b.heading(t);
    d = std::remainder(d, 2 * 3.14159265358979323846);
    return d;
}

// Position of the origin in the heading frame (x left, z forward).
dvec3 originInHeadingFrame(const Builder& b) {
    const double t = b.now();
    return glm::inverse(detail::rotY(b.heading(t))) * (-b.base(t));
}

// ---- shadow boxing -------------------------------------------------------------

const std::vector<std::string>& fightDeck() {
    static const std::vector<std::string> deck = {
        "jab", "cross", "hook_left", "hook_right", "uppercut_left", "uppercut_right", "front_kick",
        "roundhouse_left", "roundhouse_right", "knee_strike", "block_high", "block_low", "parry", "slip_left",
        "slip_right", "duck", "sway_back", "step_forward", "step_back", "step_left", "step_right", "pivot_left",
        "pivot_right", "guard_idle", "head_snap", "body_stagger", "knocked_back", "knocked_down"};
    return deck;
}

void performFight(Builder& b, const std::string& name) {
    using namespace detail;
    static const std::map<std::string, std::function<void(Builder&)>> table = {
        {"jab", jab}, {"cross", cross},
        {"hook_left", [](Builder& x) { hook(x, 0); }}, {"hook_right", [](Builder& x) { hook(x, 1); }},
        {"uppercut_left", [](Builder& x) { uppercut(x, 0); }}, {"uppercut_right", [](Builder& x) { uppercut(x, 1); }},
        {"front_kick", frontKick},
        {"roundhouse_left", [](Builder& x) { roundhouse(x, 0); }},
        {"roundhouse_right", [](Builder& x) { roundhouse(x, 1); }},
        {"knee_strike", kneeStrike}, {"block_high", blockHigh}, {"block_low", blockLow}, {"parry", parry},
        {"slip_left", [](Builder& x) { slip(x, 0); }}, {"slip_right", [](Builder& x) { slip(x, 1); }},
        {"duck", duck}, {"sway_back", swayBack},
        {"step_forward", [](Builder& x) { guardStep(x, 0); }}, {"step_back", [](Builder& x) { guardStep(x, 1); }},
        {"step_left", [](Builder& x) { guardStep(x, 2); }}, {"step_right", [](Builder& x) { guardStep(x, 3); }},
        {"pivot_left", [](Builder& x) { pivot(x, 0); }}, {"pivot_right", [](Builder& x) { pivot(x, 1); }},
        {"guard_idle", [](Builder& x) {
             const bool tired = x.sp.style == Style::Tired;
             guardIdle(x, tired ? x.rng.uniform(1.5, 3.0) : x.rng.uniform(0.8, 1.8));
         }},
        {"head_snap", headSnap}, {"body_stagger", bodyStagger}, {"knocked_back", knockedBack},
        {"knocked_down", knockedDown},
    };
    table.at(name)(b);
}

// Footwork that keeps the fighter near the origin and facing it roughly.
std::string chooseFootwork(Builder& b) {
    const dvec3 o = originInHeadingFrame(b);
    const double bearing = bearingToOrigin(b);
    if (distanceFromOrigin(b) > 1.2) {
        if (std::abs(bearing) > 1.2) return bearing > 0 ? "pivot_left" : "pivot_right";
        if (std::abs(o.x) > std::abs(o.z)) return o.x > 0 ? "step_left" : "step_right";
        return o.z > 0 ? "step_forward" : "step_back";
    }
    static const char* moves[] = {"step_forward", "step_back", "step_left", "step_right", "pivot_left", "pivot_right"};
    return moves[b.rng.below(6)];
}

std::string chooseFight(Builder& b) {
    static const char* attacks[] = {"jab", "jab", "cross", "hook_left", "hook_right", "uppercut_left",
                                    "uppercut_right", "front_kick", "roundhouse_left", "roundhouse_right",
                                    "knee_strike", "jab", "cross"};
    static const char* defences[] = {"block_high", "block_low", "parry", "slip_left", "slip_right", "duck", "sway_back"};
    static const char* reactions[] = {"head_snap", "body_stagger", "knocked_back"};
    const double r = b.rng.uniform();
    if (r < 0.45) return attacks[b.rng.below(13)];
    if (r < 0.70) return defences[b.rng.below(7)];
    if (r < 0.86) return chooseFootwork(b);
    if (r < 0.96) return "guard_idle";
    return reactions[b.rng.below(3)];
}

void shadowBoxing(Builder& b, double seconds) {
    detail::idleStand(b, b.rng.uniform(1.0, 1.6));
    detail::toGuard(b);
    std::vector<std::string> deck = fightDeck();
    b.rng.shuffle(deck);
    const double stop = seconds - 3.0;
    for (const std::string& name : deck) {
        // Keep footwork from the deck steering toward the origin when far.
        const bool footwork = name.rfind("step_", 0) == 0 || name.rfind("pivot_", 0) == 0;
        if (footwork && distanceFromOrigin(b) > 1.2) performFight(b, chooseFootwork(b));
        performFight(b, name);
    }
    while (b.now() < stop) performFight(b, chooseFight(b));
    detail::toStand(b);
    detail::idleStand(b, 1.0);
}

// ---- locomotion ----------------------------------------------------------------

// Turning rate that steers back toward the origin when far from it.
double steer(Builder& b, double radius, double rate) {
    const double bearing = bearingToOrigin(b);
    if (distanceFromOrigin(b) < radius || std::abs(bearing) < 0.35) return 0.0;
    return bearing > 0 ? rate : -rate;
}

void walkSteps(Builder& b, int n, double speed, Gait gait, const char* name, const char* turnName, double radius) {
    for (int i = 0; i < n; ++i) {
        double r = steer(b, radius, gait == Gait::Carry ? 0.5 : 0.6);
        if (r == 0.0 && b.rng.chance(0.12)) r = b.rng.chance(0.5) ? 0.55 : -0.55;
        detail::locoStep(b, gait, speed * b.rng.jitter(0.05), r, r != 0.0 ? turnName : name);
    }
}

void backpedal(Builder& b, int n) {
    for (int i = 0; i < n; ++i) detail::locoStep(b, Gait::Backpedal, -0.8 * b.rng.jitter(0.08), 0.0, "backpedal");
    detail::locoStop(b, Gait::Backpedal, "backpedal");
}

void runningAround(Builder& b, double seconds) {
    detail::idleStand(b, b.rng.uniform(1.0, 1.8));
    bool first = true;
    while (b.now() < seconds - 8.0 || first) {
        walkSteps(b, b.rng.between(2, 3), 1.3, Gait::Walk, "walk", "turn_walk", 4.0);
        if (first) detail::locoStep(b, Gait::Walk, 1.3, 0.55, "turn_walk");
        for (int i = 0; i < b.rng.between(3, 5); ++i) detail::locoStep(b, Gait::Jog, 2.3, steer(b, 4.0, 0.9), "jog");
        const int runSteps = b.rng.between(8, 16);
        for (int i = 0; i < runSteps; ++i) {
            double r = steer(b, 5.0, 1.3);
            if (first && i >= 2 && i < 6) r = 1.3;  // every take turns while running at least once
            detail::locoStep(b, Gait::Run, 3.2 * b.rng.jitter(0.05), r, r != 0.0 ? "turn_run" : "run");
        }
        for (int i = 0; i < 3; ++i) detail::locoStep(b, Gait::Jog, 2.2, steer(b, 5.0, 0.9), "jog");
        walkSteps(b, 3, 1.3, Gait::Walk, "walk", "turn_walk", 5.0);
        detail::locoStop(b, Gait::Walk, "walk");
        detail::idleStand(b, b.rng.uniform(0.8, 1.5));
        if (first || b.rng.chance(0.4)) backpedal(b, b.rng.between(3, 5));
        first = false;
    }
    detail::idleStand(b, 1.0);
}

void walking(Builder& b, double seconds) {
    detail::idleStand(b, b.rng.uniform(1.0, 1.8));
    bool first = true;
    while (b.now() < seconds - 6.0 || first) {
        const int n = b.rng.between(6, 14);
        for (int i = 0; i < n; ++i) {
            double r = steer(b, 3.5, 0.6);
            if (first && i >= 2 && i < 5) r = -0.6;
            if (r == 0.0 && b.rng.chance(0.15)) r = b.rng.chance(0.5) ? 0.6 : -0.6;
            detail::locoStep(b, Gait::Walk, 1.25 * b.rng.jitter(0.08), r, r != 0.0 ? "turn_walk" : "walk");
        }
        detail::locoStop(b, Gait::Walk, "walk");
        detail::idleStand(b, b.rng.uniform(0.8, 2.0));
        if (first || b.rng.chance(0.35)) {
            backpedal(b, b.rng.between(3, 5));
            detail::idleStand(b, b.rng.uniform(0.6, 1.2));
        }
        first = false;
    }
    detail::idleStand(b, 1.0);
}

// ---- falls ---------------------------------------------------------------------

void falls(Builder& b, double seconds) {
    detail::idleStand(b, b.rng.uniform(1.0, 1.8));
    std::vector<std::string> deck = {"fall_forward", "fall_backward", "fall_sideways", "fall_pushed", "fight"};
    b.rng.shuffle(deck);
    std::size_t i = 0;
    while (i < deck.size() || b.now() < seconds - 6.0) {
        const std::string name = i < deck.size() ? deck[i] : (b.rng.chance(0.25) ? "fight" : deck[static_cast<std::size_t>(b.rng.below(4))]);
        ++i;
        if (name == "fight") {
            detail::toGuard(b);
            detail::guardIdle(b, b.rng.uniform(0.8, 1.5));
            static const char* hits[] = {"head_snap", "body_stagger", "knocked_back"};
            performFight(b, hits[b.rng.below(3)]);
            detail::guardIdle(b, b.rng.uniform(0.6, 1.2));
            detail::knockedDown(b);
            detail::guardIdle(b, b.rng.uniform(0.6, 1.2));
            detail::toStand(b);
        } else {
            if (name == "fall_forward") detail::fallForward(b);
            else if (name == "fall_backward") detail::fallBackward(b);
            else if (name == "fall_sideways") detail::fallSideways(b);
            else detail::fallPushed(b);
            detail::getUp(b);
        }
        detail::idleStand(b, b.rng.uniform(1.0, 2.0));
        // Walk back toward the middle now and then, so falls do not drift away.
        if (distanceFromOrigin(b) > 1.5 || b.rng.chance(0.3)) {
            const double bearing = bearingToOrigin(b);
            if (std::abs(bearing) > 0.5) detail::turnInPlace(b, bearing, "turn_walk");
            walkSteps(b, b.rng.between(2, 4), 1.1, Gait::Walk, "walk", "turn_walk", 100.0);
            detail::locoStop(b, Gait::Walk, "walk");
            detail::idleStand(b, b.rng.uniform(0.6, 1.2));
        }
    }
    detail::idleStand(b, 1.0);
}

// ---- football ------------------------------------------------------------------

void runSteps(Builder& b, int n, bool forceTurn) {
    for (int i = 0; i < n; ++i) {
        double r = steer(b, 6.0, 1.3);
        if (forceTurn && i < 2) r = 1.3;
        detail::locoStep(b, Gait::Run, 3.2 * b.rng.jitter(0.05), r, r != 0.0 ? "turn_run" : "run");
    }
}

void football(Builder& b, double seconds) {
    detail::idleStand(b, b.rng.uniform(1.0, 1.6));
    bool first = true;
    while (b.now() < seconds - 10.0 || first) {
        for (int i = 0; i < 3; ++i) detail::locoStep(b, Gait::Jog, 2.3, steer(b, 6.0, 0.9), "jog");
        runSteps(b, b.rng.between(3, 5), first);
        const int cuts = first ? 2 : b.rng.between(2, 3);
        for (int c = 0; c < cuts; ++c) {
            // Cut toward the middle of the capture area when far from it.
            int side = b.rng.below(2);
            if (first) side = c % 2;
            else if (distanceFromOrigin(b) > 4.0) side = bearingToOrigin(b) > 0 ? 0 : 1;
            detail::juke(b, side);
            runSteps(b, b.rng.between(2, 4), false);
        }
        if (first || b.rng.chance(0.7)) {
            for (int i = 0; i < 2; ++i) detail::locoStep(b, Gait::Run, 3.3 * b.rng.jitter(0.03), 0.0, "run");
            detail::tackle(b);
            detail::getUp(b);
            detail::idleStand(b, b.rng.uniform(0.8, 1.4));
            double bearing = bearingToOrigin(b);
            if (first && std::abs(bearing) < 0.5) bearing = bearing >= 0 ? 0.8 : -0.8;
            if (std::abs(bearing) > 0.5) detail::turnInPlace(b, bearing, "turn_walk");
        } else {
            for (int i = 0; i < 3; ++i) detail::locoStep(b, Gait::Jog, 2.2, steer(b, 6.0, 0.9), "jog");
            walkSteps(b, 3, 1.3, Gait::Walk, "walk", "turn_walk", 6.0);
            detail::locoStop(b, Gait::Walk, "walk");
            detail::idleStand(b, b.rng.uniform(0.8, 1.4));
        }
        first = false;
    }
    detail::idleStand(b, 1.0);
}

// ---- carrying ------------------------------------------------------------------

void carrying(Builder& b, double seconds) {
    detail::idleStand(b, b.rng.uniform(1.0, 1.8));
    bool first = true;
    while (b.now() < seconds - 10.0 || first) {
        detail::pickUpBox(b);
        detail::idleStand(b, b.rng.uniform(0.4, 0.8));
        walkSteps(b, b.rng.between(3, 6), 1.1, Gait::Carry, "walk_carry", "walk_carry", 3.0);
        detail::locoStop(b, Gait::Carry, "walk_carry");
        detail::turnInPlace(b, (b.rng.chance(0.5) ? 1.0 : -1.0) * b.rng.uniform(1.3, 2.6), "turn_carry");
        walkSteps(b, b.rng.between(3, 6), 1.1, Gait::Carry, "walk_carry", "walk_carry", 3.0);
        detail::locoStop(b, Gait::Carry, "walk_carry");
        if (first || b.rng.chance(0.5)) {
            detail::handOver(b);
            detail::idleStand(b, b.rng.uniform(0.8, 1.6));
            detail::receiveBox(b);
            walkSteps(b, b.rng.between(3, 5), 1.1, Gait::Carry, "walk_carry", "walk_carry", 3.0);
            detail::locoStop(b, Gait::Carry, "walk_carry");
        }
        detail::putDown(b);
        detail::idleStand(b, b.rng.uniform(0.6, 1.2));
        const double bearing = bearingToOrigin(b);
        if (std::abs(bearing) > 0.6) detail::turnInPlace(b, bearing, "turn_walk");
        walkSteps(b, b.rng.between(3, 6), 1.25, Gait::Walk, "walk", "turn_walk", 3.0);
        detail::locoStop(b, Gait::Walk, "walk");
        detail::idleStand(b, b.rng.uniform(0.6, 1.4));
        first = false;
    }
    detail::idleStand(b, 1.0);
}

// ---- one end of a long box -------------------------------------------------------

// Lifts the end, then steps in a shuffled deck of the eleven carry-end
// moves (every move equally often), steered back toward the origin when the
// take wanders more than 3 m away.
void carryingEnd(Builder& b, double seconds) {
    using detail::CarryEndMove;
    detail::idleStand(b, b.rng.uniform(0.8, 1.2));
    detail::carryEndLift(b);
    std::vector<CarryEndMove> deck;
    while (b.now() < seconds - 1e-9 || deck.size() > 0) {
        if (deck.empty()) {
            if (b.now() >= seconds - 1e-9) break;
            deck = {CarryEndMove::Forward, CarryEndMove::Back, CarryEndMove::Left, CarryEndMove::Right,
                    CarryEndMove::TurnLeft, CarryEndMove::TurnRight, CarryEndMove::Hold, CarryEndMove::ForwardLeft,
                    CarryEndMove::ForwardRight, CarryEndMove::BackLeft, CarryEndMove::BackRight};
            b.rng.shuffle(deck);
        }
        CarryEndMove m = deck.back();
        deck.pop_back();
        if (distanceFromOrigin(b) > 3.0 && m != CarryEndMove::TurnLeft && m != CarryEndMove::TurnRight && m != CarryEndMove::Hold) {
            // The step of the four that heads most toward the origin.
            const dvec3 o = originInHeadingFrame(b);
            m = std::abs(o.z) >= std::abs(o.x) ? (o.z > 0 ? CarryEndMove::Forward : CarryEndMove::Back)
                                                : (o.x > 0 ? CarryEndMove::Left : CarryEndMove::Right);
        }
        detail::carryEndStep(b, m);
    }
}

}  // namespace

double defaultLibraryMinutes() {
    double s = 0;
    for (const auto& t : kDefaultTakes) s += t.seconds;
    return s / 60.0;
}

const std::vector<std::string>& librarySets() {
    static const std::vector<std::string> sets = {"default", "football", "carry"};
    return sets;
}

std::vector<TakeSpec> planLibrary(const LibraryOptions& options) {
    std::vector<TakeSpec> out;
    // A named set: its takes, scaled to the minutes asked for.
    auto scaled = [&](const auto& takes) {
        double total = 0;
        for (const auto& t : takes) total += t.seconds;
        const double scale = options.minutes > 0 ? options.minutes * 60.0 / total : 1.0;
        for (const auto& t : takes) out.push_back({t.name, t.kind, t.style, t.seconds * scale});
        return out;
    };
    if (options.set == "football") return scaled(kFootballTakes);
    if (options.set == "carry") return scaled(kCarryTakes);
    if (options.set != "default") return out;
    const double scale = options.minutes > 0 ? options.minutes / defaultLibraryMinutes() : 1.0;
    for (const auto& t : kDefaultTakes) out.push_back({t.name, t.kind, t.style, t.seconds * scale});
    return out;
}

std::uint64_t takeSeed(std::uint64_t librarySeed, std::string_view takeName) {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a of the name
    for (char c : takeName) {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ull;
    }
    std::uint64_t z = librarySeed + 0x9e3779b97f4a7c15ull * (h | 1);  // splitmix64 finaliser
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

std::vector<std::string> actionKindsOf(TakeKind kind) {
    switch (kind) {
        case TakeKind::ShadowBoxing: {
            std::vector<std::string> v = fightDeck();
            v.insert(v.end(), {"to_guard", "to_stand", "idle_stand"});
            return v;
        }
        case TakeKind::RunningAround:
            return {"idle_stand", "walk", "turn_walk", "jog", "run", "turn_run", "backpedal"};
        case TakeKind::Falls:
            return {"idle_stand", "fall_forward", "fall_backward", "fall_sideways", "fall_pushed", "get_up",
                    "to_guard", "guard_idle", "knocked_down", "to_stand"};
        case TakeKind::Carrying:
            return {"idle_stand", "pick_up_box", "walk_carry", "turn_carry", "hand_over", "receive", "put_down", "walk"};
        case TakeKind::Football:
            return {"idle_stand", "jog", "run", "turn_run", "juke_left", "juke_right", "tackle", "get_up", "turn_walk"};
        case TakeKind::CarryingEnd:
            return {"idle_stand", "carry_end_lift", "carry_end_forward", "carry_end_back", "carry_end_left", "carry_end_right",
                    "carry_end_turn_left", "carry_end_turn_right", "carry_end_hold", "carry_end_forward_left",
                    "carry_end_forward_right", "carry_end_back_left", "carry_end_back_right"};
        case TakeKind::Walking: break;
    }
    return {"idle_stand", "walk", "turn_walk", "backpedal"};
}

namespace detail {
// Fills the attack vectors and peak speeds of attacks from the finished motion.
void measureAttacks(const Motion& motion, const Timeline& tl, std::vector<TruthAction>& actions);
}  // namespace detail

Take generateTake(const TakeSpec& spec, std::uint64_t seed) {
    Builder b(spec.kind == TakeKind::ShadowBoxing || spec.kind == TakeKind::Falls ? spec.style : Style::Neutral, seed);
    const auto feet = b.stanceFeet(Mode::Stand, dvec3(0.0), 0.0);
    b.tl.feet[0].setInitial(feet[0]);
    b.tl.feet[1].setInitial(feet[1]);
    b.pose(0.0, 0.0, b.modePose(Mode::Stand));
    for (detail::Ch c : {detail::BaseX, detail::BaseZ, detail::Heading}) b.key(c, 0.0, 0.0);
    switch (spec.kind) {
        case TakeKind::ShadowBoxing: shadowBoxing(b, spec.seconds); break;
        case TakeKind::RunningAround: runningAround(b, spec.seconds); break;
        case TakeKind::Falls: falls(b, spec.seconds); break;
        case TakeKind::Carrying: carrying(b, spec.seconds); break;
        case TakeKind::Walking: walking(b, spec.seconds); break;
        case TakeKind::Football: football(b, spec.seconds); break;
        case TakeKind::CarryingEnd: carryingEnd(b, spec.seconds); break;
    }
    Take take;
    take.spec = spec;
    GroundTruth& gt = take.truth;
    take.motion = detail::synthesize(b.tl, b.frame, gt.leftContact, gt.rightContact);
    take.motion.source().path = spec.name + ".bvh";
    gt.take = spec.name;
    gt.motionFile = spec.name + ".bvh";
    gt.kind = std::string(toString(spec.kind));
    gt.style = std::string(toString(spec.style));
    gt.seed = seed;
    gt.fps = kDemoFps;
    gt.frameCount = b.frame;
    gt.actions = std::move(b.actions);
    detail::measureAttacks(take.motion, b.tl, gt.actions);
    return take;
}

}  // namespace fray::demo
