// American football: a carrier runs for the goal line past tacklers (SPEC 4.5).
#include <atomic>
#include <mutex>

#include <tbb/parallel_for.h>

#include "compose_kinds.h"
#include "fray/sim/compose/football.h"

namespace fray::sim::detail {

namespace {

struct FootballComposer : KindComposer<FootballSpec, FootballStats> {
    using KindComposer::KindComposer;

    // ---- American football (SPEC 4.5): the carrier runs for the goal line
    // (+Z, own.goal m out) in the direction the user sets over time; tacklers
    // dive at it one after another from patches of {run, TACKLE, avoid}.
    double wantedHeading(double t) const {
        double h = 0;
        for (const auto& d : own.directions) {
            if (d.time <= t + 1e-9) h = d.heading;
        }
        return h;
    }

    // The run step that continues `last` and keeps closest to heading `want`
    // (any run when none continues: a dead end of the graph).
    int nextRun(int last, const RootXf& at, double want) const {
        int best = -1;
        double bestErr = 0;
        for (int pass = 0; pass < 2 && best < 0; ++pass) {
            for (int a : locomotion) {
                if (!act(a).is(kRun) || (pass == 0 && last >= 0 && !lib.continuesInto(last, a))) continue;
                const double err = std::fabs(wrapAngle(want - (at * act(a).end).heading));
                if (best < 0 || err < bestErr - 1e-9) best = a, bestErr = err;
            }
        }
        return best;
    }

    // The tackler's run-up, planned backward from its first patch action
    // (placed at `at`, starting at scene time t): the straightest, longest run
    // steps that lead into it, until it starts entryRadius away; or from a
    // stand when the capture started the run from one. Before time 0 it is
    // already under way.
    // The run step that leads into action `cur` in a run-up (-1: none): running
    // first (a cut if nothing else leads on), then straightest, then the
    // longest stride. A function of `cur` alone, so it is remembered.
    int leadInto(int cur) const {
        if (leads_.empty()) leads_.assign(static_cast<std::size_t>(lib.size()), -2);
        int& memo = leads_[static_cast<std::size_t>(cur)];
        if (memo != -2) return memo;
        int best = -1;
        double bestKey = 0;
        for (int q = 0; q < lib.size(); ++q) {
            const auto& Q = act(q);
            const bool cut = Q.is(kAvoid) && !Q.is(kAttack);  // a running cut is a run step too
            if (!(Q.is(kRun | kIdle) || cut) || Q.is(kAttack) || !lib.continuesInto(q, cur)) continue;
            const double key = (Q.is(kRun) ? 0.0 : cut ? 500.0 : 1000.0) + std::round(std::fabs(Q.end.heading) / 0.05) * 10.0 -
                               static_cast<double>(glm::length(Q.end.pos));
            if (best < 0 || key < bestKey - 1e-9) best = q, bestKey = key;
        }
        memo = best;
        return best;
    }
    mutable std::vector<int> leads_;  // leadInto's answers, -2: not asked yet

    std::vector<ActionInstance> runUp(int first, const RootXf& at, double t) const {
        std::vector<ActionInstance> rev;
        int cur = first;
        RootXf root = at;
        double start = t;
        while (start > 1e-9 && static_cast<double>(glm::length(root.pos - at.pos)) < spec.entryRadius && rev.size() < 64) {
            const int best = leadInto(cur);
            if (best < 0) break;
            root = root * act(best).end.inverse();
            const double s0 = start - act(best).duration;
            rev.push_back({best, s0, 0.0, start, root, false, false});
            cur = best;
            start = s0;
            if (act(best).is(kIdle)) break;  // it stood there until it set off
        }
        std::vector<ActionInstance> out;
        for (auto it = rev.rbegin(); it != rev.rend(); ++it) {
            ActionInstance w = *it;
            if (w.end <= 0) continue;
            if (w.start < 0) w.offset = -w.start, w.start = 0;
            out.push_back(w);
        }
        return out;
    }

