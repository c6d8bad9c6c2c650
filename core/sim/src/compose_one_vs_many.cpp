// One vs many: the main character meets the enemies one after another (SPEC 4.5).
#include <atomic>
#include <mutex>

#include <tbb/parallel_for.h>

#include "compose_kinds.h"
#include "fray/sim/compose/one_vs_many.h"

namespace fray::sim::detail {

namespace {

// What the candidate search reads of every patch, worked out once per patch
// library rather than once per candidate (the many-main fights share it):
// the main character's first placement inverted, the newcomer's start, the
// start node of the main character's first action, the centre and half size
// of each swept box's square (both roles, in order), and the patch's answer to
// each user command (userPreference for role 0).
struct PatchSearchData {
    struct Entry {
        RootXf mainStartInverse;
        glm::vec2 newcomerStart{0.0f};
        int mainStartNode = 0;
        std::uint32_t runBegin = 0, runEnd = 0;
        glm::vec2 centre{0.0f};  // a disc round all its squares (in the patch's frame)
        float radius = 0;
    };
    struct Square {
        glm::vec2 centre{0.0f};
        float half = 0;
    };
    // Runs of up to kRun consecutive squares of one patch and a disc round
    // them (in the patch's frame): a run whose disc's square is clear of an
    // obstacle has each of its squares clear of it.
    struct Run {
        glm::vec2 centre{0.0f};
        float radius = 0;
        std::uint32_t begin = 0, end = 0;
    };
    static constexpr std::uint32_t kRun = 8;
    std::vector<Entry> entries;
    std::vector<Square> squares;
    std::vector<Run> runs;
    std::vector<std::vector<signed char>> commandMatch;  // per user command (none for a move)

    PatchSearchData(const ActionLibrary& lib, const PatchLibrary& patches, const std::vector<UserCommand>& commands) {
        const auto& all = patches.patches();
        entries.resize(all.size());
        for (std::size_t i = 0; i < all.size(); ++i) {
            const Patch& p = all[i];
            Entry& e = entries[i];
            e.mainStartInverse = p.tracks[0].front().root.inverse();
            e.newcomerStart = p.tracks[1].front().root.pos;
            e.mainStartNode = lib.startNode()[static_cast<std::size_t>(p.tracks[0].front().action)];
            const auto first = static_cast<std::uint32_t>(squares.size());
            for (int r = 0; r < 2; ++r) {
                for (const auto& sw : p.swept[static_cast<std::size_t>(r)]) {
                    const glm::vec2 h = (sw.hi - sw.lo) * 0.5f;
                    squares.push_back({(sw.lo + sw.hi) * 0.5f, std::max(h.x, h.y)});
                }
            }
            const auto last = static_cast<std::uint32_t>(squares.size());
            e.runBegin = static_cast<std::uint32_t>(runs.size());
            for (std::uint32_t b = first; b < last; b += kRun) {
                Run run;
                run.begin = b, run.end = std::min(last, b + kRun);
                SweptBox around = SweptBox::empty();
                for (std::uint32_t k = run.begin; k < run.end; ++k) around.add({squares[k].centre, squares[k].centre});
                run.centre = (around.lo + around.hi) * 0.5f;
                // Each square lies within half * sqrt(2) of its centre; a
                // millimetre more covers the rounding of placing either.
                for (std::uint32_t k = run.begin; k < run.end; ++k) {
                    run.radius = std::max(run.radius, glm::length(squares[k].centre - run.centre) + squares[k].half * 1.4143f + 1e-3f);
                }
                runs.push_back(run);
            }
            e.runEnd = static_cast<std::uint32_t>(runs.size());
            SweptBox whole = SweptBox::empty();
            for (std::uint32_t r = e.runBegin; r < e.runEnd; ++r) whole.add({runs[r].centre, runs[r].centre});
            if (e.runBegin < e.runEnd) e.centre = (whole.lo + whole.hi) * 0.5f;
            for (std::uint32_t r = e.runBegin; r < e.runEnd; ++r) {
                e.radius = std::max(e.radius, glm::length(runs[r].centre - e.centre) + runs[r].radius + 1e-3f);
            }
        }
        commandMatch.resize(commands.size());
        for (std::size_t k = 0; k < commands.size(); ++k) {
            if (commands[k].annotation == "move") continue;
            auto& m = commandMatch[k];
            m.assign(all.size(), 0);
            for (std::size_t i = 0; i < all.size(); ++i) {
                for (const auto& inst : all[i].tracks[0]) {
                    if (matchesAnnotation(lib.actions()[static_cast<std::size_t>(inst.action)], commands[k].annotation)) {
                        m[i] = 1;
                        break;
                    }
                }
            }
        }
    }
};

struct OneVsManyComposer : KindComposer<OneVsManySpec> {
    using KindComposer::KindComposer;

