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

namespace {

// What an edit changed, as the steps of the last run must not have read it
// (docs/TREE_EXPANSION.md "Re-planning after an edit").
struct EditBound {
    std::string full;  // why nothing can be kept ("" when something can)
    std::vector<double> pinTime;   // per character: its earliest changed pin's time less kPinEarly (inf: none)
    std::vector<double> pathTime;  // per character: where its schedule starts to differ (inf: unchanged)
    std::vector<int> pathIndex;    // per character: its first changed checkpoint (INT_MAX: unchanged)
};

EditBound compareSpecs(const PlanRecord& last, const ActionLibrary& lib, const std::vector<float>& combo, const SceneSpec& now) {
    EditBound b;
    const SceneSpec& was = last.spec;
    if (last.lib != &lib || last.libActions != lib.size() || last.combo != combo) {
        b.full = "the action library or combination table changed";
        return b;
    }
    SimOptions a = was.options, c = now.options;
    a.duration = c.duration = 0;  // read by the scene loop only
    if (!(a == c)) {
        b.full = "a scene option (seed, stage, pruning, budget...) changed";
        return b;
    }
    if (was.characters.size() != now.characters.size()) {
        b.full = "characters were added or removed";
        return b;
    }
    const std::size_t n = now.characters.size();
    b.pathTime.assign(n, std::numeric_limits<double>::infinity());
    b.pathIndex.assign(n, std::numeric_limits<int>::max());
    b.pinTime.assign(n, std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < n; ++i) {
        CharacterSpec x = was.characters[i], y = now.characters[i];
        const std::vector<Checkpoint> px = std::move(x.path), py = std::move(y.path);
        x.path.clear(), y.path.clear();
        if (!(x == y)) {
            b.full = "character '" + y.name + "' changed (weights, preset, depth, actions, start...)";
            return b;
        }
        if (px == py) continue;
        if (y.loopPath) {
            b.full = "the looped path of '" + y.name + "' changed";
            return b;
        }
        // The first checkpoint that differs (or is added or removed); the
        // schedule differs from the last timed checkpoint before it.
        std::size_t k = 0;
        while (k < px.size() && k < py.size() && px[k] == py[k]) ++k;
        double t = 0;
        for (std::size_t j = 0; j < k; ++j) {
            if (px[j].time) t = std::max(t, *px[j].time);
        }
        b.pathIndex[i] = static_cast<int>(k);
        b.pathTime[i] = t;
    }
    // Pins: those in one list and not the other (read by their character's group only).
    const auto missing = [](const std::vector<ActionPin>& from, const std::vector<ActionPin>& in, std::vector<double>& earliest) {
        std::vector<bool> used(in.size(), false);
        for (const ActionPin& p : from) {
            bool found = false;
            for (std::size_t j = 0; j < in.size() && !found; ++j) {
                if (!used[j] && in[j] == p) used[j] = found = true;
            }
            if (found) continue;
            if (p.character >= 0 && static_cast<std::size_t>(p.character) < earliest.size()) {
                auto& e = earliest[static_cast<std::size_t>(p.character)];
                e = std::min(e, p.time - kPinEarly);
            } else {
                for (double& e : earliest) e = std::min(e, p.time - kPinEarly);
            }
        }
    };
    missing(was.pins, now.pins, b.pinTime);
    missing(now.pins, was.pins, b.pinTime);
    return b;
}

// Whether a step that read up to `reach` and these checkpoints (by member)
// may have read something the edit changed.
bool stepReads(const EditBound& b, const Context& ctx, double reach, const std::array<int, kMaxGroupSize>& checkpoint) {
    for (std::size_t m = 0; m < ctx.members.size(); ++m) {
        const auto c = static_cast<std::size_t>(ctx.members[m].global);
        if (reach >= b.pinTime[c]) return true;
        if (b.pathIndex[c] == std::numeric_limits<int>::max()) continue;
        if (reach >= b.pathTime[c]) return true;
        if (static_cast<std::int64_t>(checkpoint[m]) + 3 >= b.pathIndex[c]) return true;
    }
    return false;
}

void keepMarks(const ReadMarks& r, double& reach, std::array<int, kMaxGroupSize>& checkpoint) {
    reach = r.reach.load(std::memory_order_relaxed);
    for (std::size_t i = 0; i < checkpoint.size(); ++i) checkpoint[i] = r.checkpoint[i].load(std::memory_order_relaxed);
}

Result<Scene> run(const ActionLibrary& lib, const prep::ComboTable& combos, const SceneSpec& spec, const ProgressFn& progress,
                  PlanCache* cache, ReplanInfo* info) {
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

    // Incremental re-planning: what the edit changed since the cached run.
    std::shared_ptr<PlanRecord> record;
    const PlanRecord* last = cache && cache->last ? cache->last.get() : nullptr;
    EditBound bound;
    if (cache) {
        record = std::make_shared<PlanRecord>();
        record->lib = &lib;
        record->libActions = lib.size();
        record->combo = combo;
        record->spec = spec;
        if (last) bound = compareSpecs(*last, lib, combo, spec);
        else bound.full = "no earlier run";
        if (info) *info = ReplanInfo{};
    }
    ReadMarks marks;

    // Groups, in order of first appearance.
    std::vector<int> groupIds;
    for (const auto& c : spec.characters) {
        if (std::find(groupIds.begin(), groupIds.end(), c.group) == groupIds.end()) groupIds.push_back(c.group);
    }
    std::mt19937_64 rng(opt.seed);
    Stats total;
    double resumedAt = std::numeric_limits<double>::infinity();
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
        ctx.memory = makeSearchMemory();
        PinGuide pins(ctx, spec);
        // The group's share of the scene so far (kept states count from here).
        const std::size_t hitsBegin = scene.hits.size(), catchesBegin = scene.catches.size();
        const std::int64_t decisionsBegin = scene.stats.decisions, fallbacksBegin = scene.stats.fallbacks,
                           forcedBegin = scene.stats.forced;
        Stats groupSearch;
        PlanGroupRecord* gr = nullptr;
        if (record) {
            gr = &record->groups.emplace_back();
            ctx.reads = &marks;
            marks.reset();
        }
        {
            Events ev;  // the first node: whoever finishes its start action first
            advance(ctx, g, ev, &rec);
        }
        if (gr) {
            for (int i = 0; i < g.n; ++i) {
                ReadMarks::raise(marks.reach, g.time);
                ReadMarks::raise(marks.checkpoint[static_cast<std::size_t>(i)], g.c[static_cast<std::size_t>(i)].checkpoint);
            }
            keepMarks(marks, gr->initReach, gr->initCheckpoint);
        }
        const auto snapshot = [&]() {
            PlanSnapshot sn;
            sn.g = g;
            sn.stop = rec.stop;
            for (const auto& m : ctx.members) {
                const auto& sc = scene.characters[static_cast<std::size_t>(m.global)];
                sn.trackSize.push_back(sc.track.size());
                sn.trackLast.push_back(sc.track.back());
                sn.fallbacks.push_back(sc.fallbacks);
            }
            sn.hits = scene.hits.size() - hitsBegin;
            sn.catches = scene.catches.size() - catchesBegin;
            sn.decisions = scene.stats.decisions - decisionsBegin;
            sn.fallbackDecisions = scene.stats.fallbacks - fallbacksBegin;
            sn.forced = scene.stats.forced - forcedBegin;
            sn.search = groupSearch;
            sn.pinsFired = pins.firedCounts(g.n);
            return sn;
        };
        // Resume from the last kept state the edit cannot have reached.
        if (gr && last && bound.full.empty() && gi < last->groups.size() && !stepReads(bound, ctx, last->groups[gi].initReach, last->groups[gi].initCheckpoint)) {
            const PlanGroupRecord& old = last->groups[gi];
            std::size_t k = 0;
            while (k + 1 < old.snaps.size() && old.snaps[k].g.time < opt.duration && !old.snaps[k].stop &&
                   !stepReads(bound, ctx, old.snaps[k].reach, old.snaps[k].checkpoint)) {
                ++k;
            }
            const PlanSnapshot& sn = old.snaps[k];
            g = sn.g;
            rec.stop = sn.stop;
            for (std::size_t m = 0; m < ctx.members.size(); ++m) {
                auto& sc = scene.characters[static_cast<std::size_t>(ctx.members[m].global)];
                sc.track.assign(old.tracks[m].begin(), old.tracks[m].begin() + static_cast<std::ptrdiff_t>(sn.trackSize[m]));
                sc.track.back() = sn.trackLast[m];
                sc.fallbacks = sn.fallbacks[m];
            }
            scene.hits.resize(hitsBegin);
            scene.hits.insert(scene.hits.end(), old.hits.begin(), old.hits.begin() + static_cast<std::ptrdiff_t>(sn.hits));
            scene.catches.resize(catchesBegin);
            scene.catches.insert(scene.catches.end(), old.catches.begin(), old.catches.begin() + static_cast<std::ptrdiff_t>(sn.catches));
            scene.stats.decisions = decisionsBegin + sn.decisions;
            scene.stats.fallbacks = fallbacksBegin + sn.fallbackDecisions;
            scene.stats.forced = forcedBegin + sn.forced;
            groupSearch = sn.search;
            total.add(sn.search);
            pins.restoreFired(sn.pinsFired);
            gr->initReach = old.initReach;
            gr->initCheckpoint = old.initCheckpoint;
            gr->snaps.assign(old.snaps.begin(), old.snaps.begin() + static_cast<std::ptrdiff_t>(k));
            if (info) info->decisionsKept += sn.decisions;
            resumedAt = std::min(resumedAt, g.time);
        } else {
            resumedAt = 0;
        }
        while (g.time < opt.duration && !rec.stop) {
            if (gr) {
                gr->snaps.push_back(snapshot());
                marks.reset();
            }
            const int who = chooserOf(g);
            const auto& cs = specOf(ctx, who);
            Stats st;
            bool fellBack = false;
            if (!pins.empty() && opt.pinsInTree) pins.inTree(ctx);
            int action = decide(ctx, g, cs.depth, st, fellBack);
            total.add(st);
            groupSearch.add(st);
            if (!pins.empty()) {
                auto pinned = pins.choose(ctx, g, who, action, [&](const CandidateFilter& filter) {
                    Stats again;
                    const int a = decide(ctx, g, cs.depth, again, fellBack, &filter);
                    total.add(again);
                    groupSearch.add(again);
                    return a;
                });
                if (!pinned) return pinned.error();
                action = *pinned;
            }
            ++scene.stats.decisions;
            if (info) ++info->decisionsPlanned;
            const int global = ctx.members[static_cast<std::size_t>(who)].global;
            auto& sc = scene.characters[static_cast<std::size_t>(global)];
            if (fellBack) ++scene.stats.fallbacks, ++sc.fallbacks;
            if (action < 0) return makeError("character '" + cs.name + "' has no action to take");
            const double t = g.time;
            const GroupState before = g;
            launch(ctx, g, who, action, t);
            const auto& s = g.c[static_cast<std::size_t>(who)];
            sc.track.push_back({action, t, 0.0, s.end, s.root, false, fellBack});
            Events ev;
            advance(ctx, g, ev, &rec);
            if (gr) {
                noteReads(ctx, before, g, who, action);
                keepMarks(marks, gr->snaps.back().reach, gr->snaps.back().checkpoint);
            }
            const double overall = (static_cast<double>(gi) + std::min(g.time / opt.duration, 1.0)) /
                                   static_cast<double>(groupIds.size());
            if (!reportProgress(progress, overall, "simulate")) return cancelled();
        }
        if (gr) {
            gr->snaps.push_back(snapshot());
            for (const auto& m : ctx.members) gr->tracks.push_back(scene.characters[static_cast<std::size_t>(m.global)].track);
            gr->hits.assign(scene.hits.begin() + static_cast<std::ptrdiff_t>(hitsBegin), scene.hits.end());
            gr->catches.assign(scene.catches.begin() + static_cast<std::ptrdiff_t>(catchesBegin), scene.catches.end());
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
    if (record) {
        cache->last = std::move(record);
        if (info) {
            info->incremental = info->decisionsKept > 0;
            info->resumedAt = info->incremental ? resumedAt : 0;
            info->reason = info->incremental ? std::string() : !bound.full.empty() ? bound.full : "the edit reaches the first decision";
        }
    }
    reportProgress(progress, 1.0, "simulate");
    return scene;
}

}  // namespace

Result<Scene> simulate(const ActionLibrary& lib, const prep::ComboTable& combos, const SceneSpec& spec, const ProgressFn& progress) {
    return run(lib, combos, spec, progress, nullptr, nullptr);
}

Result<Scene> simulate(const ActionLibrary& lib, const prep::ComboTable& combos, const SceneSpec& spec, PlanCache& cache,
                       const ProgressFn& progress, ReplanInfo* info) {
    return run(lib, combos, spec, progress, &cache, info);
}

}  // namespace fray::sim