    // A second tackler at once (SPEC 4.3 spatial concatenation, the thesis'
    // own example): a patch whose carrier plays the very same run and cut as
    // patch `a` (placed by xf at scene time t) from its start, its tackler
    // never meeting a's. Returns whether one came in.
    bool secondTackler(std::size_t a, double t, const RootXf& xf, int number) {
        const Patch& pa = patches.patches()[a];
        const int carrier = 0;
        for (const auto& l : patches.spatial()[a]) {
            const Patch& pb = patches.patches()[static_cast<std::size_t>(l.to)];
            if (l.sharedA != 0 || l.sharedB != 0 || !allowed[static_cast<std::size_t>(l.to)] || pb.tracks[1].empty() ||
                !act(pb.tracks[1].front().action).is(kTackle)) {
                continue;
            }
            // The shared run must cover all of b's carrier (the carrier plays a's).
            const auto offset = static_cast<double>(l.offset);
            std::size_t j = 0;
            while (j < pa.tracks[0].size() && std::fabs(pa.tracks[0][j].start - offset - pb.tracks[0].front().start) > 1e-4) ++j;
            if (j == pa.tracks[0].size() || pa.tracks[0].size() - j < pb.tracks[0].size()) continue;
            const RootXf xb = xf * pa.tracks[0][j].root * pb.tracks[0].front().root.inverse();
            const double tb = t + offset;
            const auto& dive = pb.tracks[1].front();
            const int tackler = addCharacter("tackler-" + std::to_string(number), 1);
            auto walk = runUp(dive.action, xb * dive.root, tb + dive.start);
            bool ok = !(walk.empty() && tb + dive.start > 1e-9) && !penetrates(walk, tackler);
            if (ok) {
                const auto part = placed(pb, 1, tb, xb);
                ok = !penetrates(part, tackler);
                if (ok) {
                    for (auto& w : walk) track(tackler).push_back(w);
                    for (const auto& w : part) track(tackler).push_back(w);
                }
            }
            if (!ok) {
                scene.characters.pop_back();
                continue;
            }
            placeHits(pb, {carrier, tackler}, tb);
            stats.locomotionSteps += static_cast<int>(walk.size());
            ++ownStats.secondTacklers;
            ownStats.tacklersPassed += pb.hits.empty() ? 1 : 0;
            used(static_cast<std::size_t>(l.to));
            getUpAndStand(tackler);
            return true;
        }
        return false;
    }

    // A tackler gets up where it landed (the capture's own continuation) and stays.
    void getUpAndStand(int tackler) {
        const int down = track(tackler).back().action;
        for (int n : lib.next()[static_cast<std::size_t>(down)]) {
            if (!act(n).is(kTransition)) continue;
            append(tackler, n, freeAt(tackler), leaves(tackler));
            break;
        }
        append(tackler, idleAfter(track(tackler).back().action), freeAt(tackler), leaves(tackler));
    }

    Status run(const ProgressFn& progress) {
        if (own.runs > 1) return runMany(progress);
        if (auto st = runOne(progress); !st) return st.error();
        addBall(0, 1);
        return {};
    }

    // The ball, a one-joint body ("ball") tucked at the carrier's carrying
    // hand along its forearm (SPEC 4.5), held from its first action to its
    // last: through the cuts, and down with it when it is tackled (it keeps
    // the ball; nobody else takes it in this scene). Its keys follow the
    // carrier's kinematic pose at the scene's frame rate (heldBallKeys, as
    // the scene reader makes them again); a run of many places its balls
    // once they are where they run (runMany).
    void addBall(int carrier, int hand) {
        const auto& joints = lib.motion(act(track(carrier).front().action).motion).joints;
        const int handJoint = hand == 0 ? joints.leftHand : joints.rightHand;
        const int elbowJoint = hand == 0 ? joints.leftElbow : joints.rightElbow;
        if (handJoint < 0 || elbowJoint < 0) return;  // a skeleton without arms carries no ball
        SceneCharacter ball;
        ball.name = "ball";
        ball.body = "ball";
        ball.side = 0;
        ball.preset = "prop";
        ball.holder = carrier;
        ball.hand = hand;
        ball.heldFrom = track(carrier).front().start;
        ball.heldTo = freeAt(carrier);
        scene.characters.push_back(std::move(ball));
        const int b = static_cast<int>(scene.characters.size()) - 1;
        if (placeBall) scene.characters.back().keys = heldBallKeys(scene, lib, b);
    }

    bool placeBall = true;  // false for a run of many: its ball is placed after the merge