    // Shared by the fights of a many-main scene (runMany), else made by run().
    const PatchSearchData* search = nullptr;
    std::optional<PatchSearchData> ownSearch;

    // Where everyone present is at time t (their placement's position), for
    // d_p: the same positions densityAround takes, placed once per time
    // rather than once per candidate patch.
    std::vector<glm::vec2> positionsAt(double t) const {
        std::vector<glm::vec2> out;
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
            if (scene.characters[static_cast<std::size_t>(c)].track.empty()) continue;
            const auto& inst = playingAt(c, t);
            out.push_back(inst.placementAt(lib, inst.clipTimeAt(t)).pos);
        }
        return out;
    }
    static int densityAmong(const std::vector<glm::vec2>& at, const glm::vec2& p) {
        int n = 0;
        for (const glm::vec2& q : at) n += glm::length(q - p) < 2.5f ? 1 : 0;
        return n;
    }
    // collides(p, xf, obstacles) with the rotation of xf worked out once, the
    // patch's swept squares from PatchSearchData and a first test against the
    // box round every obstacle (a patch box clear of it is clear of each):
    // the same answer.
    // The runs and squares are tested only against the obstacles that meet
    // the square round the whole patch: every run and square lies inside it
    // (its disc's margins cover the rounding, as for the test against `all`),
    // so no other obstacle can meet one of them.
    bool collidesFast(std::size_t i, const RootXf& xf, const std::vector<SweptBox>& obstacles, const SweptBox& all) const {
        if (obstacles.empty()) return false;
        const FloorRotation rot(xf.heading);
        const auto& e = search->entries[i];
        auto around = [](const glm::vec2& centre, float radius) {
            const float reach = radius + 1e-5f * (std::fabs(centre.x) + std::fabs(centre.y));  // and the rounding far out
            return SweptBox{centre - glm::vec2(reach), centre + glm::vec2(reach)};
        };
        // The whole patch first, then its runs, then their squares.
        const SweptBox whole = around(xf.pos + rot(e.centre), e.radius);
        if (!whole.overlaps(all, kClearance)) return false;
        std::vector<SweptBox>& near = nearScratch;
        near.clear();
        SweptBox nearAll = SweptBox::empty();
        for (const auto& o : obstacles) {
            if (whole.overlaps(o, kClearance)) near.push_back(o), nearAll.add(o);
        }
        if (near.empty()) return false;
        auto hits = [&](const SweptBox& w) {
            if (!w.overlaps(nearAll, kClearance)) return false;
            for (const auto& o : near) {
                if (w.overlaps(o, kClearance)) return true;
            }
            return false;
        };
        for (std::uint32_t r = e.runBegin; r < e.runEnd; ++r) {
            const auto& run = search->runs[r];
            if (!hits(around(xf.pos + rot(run.centre), run.radius))) continue;
            for (std::uint32_t k = run.begin; k < run.end; ++k) {
                const auto& sq = search->squares[k];
                const glm::vec2 c0 = xf.pos + rot(sq.centre);
                if (hits(SweptBox{c0 - glm::vec2(sq.half), c0 + glm::vec2(sq.half)})) return true;
            }
        }
        return false;
    }
    mutable std::vector<SweptBox> nearScratch;  // collidesFast's (one thread per composer)

    // userPreference(patch i, role 0, t) is commandAt(t)[i] (0 where it
    // gives null): the user command due at t (the last non-move one)
    // looked up in PatchSearchData.
    const signed char* commandAt(double t) const {
        const signed char* m = nullptr;
        for (std::size_t k = 0; k < spec.commands.size(); ++k) {
            if (spec.commands[k].time <= t && !search->commandMatch[k].empty()) m = search->commandMatch[k].data();
        }
        return m;
    }

