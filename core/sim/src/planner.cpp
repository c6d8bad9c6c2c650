#include "fray/sim/planner.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <random>

#include "planner_state.h"

namespace fray::sim {

namespace planner {

std::vector<std::vector<int>> legalChoices(const ActionLibrary& lib, const CharacterSpec& spec) {
    std::vector<std::vector<int>> legal(static_cast<std::size_t>(lib.size()));
    for (int a = 0; a < lib.size(); ++a) {
        const auto& next = lib.next()[static_cast<std::size_t>(a)];
        auto& out = legal[static_cast<std::size_t>(a)];
        std::set_intersection(next.begin(), next.end(), spec.allowed.begin(), spec.allowed.end(), std::back_inserter(out));
        std::erase_if(out, [&](int b) { return lib.actions()[static_cast<std::size_t>(b)].is(kReactive); });
    }
    return legal;
}

std::vector<std::vector<int>> foldVariants(const ActionLibrary& lib, const std::vector<std::vector<int>>& legal) {
    std::vector<std::vector<int>> folded(legal.size());
    for (std::size_t a = 0; a < legal.size(); ++a) {
        std::vector<int> seen;
        for (int b : legal[a]) {
            const int c = lib.variantClass()[static_cast<std::size_t>(b)];
            if (std::find(seen.begin(), seen.end(), c) != seen.end()) continue;
            seen.push_back(c);
            folded[a].push_back(b);
        }
    }
    return folded;
}

std::vector<float> comboMatrix(const ActionLibrary& lib, const prep::ComboTable& combos, const std::vector<CharacterSpec>& characters) {
    // Suitability of every (mine, theirs) pair among the actions in play.
    std::vector<int> inPlay;
    for (const auto& c : characters) inPlay.insert(inPlay.end(), c.allowed.begin(), c.allowed.end());
    for (const auto& c : characters) inPlay.insert(inPlay.end(), c.reactions.begin(), c.reactions.end());
    std::sort(inPlay.begin(), inPlay.end());
    inPlay.erase(std::unique(inPlay.begin(), inPlay.end()), inPlay.end());
    const int n = lib.size();
    std::vector<float> combo(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0f);
    if (!combos.records().empty()) {
        for (int a : inPlay) {
            const auto& x = lib.actions()[static_cast<std::size_t>(a)];
            for (int b : inPlay) {
                const auto& y = lib.actions()[static_cast<std::size_t>(b)];
                combo[static_cast<std::size_t>(a) * static_cast<std::size_t>(n) + static_cast<std::size_t>(b)] =
                    static_cast<float>(combos.query(x.name, x.annotations, y.name, y.annotations));
            }
        }
    }
    return combo;
}

Context baseContext(const ActionLibrary& lib, const SimOptions& opt, const std::vector<float>& combo,
                    const detail::InteractionEngine& engine) {
    const int n = lib.size();
    Context base;
    base.lib = &lib;
    base.combo = &combo;
    base.comboN = n;
    base.opt = &opt;
    base.engine = &engine;
    {
        std::map<std::string, int> names;
        base.nameId.resize(static_cast<std::size_t>(n));
        for (int a = 0; a < n; ++a) {
            const auto& name = lib.actions()[static_cast<std::size_t>(a)].name;
            base.nameId[static_cast<std::size_t>(a)] =
                name.empty() ? -1 - a : names.emplace(name, static_cast<int>(names.size())).first->second;
        }
    }
    for (int a = 0; a < n; ++a) {
        base.endAt.push_back(lib.rootAt(a, lib.actions()[static_cast<std::size_t>(a)].duration));
        base.endFacing.push_back(headingVector(base.endAt.back().heading));
    }
    base.maxHitSpeed.assign(static_cast<std::size_t>(n), 0.0);
    for (int a = 0; a < n; ++a) {
        const auto& x = lib.actions()[static_cast<std::size_t>(a)];
        if (!x.is(kAttack)) continue;
        double fastest = 0;
        for (int k = x.activeBegin; k <= std::min(x.activeEnd, x.sampleCount - 1); ++k) {
            fastest = std::max(fastest, static_cast<double>(lib.effectorSpeed()[static_cast<std::size_t>(x.sampleBegin + k)]));
        }
        base.maxHitSpeed[static_cast<std::size_t>(a)] = fastest;
    }
    for (int a = 0; a < n; ++a) {
        base.testPelvisBegin.push_back(base.testPelvis.size());
        const double duration = lib.actions()[static_cast<std::size_t>(a)].duration;
        for (double tau = 0; tau <= duration + 1e-9; tau += kPenetrationStep) {
            base.testPelvis.push_back(lib.rootAt(a, tau).pos);
            const Obb* local = lib.boxesAt(a, lib.sampleAt(a, tau));
            auto& body = base.testBodies.emplace_back();
            for (std::size_t k = 0; k < kCoreSegments.size(); ++k) {
                body.boxes[k] = local[kCoreSegments[k]].shrunk(kPenetrationShrink);
                body.radii[k] = body.boxes[k].radius();
            }
        }
    }
    base.testPelvisBegin.push_back(base.testPelvis.size());
    return base;
}

}  // namespace planner

using namespace planner;

Result<Scene> simulate(const ActionLibrary& lib, const prep::ComboTable& combos, const SceneSpec& spec,
                       const ProgressFn& progress) {
    const auto& opt = spec.options;
    if (!(opt.duration > 0)) return makeError("scene duration must be positive");
    if (spec.characters.empty()) return makeError("the scene has no characters");
    const auto wallStart = std::chrono::steady_clock::now();

    Scene scene;
    scene.duration = opt.duration;
    scene.seed = opt.seed;
    scene.arena = opt.arena;
    scene.spec = spec.text;
    for (const auto& c : spec.characters) {
        if (c.allowed.empty()) return makeError("character '" + c.name + "' has no usable action");
        if (c.depth < 1) return makeError("character '" + c.name + "': depth must be at least 1");
        SceneCharacter sc;
        sc.name = c.name;
        sc.side = c.side;
        sc.group = c.group;
        sc.preset = c.preset;
        sc.depth = c.depth;
        sc.path = c.path;
        sc.loopPath = c.loopPath;
        sc.opponent = c.opponent;
        scene.characters.push_back(std::move(sc));
    }

    const std::vector<float> combo = comboMatrix(lib, combos, spec.characters);
    detail::InteractionEngine engine(lib);
    const Context base = baseContext(lib, opt, combo, engine);

    // Groups, in order of first appearance.
    std::vector<int> groupIds;
    for (const auto& c : spec.characters) {
        if (std::find(groupIds.begin(), groupIds.end(), c.group) == groupIds.end()) groupIds.push_back(c.group);
    }
    std::mt19937_64 rng(opt.seed);
    Stats total;
    for (std::size_t gi = 0; gi < groupIds.size(); ++gi) {
        Context ctx = base;
        bool catches = false;
        GroupState g;
        Recorder rec;
        rec.scene = &scene;
        for (int i = 0; i < static_cast<int>(spec.characters.size()); ++i) {
            const auto& c = spec.characters[static_cast<std::size_t>(i)];
            if (c.group != groupIds[gi]) continue;
            if (g.n == kMaxGroupSize) {
                return makeError("group " + std::to_string(c.group) + " has more than " + std::to_string(kMaxGroupSize) +
                                 " characters (the game tree holds every member of a group)");
            }
            auto legal = legalChoices(lib, c);
            auto folded = foldVariants(lib, legal);
            ctx.members.push_back({i, &c, std::move(legal), std::move(folded), engine.addPool(c.reactions), makePathPlan(c)});
            rec.global[static_cast<std::size_t>(g.n)] = i;
            if (c.weights.wPath > 0 || c.weights.wPsi > 0 || c.weights.wReq > 0) ctx.cooperative = true;
            if (c.weights.catches) catches = true;
            // Start: the given action, or an idle one of its set chosen by the
            // seed, entered at a seeded point so decisions interleave differently.
            int a0 = c.startAction;
            if (a0 < 0) {
                std::vector<int> idle;
                for (int a : c.allowed) {
                    if (lib.actions()[static_cast<std::size_t>(a)].is(kIdle)) idle.push_back(a);
                }
                const auto& pool = idle.empty() ? c.allowed : idle;
                a0 = pool[static_cast<std::size_t>(rng() % pool.size())];
            }
            const double dur = lib.actions()[static_cast<std::size_t>(a0)].duration;
            const double offset = std::uniform_real_distribution<double>(0.0, 0.5 * dur)(rng);
            CharState s;
            s.action = a0;
            s.start = 0;
            s.offset = offset;
            s.end = dur - offset;
            RootXf start = c.start;
            if (opt.startJitter > 0 || opt.startJitterDegrees > 0) {
                std::uniform_real_distribution<double> u(-1.0, 1.0);
                const double jx = u(rng) * opt.startJitter, jz = u(rng) * opt.startJitter;
                const double jh = u(rng) * opt.startJitterDegrees * std::numbers::pi / 180.0;
                start.pos += glm::vec2(static_cast<float>(jx), static_cast<float>(jz));
                start.heading = wrapAngle(start.heading + jh);
            }
            s.root = start * lib.rootAt(a0, offset).inverse();
            pushRecent(ctx, s, a0);
            g.c[static_cast<std::size_t>(g.n)] = s;
            auto& track = scene.characters[static_cast<std::size_t>(i)].track;
            track.push_back({a0, 0.0, offset, s.end, s.root, false, false});
            ++g.n;
        }
        ctx.duel = g.n == 2 && specOf(ctx, 0).side != specOf(ctx, 1).side &&
                   (specOf(ctx, 0).opponent < 0 || specOf(ctx, 0).opponent == ctx.members[1].global) &&
                   (specOf(ctx, 1).opponent < 0 || specOf(ctx, 1).opponent == ctx.members[0].global);
        ctx.boundedFrontier = ctx.duel && !catches;
        PinGuide pins(ctx, spec);
        {
            Events ev;  // the first node: whoever finishes its start action first
            advance(ctx, g, ev, &rec);
        }
        while (g.time < opt.duration && !rec.stop) {
            const int who = chooserOf(g);
            const auto& cs = specOf(ctx, who);
            Stats st;
            bool fellBack = false;
            if (!pins.empty() && opt.pinsInTree) pins.inTree(ctx);
            int action = decide(ctx, g, cs.depth, st, fellBack);
            total.add(st);
            if (!pins.empty()) {
                auto pinned = pins.choose(ctx, g, who, action, [&](const CandidateFilter& filter) {
                    Stats again;
                    const int a = decide(ctx, g, cs.depth, again, fellBack, &filter);
                    total.add(again);
                    return a;
                });
                if (!pinned) return pinned.error();
                action = *pinned;
            }
            ++scene.stats.decisions;
            const int global = ctx.members[static_cast<std::size_t>(who)].global;
            auto& sc = scene.characters[static_cast<std::size_t>(global)];
            if (fellBack) ++scene.stats.fallbacks, ++sc.fallbacks;
            if (action < 0) return makeError("character '" + cs.name + "' has no action to take");
            const double t = g.time;
            launch(ctx, g, who, action, t);
            const auto& s = g.c[static_cast<std::size_t>(who)];
            sc.track.push_back({action, t, 0.0, s.end, s.root, false, fellBack});
            Events ev;
            advance(ctx, g, ev, &rec);
            const double overall = (static_cast<double>(gi) + std::min(g.time / opt.duration, 1.0)) /
                                   static_cast<double>(groupIds.size());
            if (!reportProgress(progress, overall, "simulate")) return cancelled();
        }
        if (auto st = pins.finish(ctx); !st) return st.error();
        if (rec.stop) {
            for (const auto& m : ctx.members) {
                auto& track = scene.characters[static_cast<std::size_t>(m.global)].track;
                if (!track.empty()) track.back().end = std::min(track.back().end, g.time);
            }
        }
    }
    detail::sortHits(scene.hits);
    std::sort(scene.catches.begin(), scene.catches.end(), [](const CatchEvent& a, const CatchEvent& b) {
        return a.time != b.time ? a.time < b.time : a.chaser < b.chaser;
    });
    scene.stats.nodes = total.nodes;
    scene.stats.leaves = total.leaves;
    scene.stats.choices = total.choices;
    scene.stats.pruned = total.pruned;
    scene.stats.cutoffs = total.cutoffs;
    scene.stats.shallower = total.shallower;
    scene.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    reportProgress(progress, 1.0, "simulate");
    return scene;
}

}  // namespace fray::sim