    Status runOne(const ProgressFn& progress) {
        bool any = false;
        for (std::size_t i = 0; i < patches.patches().size() && !any; ++i) {
            const auto& p = patches.patches()[i];
            any = allowed[i] && !p.tracks[1].empty() && act(p.tracks[1].front().action).is(kTackle);
        }
        if (!any) {
            return makeError("football: no tackle patch in the library (a PatternList like {run, TACKLE, avoid} on a project "
                             "with tackles, e.g. fray-cli demo-library DIR --set football)");
        }
        const int carrier = addCharacter("carrier", 0);
        {
            const RootXf at{{0.0f, 0.0f}, wantedHeading(0)};
            const int first = nextRun(-1, at, at.heading);
            if (first < 0) return makeError("football: the project has no run action for the carrier");
            append(carrier, first, 0.0, at);
        }
        constexpr int kMinLead = 2;   // run steps between two tackles
        constexpr int kMaxLead = 8;
        constexpr double kLeadCost = 300;  // per extra run step before a tackle
        auto forward = [](const RootXf& x) { return static_cast<double>(x.pos.y); };
        auto runStep = [&](std::vector<ActionInstance>& out, RootXf& at, double& t, int& last) {
            const int a = nextRun(last, at, wantedHeading(t));
            out.push_back({a, t, 0.0, t + act(a).duration, at, false, false});
            at = at * act(a).end;
            t += act(a).duration;
            last = a;
        };
        for (int k = 0; k < own.tacklers; ++k) {
            if (freeAt(carrier) >= spec.duration || forward(leaves(carrier)) >= own.goal) break;
            // The carrier's run for up to kMaxLead steps; after each (from the
            // kMinLead-th on) every tackle patch whose run continues it.
            struct Option {
                double score;
                std::size_t patch;
                int lead;
            };
            std::vector<Option> options;
            std::vector<ActionInstance> lead;
            RootXf at = leaves(carrier);
            double t = freeAt(carrier);
            int last = track(carrier).back().action;
            for (int n = 1; n <= kMaxLead; ++n) {
                runStep(lead, at, t, last);
                // The carrier runs round nobody: a step into someone (a tackler
                // still getting up) ends the run here.
                if (penetrates({lead.back()}, carrier)) {
                    lead.pop_back();
                    break;
                }
                if (n < kMinLead || forward(at) >= own.goal) continue;
                const double want = wantedHeading(t);
                const auto boxes = obstacles(t, carrier);
                for (std::size_t i = 0; i < patches.patches().size(); ++i) {
                    const Patch& p = patches.patches()[i];
                    if (!allowed[i] || p.tracks[0].front().start != 0.0 || p.tracks[1].empty()) continue;
                    if (!act(p.tracks[1].front().action).is(kTackle)) continue;
                    if (!lib.continuesInto(last, p.tracks[0].front().action)) continue;
                    const RootXf xf = at * p.tracks[0].front().root.inverse();
                    if (collides(p, xf, boxes)) continue;
                    // s_u: the carrier leaves the patch running the way the user points.
                    const double err = std::fabs(wrapAngle(want - (xf * p.endPlacement(lib, 0)).heading));
                    const double user = 1.0 - err / std::numbers::pi;
                    options.push_back({score(i, densityAround(xf.apply(p.tracks[1].front().root.pos), t), user) - kLeadCost * (n - kMinLead), i, n});
                }
            }
            std::stable_sort(options.begin(), options.end(), [](const Option& x, const Option& y) { return x.score > y.score; });
            const int tackler = addCharacter("tackler-" + std::to_string(k + 1), 1);
            const std::size_t base = track(carrier).size();
            bool placed = false;
            struct Placed {
                std::size_t patch = 0;
                double time = 0;
                RootXf xf;
            } chosen;
            for (std::size_t o = 0; o < options.size() && o < 60 && !placed; ++o) {
                const Option& op = options[o];
                track(carrier).resize(base);
                for (int n = 0; n < op.lead; ++n) track(carrier).push_back(lead[static_cast<std::size_t>(n)]);
                const Patch& p = patches.patches()[op.patch];
                const double tp = freeAt(carrier);
                const RootXf xf = leaves(carrier) * p.tracks[0].front().root.inverse();
                const auto& dive = p.tracks[1].front();
                auto walk = runUp(dive.action, xf * dive.root, tp + dive.start);
                if (walk.empty() && tp + dive.start > 1e-9) continue;  // nothing leads into this tackle
                if (penetrates(walk, tackler)) continue;
                for (auto& w : walk) track(tackler).push_back(w);
                placeTrack(p, 1, tackler, tp, xf);
                // A tackle that misses must miss: the carrier's part of the
                // patch clear of every body, its tackler's dive included, at
                // the scene's 30 Hz samples, where the metrics look (a patch's
                // actions may start between them, and a few avoid patches of
                // a library graze the carrier between their own samples).
                // Tested before the carrier's part is placed: penetrates skips
                // the carrier itself.
                if (p.hits.empty() && penetrates(Composer::placed(p, 0, tp, xf), carrier, true)) {
                    track(tackler).clear();
                    continue;
                }
                placeTrack(p, 0, carrier, tp, xf);
                placeHits(p, {carrier, tackler}, tp);
                stats.locomotionSteps += static_cast<int>(walk.size()) + op.lead;
                ++ownStats.graphJoined;
                ownStats.tacklersPassed += p.hits.empty() ? 1 : 0;
                used(op.patch);
                placed = true;
                chosen = {op.patch, tp, xf};
            }
            if (!placed) {
                // Nobody can come in here: run on and try again further up the field.
                scene.characters.pop_back();
                track(carrier).resize(base);
                if (lead.empty()) {  // boxed in: the step is taken anyway (the metrics will show it)
                    RootXf a0 = leaves(carrier);
                    double t0 = freeAt(carrier);
                    int l0 = track(carrier).back().action;
                    runStep(lead, a0, t0, l0);
                }
                for (const auto& w : lead) track(carrier).push_back(w);
                stats.locomotionSteps += static_cast<int>(lead.size());
                --k;
                if (track(carrier).size() > 2000) return makeError("football: no tackle fits along the carrier's run");
                continue;
            }
            getUpAndStand(tackler);
            if (own.doubles && k + 1 < own.tacklers && secondTackler(chosen.patch, chosen.time, chosen.xf, k + 2)) ++k;
            if (!reportProgress(progress, static_cast<double>(k + 1) / own.tacklers, "compose")) return cancelled();
        }
        // Then on to the goal line.
        for (int guard = 0; guard < 400 && forward(leaves(carrier)) < own.goal + 1.0 && freeAt(carrier) < spec.duration; ++guard) {
            std::vector<ActionInstance> one;
            RootXf at = leaves(carrier);
            double t = freeAt(carrier);
            int last = track(carrier).back().action;
            runStep(one, at, t, last);
            track(carrier).push_back(one.front());
            ++stats.locomotionSteps;
        }
        // The floor marks: the goal line across the run, and the user's arrows
        // where the carrier was when each one was set.
        float lo = 0.0f, hi = 0.0f;
        for (const auto& inst : track(carrier)) {
            const float x = inst.root.pos.x;
            lo = std::min(lo, x), hi = std::max(hi, x);
        }
        const auto goal = static_cast<float>(own.goal);
        scene.marks.push_back({"goal", {glm::vec2(lo - 8.0f, goal), glm::vec2(hi + 8.0f, goal)}});
        for (const auto& d : own.directions) {
            const auto& i = track(carrier)[static_cast<std::size_t>(scene.instanceAt(carrier, d.time))];
            const glm::vec2 at = i.placementAt(lib, i.clipTimeAt(d.time)).pos;
            const glm::vec2 dir = headingVector(d.heading);
            const glm::vec2 tail = at + dir * 1.0f, tip = at + dir * 4.0f;
            scene.marks.push_back({"arrow", {tail, tip, tip - rotateFloor(dir, 0.5) * 0.8f, tip, tip - rotateFloor(dir, -0.5) * 0.8f}});
        }
        for (const auto& inst : track(carrier)) {
            const double into = inst.clipTimeAt(inst.end);
            for (double tau = inst.offset; tau <= into + 1e-9; tau += 1.0 / kSampleRate) {
                if (forward(inst.placementAt(lib, tau)) >= own.goal) {
                    ownStats.goalReached = inst.start + (tau - inst.offset);
                    return {};
                }
            }
        }
        return {};
    }