    // The fights of a many-main scene (issue 27) do not score every candidate
    // patch at every first step of the main character (2,135 patches x 13
    // steps on the demo, 17 ms an enemy): they score a sample, and all of
    // them only when nothing of the sample fits even after the main character
    // has walked to open space twice (where nothing of the sample fits, the
    // main character is hemmed in by those already down, and a single fight
    // finds nothing among all candidates there either, 0 of 62,370 options
    // for most such enemies on the demo: it walks). The sample: the candidates
    // of the best class (the usage and the user's command at t0, the terms
    // that outweigh all others in S(p)), those whose main character starts
    // where its last action (or one of its first steps) ends in the motion
    // graph first, then drawn at random with the fight's seed, kSample in all.
    bool sampleCandidates = false;
    static constexpr std::size_t kTried = 40;  // options whose newcomer's entry is planned, best first
    static constexpr std::size_t kSample = 48;
    std::vector<std::size_t> sampled(const std::vector<std::size_t>& cands, double t0, int lastMain) {
        if (cands.size() <= kSample) return cands;
        std::vector<double> cls(cands.size());
        double top = -std::numeric_limits<double>::max();
        const signed char* command = commandAt(t0);
        for (std::size_t j = 0; j < cands.size(); ++j) {
            const std::size_t i = cands[j];
            cls[j] = spec.wUsage * (1.0 - std::min(usage[i], 1.0)) + spec.wUser * (command ? command[i] : 0);
            top = std::max(top, cls[j]);
        }
        auto endNodeOf = [&](int a) { return lib.endNode()[static_cast<std::size_t>(a)]; };
        std::vector<int> nodes{endNodeOf(lastMain)};
        for (int mv : locomotion) nodes.push_back(endNodeOf(mv));
        std::vector<std::size_t> matched, rest;
        for (std::size_t j = 0; j < cands.size(); ++j) {
            if (cls[j] < top) continue;
            const int start = search->entries[cands[j]].mainStartNode;
            (std::find(nodes.begin(), nodes.end(), start) != nodes.end() ? matched : rest).push_back(cands[j]);
        }
        std::vector<std::size_t> out;
        auto draw = [&](std::vector<std::size_t>& from) {
            while (!from.empty() && out.size() < kSample) {
                const std::size_t j = std::uniform_int_distribution<std::size_t>(0, from.size() - 1)(rng);
                out.push_back(from[j]);
                from[j] = from.back();
                from.pop_back();
            }
        };
        draw(matched);
        draw(rest);
        std::sort(out.begin(), out.end());  // scored in the candidates' order, as all of them would be
        return out;
    }