    // ---- many runs at once (issue 27): own.runs carriers, each with its own
    // tacklers, composed in parallel (run k with seed + k, so the same spec
    // gives the same bytes on any number of threads) and laid out on the floor
    // side by side, each run's floor rectangle clear of the others'.
    struct Lane {
        Scene scene;
        ComposeStats stats;
        std::string error;
        SweptBox extent = SweptBox::empty();
    };

    Status runMany(const ProgressFn& progress) {
        const int n = own.runs;
        std::vector<Lane> lanes(static_cast<std::size_t>(n));
        std::atomic<int> done{0};
        std::atomic<bool> stop{false};
        std::mutex progressMutex;
        tbb::parallel_for(0, n, [&](int k) {
            if (stop.load(std::memory_order_relaxed)) return;
            Lane& lane = lanes[static_cast<std::size_t>(k)];
            FootballSpec one = own;
            one.runs = 1;
            // Each carrier is given its own arrows: the spec's, each turned by
            // up to spread degrees either way (drawn from the run's seed).
            std::mt19937_64 turn(spec.seed * 7919 + static_cast<std::uint64_t>(k));
            std::uniform_real_distribution<double> within(-own.spread, own.spread);
            constexpr double kMaxHeading = 79 * std::numbers::pi / 180;
            for (auto& d : one.directions) d.heading = std::clamp(d.heading + within(turn), -kMaxHeading, kMaxHeading);
            ComposeSpec s = ComposeSpec::of(one);
            static_cast<ComposeCommonSpec&>(s) = spec;
            s.seed = spec.seed + static_cast<std::uint64_t>(k);
            FootballComposer c(lib, patches, s, lane.stats);
            c.placeBall = false;
            Status st = c.ready();
            if (st) st = c.run({});
            if (!st) {
                lane.error = "run " + std::to_string(k + 1) + ": " + st.error().message;
                return;
            }
            lane.scene = std::move(c.scene);
            lane.extent = extentOf(lane.scene);
            const int finished = ++done;
            const std::lock_guard<std::mutex> lock(progressMutex);
            if (!reportProgress(progress, static_cast<double>(finished) / n, "compose")) stop = true;
        });
        if (stop.load()) return cancelled();
        for (const Lane& lane : lanes) {
            if (!lane.error.empty()) return makeError(lane.error);
        }
        // Rows of ceil(sqrt(n)) runs, each run kMargin m from its neighbours.
        constexpr float kMargin = 3.0f;
        const int perRow = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
        float rowZ = 0;
        bool allReached = true;
        double lastGoal = -1;
        for (int row = 0; row * perRow < n; ++row) {
            float x = 0, depth = 0;
            for (int k = row * perRow; k < std::min(n, (row + 1) * perRow); ++k) {
                Lane& lane = lanes[static_cast<std::size_t>(k)];
                const glm::vec2 size = lane.extent.hi - lane.extent.lo;
                const glm::vec2 shift = glm::vec2(x, rowZ) - lane.extent.lo;
                merge(lane, k, shift);
                x += size.x + kMargin;
                depth = std::max(depth, size.y);
                const auto& fs = *lane.stats.part<FootballStats>();
                allReached = allReached && fs.goalReached >= 0;
                lastGoal = std::max(lastGoal, fs.goalReached);
            }
            rowZ += depth + kMargin;
        }
        // The balls from their carriers where they run (as the scene reader places them).
        placeHeldBalls(scene, lib);
        ownStats.goalReached = allReached ? lastGoal : -1;
        return {};
    }