    // ---- one vs many: the main character meets the enemies one after another.
    Status run(const ProgressFn& progress) {
        if (own.mains > 1) return runMany(progress);
        if (!search) search = &ownSearch.emplace(lib, patches, spec.commands);
        const int mainC = addCharacter("main", 0);
        append(mainC, hold, 0.0, RootXf{}, 0, 1.0);
        int prev = -1;
        int moves = 0;
        std::size_t nextCommand = 0;  // the first user command not yet due
        for (int k = 0; k < own.enemies; ++k) {
            const double t0 = freeAt(mainC);
            if (t0 >= spec.duration) break;
            const RootXf at = leaves(mainC);
            const int lastMain = track(mainC).back().action;
            // A move command that is due: the main character walks to its
            // place first (facing on along the way), then meets the next enemy there.
            bool walked = false;
            for (; nextCommand < spec.commands.size() && spec.commands[nextCommand].time <= t0; ++nextCommand) {
                const UserCommand& c = spec.commands[nextCommand];
                if (c.annotation != "move" || !c.at) continue;
                RootXf goal;
                goal.pos = *c.at;
                const glm::vec2 d = goal.pos - at.pos;
                goal.heading = glm::length(d) > 1e-3f ? angleOf(d) : at.heading;
                std::vector<ActionInstance> walk;
                locomote(mainC, -1, at, t0, lastMain, goal, 0.0, walk);
                if (walk.empty() || penetrates(walk, mainC)) continue;  // blocked or there already: the command lapses
                for (auto& w : walk) track(mainC).push_back(w);
                stats.locomotionSteps += static_cast<int>(walk.size());
                walked = true;
                ++nextCommand;
                break;
            }
            if (walked) {
                --k;
                continue;
            }
            // Candidates: temporal links where the main character continues, else any (recycling).
            std::vector<std::size_t> cands;
            if (prev >= 0) {
                for (const auto& l : patches.temporal()[static_cast<std::size_t>(prev)]) {
                    if (l.shared == 0 && l.roles == 0 && allowed[static_cast<std::size_t>(l.to)]) cands.push_back(static_cast<std::size_t>(l.to));
                }
            }
            const bool linked = !cands.empty();
            if (!linked) {
                for (std::size_t i = 0; i < patches.patches().size(); ++i) {
                    if (allowed[i] && patches.patches()[i].tracks[0].front().start == 0.0) cands.push_back(i);
                }
            }
            // A fight of a many-main scene looks at a sample first (see sampled()).
            const std::vector<std::size_t> allCands = cands;
            bool sampledFirst = false;
            if (sampleCandidates) {
                std::vector<std::size_t> few = sampled(cands, t0, lastMain);
                sampledFirst = few.size() < cands.size();
                cands = std::move(few);
            }
          retry:
            // The main character may first take one locomotion step (turn,
            // step) so the patch fits beside those already down.
            struct Option {
                double score;
                std::size_t patch;
                int move;
                std::size_t seq;  // the order found: ties keep it
            };
            std::vector<Option> options;
            std::vector<int> moves0 = {-1};
            moves0.insert(moves0.end(), locomotion.begin(), locomotion.end());
            const auto obstacleBoxes = obstacles(t0, mainC);
            SweptBox allObstacles = SweptBox::empty();
            for (const auto& o : obstacleBoxes) allObstacles.add(o);
            for (int mv : moves0) {
                RootXf from = at;
                double tm = t0;
                if (mv >= 0) {
                    from = at * act(mv).end;
                    tm = t0 + act(mv).duration;
                    if (blocked(mainC, -1, at.pos, from.pos, tm) ||
                        blocked(mainC, -1, at.pos, (at * lib.rootAt(mv, 0.5 * act(mv).duration)).pos, t0)) {
                        continue;
                    }
                }
                // The step's body test (the dearest) only once some candidate
                // fits after it: where none does, its answer changes nothing.
                bool stepTested = mv < 0;
                const int lastA = mv >= 0 ? mv : lastMain;
                std::vector<glm::vec2> present;
                const signed char* command = commandAt(tm);
                const int lastEnd = lib.endNode()[static_cast<std::size_t>(lastA)];
                for (std::size_t i : cands) {
                    const auto& e = search->entries[i];
                    const RootXf xf = from * e.mainStartInverse;
                    if (collidesFast(i, xf, obstacleBoxes, allObstacles)) continue;
                    if (!stepTested) {
                        if (penetrates({ActionInstance{mv, t0, 0.0, tm, at, false, false}}, mainC)) break;
                        stepTested = true;
                    }
                    if (present.empty()) present = positionsAt(tm);
                    const double s = score(i, densityAmong(present, xf.apply(e.newcomerStart)), command ? command[i] : 0) +
                                     (e.mainStartNode == lastEnd ? 1.0 : 0.0) - (mv >= 0 ? 5.0 : 0.0);
                    options.push_back({s, i, mv, options.size()});
                }
            }
            // Best first, ties in the order found (a stable sort's order);
            // only the first kTried are ever looked at.
            const auto tried = options.begin() + static_cast<std::ptrdiff_t>(std::min(options.size(), kTried));
            std::partial_sort(options.begin(), tried, options.end(), [](const Option& x, const Option& y) {
                return x.score != y.score ? x.score > y.score : x.seq < y.seq;
            });
            // The best option whose newcomer can walk in.
            int bestI = -1, bestMove = -1;
            std::vector<ActionInstance> entry;
            const int enemy = addCharacter("enemy-" + std::to_string(k + 1), 1);
            for (std::size_t o = 0; o < options.size() && o < kTried && bestI < 0; ++o) {
                const Patch& p = patches.patches()[options[o].patch];
                const int mv = options[o].move;
                const RootXf from = mv >= 0 ? at * act(mv).end : at;
                const double t = mv >= 0 ? t0 + act(mv).duration : t0;
                const RootXf xf = from * p.tracks[0].front().root.inverse();
                // The newcomer's walk is tested against the main character as
                // it will move meanwhile (its step, then its part of the
                // patch), not standing where its last action left it: both
                // are placed for the test and taken away after it.
                const std::size_t mainLength = track(mainC).size();
                if (mv >= 0) append(mainC, mv, t0, at);
                placeTrack(p, 0, mainC, t, xf);
                auto walk = planEntry(enemy, mainC, p, 1, t, xf, from.pos);
                track(mainC).erase(track(mainC).begin() + static_cast<std::ptrdiff_t>(mainLength), track(mainC).end());
                if (walk) bestI = static_cast<int>(options[o].patch), bestMove = mv, entry = std::move(*walk);
            }
            if (bestI < 0) scene.characters.pop_back();
            if (bestI < 0 && sampledFirst && moves >= 1) {
                // Nothing of the sample fits, and walking to open space has not
                // helped twice: every candidate, as a single fight looks.
                cands = allCands;
                sampledFirst = false;
                goto retry;
            }
            if (bestI < 0) {
                // Crowded: the main character walks into open space and tries again.
                if (++moves > 8) return makeError("one-vs-many: no patch fits around the main character at " + std::to_string(t0) + " s");
                // Candidate spots around, best first: most room, then nearest the scene centre.
                const auto boxes = obstacles(t0, mainC);
                std::vector<std::pair<double, RootXf>> spots;
                for (float dist : {2.5f, 4.0f, 6.0f}) {
                    for (int dir = 0; dir < 12; ++dir) {
                        RootXf goal;
                        goal.heading = wrapAngle(at.heading + dir * std::numbers::pi / 6);
                        goal.pos = at.pos + headingVector(goal.heading) * dist;
                        float room = 10.0f;
                        for (const auto& o : boxes) room = std::min(room, rectDistance(o, goal.pos));
                        if (room < 2.0f) continue;
                        spots.push_back({-static_cast<double>(std::min(room, 3.0f)) + 0.2 * static_cast<double>(glm::length(goal.pos)), goal});
                    }
                }
                std::stable_sort(spots.begin(), spots.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
                std::vector<ActionInstance> walk;
                for (const auto& [rank, goal] : spots) {
                    walk.clear();
                    locomote(mainC, -1, at, t0, lastMain, goal, 0.0, walk);
                    if (!walk.empty() && !penetrates(walk, mainC)) break;
                    walk.clear();
                }
                if (walk.empty()) return makeError("one-vs-many: the main character is boxed in at " + std::to_string(t0) + " s");
                for (auto& w : walk) track(mainC).push_back(w);
                stats.locomotionSteps += static_cast<int>(walk.size());
                --k;
                continue;
            }
            moves = 0;
            (linked ? stats.temporalLinks : stats.recycled) += 1;
            const Patch& p = patches.patches()[static_cast<std::size_t>(bestI)];
            RootXf from = at;
            double t = t0;
            if (bestMove >= 0) {
                append(mainC, bestMove, t, at);
                ++stats.locomotionSteps;
                from = leaves(mainC);
                t = freeAt(mainC);
            }
            const RootXf xf = from * p.tracks[0].front().root.inverse();
            for (auto& w : entry) track(enemy).push_back(w);
            placeTrack(p, 0, mainC, t, xf);
            placeTrack(p, 1, enemy, t, xf);
            placeHits(p, {mainC, enemy}, t);
            used(static_cast<std::size_t>(bestI));
            prev = bestI;
            if (!reportProgress(progress, static_cast<double>(k + 1) / own.enemies, "compose")) return cancelled();
        }
        return {};
    }

    // ---- many main characters (issue 27): own.mains fights, each a main
    // character and its own `enemies`, composed in parallel (fight k with
    // seed + k, so the bytes do not depend on the number of threads) and laid
    // out on the floor in rows, each fight's floor rectangle clear of its
    // neighbours'. Fights never share anyone, so no pass looks at two of them.
    struct Fight {
        Scene scene;
        ComposeStats stats;
        std::string error;
        SweptBox extent = SweptBox::empty();
    };

    Status runMany(const ProgressFn& progress) {
        const int n = own.mains;
        const float reach = measureBodyReach(lib);
        const std::vector<float> actionReaches = measureActionReach(lib);
        const std::vector<CoreDiscs::Disc> paths = pelvisPathDiscs(lib);
        const PatchSearchData shared(lib, patches, spec.commands);
        const CoreDiscs discs(lib, kPenetrationShrink);
        std::vector<Fight> fights(static_cast<std::size_t>(n));
        std::atomic<int> done{0};
        std::atomic<bool> stop{false};
        std::mutex progressMutex;
        tbb::parallel_for(0, n, [&](int k) {
            if (stop.load(std::memory_order_relaxed)) return;
            Fight& f = fights[static_cast<std::size_t>(k)];
            OneVsManySpec one = own;
            one.mains = 1;
            ComposeSpec s = ComposeSpec::of(one);
            static_cast<ComposeCommonSpec&>(s) = spec;
            // A fight whose main character gets hemmed in (no patch fits
            // after eight walks to open space) is composed again with the
            // next seed of its own (seed + k + n * mains), three times at most.
            Status st;
            for (int attempt = 0; attempt < 4; ++attempt) {
                s.seed = spec.seed + static_cast<std::uint64_t>(k) + static_cast<std::uint64_t>(attempt) * static_cast<std::uint64_t>(n);
                f.stats = ComposeStats{};
                OneVsManyComposer c(lib, patches, s, f.stats);
                c.sampleCandidates = true;
                c.bodyReach = reach;
                c.actionReach = &actionReaches;
                c.pathDiscs = &paths;
                c.memoBodyBoxes = true;
                c.search = &shared;
                c.coreDiscs = &discs;
                st = c.ready();
                if (st) st = c.run({});
                if (st) {
                    f.scene = std::move(c.scene);
                    break;
                }
            }
            if (!st) {
                f.error = "fight " + std::to_string(k + 1) + ": " + st.error().message;
                return;
            }
            f.extent = sceneExtent(lib, f.scene);
            const int finished = ++done;
            const std::lock_guard<std::mutex> lock(progressMutex);
            if (!reportProgress(progress, static_cast<double>(finished) / n, "compose")) stop = true;
        });
        if (stop.load()) return cancelled();
        for (const Fight& f : fights) {
            if (!f.error.empty()) return makeError(f.error);
        }
        // Rows of ceil(sqrt(n)) fights, each kMargin m from its neighbours.
        constexpr float kMargin = 3.0f;
        const int perRow = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
        float rowZ = 0;
        for (int row = 0; row * perRow < n; ++row) {
            float x = 0, depth = 0;
            for (int k = row * perRow; k < std::min(n, (row + 1) * perRow); ++k) {
                Fight& f = fights[static_cast<std::size_t>(k)];
                const glm::vec2 size = f.extent.hi - f.extent.lo;
                mergeScene(scene, std::move(f.scene), "fight-" + std::to_string(k + 1) + "/", glm::vec2(x, rowZ) - f.extent.lo);
                const ComposeStats& fs = f.stats;
                stats.patchesUsed += fs.patchesUsed, stats.temporalLinks += fs.temporalLinks, stats.recycled += fs.recycled;
                stats.locomotionSteps += fs.locomotionSteps;
                stats.maxJunctionError = std::max(stats.maxJunctionError, fs.maxJunctionError);
                x += size.x + kMargin;
                depth = std::max(depth, size.y);
            }
            rowZ += depth + kMargin;
        }
        return {};
    }
};

Status parseOneVsMany(const prep::JsonReader& rd, const Json& j, OneVsManySpec& s) {
    if (auto st = optionalInt(rd, j, "mains", 1, 100000, s.mains); !st) return st.error();
    return optionalInt(rd, j, "enemies", 1, 1000, s.enemies);
}

constexpr const char* kFields[] = {"enemies", "mains"};

}  // namespace

const SceneKindModule& oneVsManyKind() {
    static const SceneKindModule kind = kindModule<OneVsManyComposer, OneVsManySpec, parseOneVsMany, noCheck<OneVsManySpec>>(true, kFields);
    return kind;
}

}  // namespace fray::sim::detail