    // The floor rectangle a run's characters and marks cover (bodies included).
    SweptBox extentOf(const Scene& s) const {
        SweptBox box = SweptBox::empty();
        for (const auto& ch : s.characters) {
            for (const auto& inst : ch.track) {
                for (double tau = inst.offset; tau <= inst.clipTimeAt(inst.end) + 1e-9; tau += 0.25) {
                    const glm::vec2 p = inst.placementAt(lib, tau).pos;
                    box.add({p, p});
                }
                const glm::vec2 e = inst.placementAt(lib, inst.clipTimeAt(inst.end)).pos;
                box.add({e, e});
            }
        }
        for (const auto& m : s.marks) {
            for (const auto& p : m.points) box.add({p, p});
        }
        box.lo -= glm::vec2(1.5f), box.hi += glm::vec2(1.5f);  // bodies and falls around the roots
        return box;
    }

    // Appends run k's characters, hits and marks, moved by `shift`, and its stats.
    void merge(const Lane& lane, int k, const glm::vec2& shift) {
        const int base = static_cast<int>(scene.characters.size());
        const RootXf offset{shift, 0.0};
        for (SceneCharacter ch : lane.scene.characters) {
            ch.name = "run-" + std::to_string(k + 1) + "/" + ch.name;
            for (auto& inst : ch.track) inst.root = offset * inst.root;
            for (auto& key : ch.keys) key.at = offset * key.at;
            if (ch.holder >= 0) ch.holder += base;
            scene.characters.push_back(std::move(ch));
        }
        for (HitEvent h : lane.scene.hits) {
            h.attacker += base, h.defender += base;
            scene.hits.push_back(h);
        }
        for (FloorMark m : lane.scene.marks) {
            for (auto& p : m.points) p += shift;
            scene.marks.push_back(std::move(m));
        }
        const ComposeStats& ls = lane.stats;
        stats.patchesUsed += ls.patchesUsed, stats.temporalLinks += ls.temporalLinks, stats.recycled += ls.recycled;
        stats.locomotionSteps += ls.locomotionSteps;
        stats.maxJunctionError = std::max(stats.maxJunctionError, ls.maxJunctionError);
        const auto& fs = *ls.part<FootballStats>();
        ownStats.graphJoined += fs.graphJoined, ownStats.secondTacklers += fs.secondTacklers;
        ownStats.tacklersPassed += fs.tacklersPassed;
    }
};

Status parseFootball(const prep::JsonReader& rd, const Json& j, FootballSpec& s) {
    if (auto st = optionalInt(rd, j, "tacklers", 1, 1000, s.tacklers); !st) return st.error();
    if (auto st = optionalInt(rd, j, "runs", 1, 100000, s.runs); !st) return st.error();
    double spreadDeg = s.spread * 180 / std::numbers::pi;
    if (auto st = optionalNumberIn(rd, j, "", "spread_deg", 0, 45, "degrees", spreadDeg, true); !st) return st.error();
    s.spread = spreadDeg * std::numbers::pi / 180;
    if (auto st = optionalNumber(rd, j, "goal", 0, 1000, "m", s.goal); !st) return st.error();
    if (auto f = rd.field(j, "", "doubles", false); !f) return f.error();
    else if (*f) {
        if (!(*f)->is_boolean()) return rd.error("/doubles", "must be true or false");
        s.doubles = (*f)->get<bool>();
    }
    if (auto f = rd.field(j, "", "directions", false); !f) return f.error();
    else if (*f) {
        if (!(*f)->is_array()) return rd.error("/directions", "must be an array of {time, heading_deg}");
        for (std::size_t i = 0; i < (*f)->size(); ++i) {
            const std::string p = "/directions/" + std::to_string(i);
            const Json& d = (**f)[i];
            if (!d.is_object()) return rd.error(p, "must be an object {time, heading_deg}");
            for (auto it = d.begin(); it != d.end(); ++it) {
                // "at": where the editor drew the arrow; composing does not read it.
                if (it.key() != "time" && it.key() != "heading_deg" && it.key() != "at") return rd.error(p + "/" + it.key(), "unknown field");
            }
            FRAY_TRY(t, rd.numberAt(d, p, "time"));
            FRAY_TRY(h, rd.numberAt(d, p, "heading_deg"));
            if (t < 0 || t > 3600) return rd.error(p + "/time", "must be in [0, 3600] seconds");
            if (!(std::fabs(h) < 80)) {
                return rd.error(p + "/heading_deg", "must be within 80 degrees of the goal direction (0 = straight at the goal line, +Z)");
            }
            if (!s.directions.empty() && t < s.directions.back().time) return rd.error(p + "/time", "directions must be in time order");
            s.directions.push_back({t, h * std::numbers::pi / 180});
        }
    }
    return {};
}

constexpr const char* kFields[] = {"tacklers", "goal", "directions", "doubles", "runs", "spread_deg"};

}  // namespace

const SceneKindModule& footballKind() {
    static const SceneKindModule kind = kindModule<FootballComposer, FootballSpec, parseFootball, noCheck<FootballSpec>>(true, kFields);
    return kind;
}

}  // namespace fray::sim::detail
