// The rat scene: people step out of the way of a rat and bump into their neighbours (SPEC 4.5).
// The composer is declared in compose_rat.h; its ways out are in compose_rat_ways.cpp.
#include "compose_rat.h"

namespace fray::sim::detail {

Status RatComposer::run(const ProgressFn& progress) {
    ratBody.body = "rat";
    ratBody.keys = ratKeys();
    const auto& keys = ratBody.keys;
    const double ratEnd = keys.back().time;
    const double until = ratEnd + 2.0;  // reactions and steps settle
    std::vector<int> pushed;
    for (int a = 0; a < lib.size(); ++a) {
        if (act(a).is(kPushed) && !act(a).is(kFalling)) pushed.push_back(a);
    }
    if (pushed.empty()) {
        for (int a = 0; a < lib.size(); ++a) {
            if (act(a).is(kPushed)) pushed.push_back(a);
        }
    }
    pushedPool = rules.emplace(lib).addPool(pushed);
    measureHoldWander();
    holdRootInverse = lib.rootAt(hold, 0).inverse();
    discs.emplace(lib, kTouchShrink);
    pelvisPaths = pelvisPathDiscs(lib);
    measureCoreHulls();
    spheres.emplace(lib, kTouchShrink);
    measureFootHulls();
    if (!findWays()) return makeError(kNoWays);
    makeRatPatches();

    // The crowd: people standing within `band` of the trajectory, `spacing` apart.
    std::vector<Bystander> crowd;
    glm::vec2 lo = own.ratPath.front(), hi = lo;
    for (const auto& p : own.ratPath) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const auto band = static_cast<float>(own.band);
    lo -= glm::vec2(band), hi += glm::vec2(band);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    // Spacing against those already standing nearby (the grid's query is
    // a superset of those within `spacing`; the same test then decides).
    FloorGrid placed(static_cast<float>(std::max(own.spacing, 0.5)));
    const float query = static_cast<float>(own.spacing) + 0.05f;
    for (int tries = 0; static_cast<int>(crowd.size()) < own.crowd && tries < 400 * own.crowd; ++tries) {
        const glm::vec2 q(lo.x + static_cast<float>(unit(rng)) * (hi.x - lo.x), lo.y + static_cast<float>(unit(rng)) * (hi.y - lo.y));
        const double heading = wrapAngle(unit(rng) * 2 * std::numbers::pi);
        if (distanceToPolyline(q, own.ratPath) > own.band) continue;
        if (glm::length(q - own.ratPath.front()) < 1.5f) continue;  // not on the rat's hole
        const auto& around = placed.near(q, query);
        if (std::any_of(around.begin(), around.end(), [&](int k) {
                return static_cast<double>(glm::length(crowd[static_cast<std::size_t>(k)].spot - q)) < own.spacing;
            })) {
            continue;
        }
        Bystander b;
        b.spot = q;
        b.at = {q, heading};
        placed.insert(static_cast<int>(crowd.size()), q);
        crowd.push_back(b);
    }
    if (crowd.empty()) return makeError("rat: nobody could stand near the trajectory (widen band or lower spacing)");
    for (std::size_t k = 0; k < crowd.size(); ++k) spotGrid.insert(static_cast<int>(k), crowd[k].spot);
    for (auto& b : crowd) {
        b.standRoot = b.at * holdRootInverse;
        b.standHull = placedHull(hold, b.at * lib.rootAt(hold, 0).inverse());
        refreshDiscs(b);
    }
    findNeighbours(crowd);
    // The rat's closest approach to each person, sampled every 0.02 s:
    // the samples once for everyone, in blocks with a bounding circle, so
    // a person looks only at the blocks that can beat its best so far
    // (in time order: the same first closest sample as a pass over all).
    std::vector<double> sampleTime;
    std::vector<glm::vec2> samplePos;
    for (double t = own.ratStart; t <= ratEnd + 1e-9; t += 0.02) {
        sampleTime.push_back(t);
        samplePos.push_back(creatureAt(ratBody, t).pos);
    }
    constexpr std::size_t kBlock = 32;
    struct Block {
        glm::vec2 centre{0.0f};
        double radius = 0;
    };
    std::vector<Block> blocks;
    for (std::size_t b0 = 0; b0 < samplePos.size(); b0 += kBlock) {
        const std::size_t b1 = std::min(samplePos.size(), b0 + kBlock);
        glm::vec2 lo2 = samplePos[b0], hi2 = lo2;
        for (std::size_t k = b0; k < b1; ++k) lo2 = glm::min(lo2, samplePos[k]), hi2 = glm::max(hi2, samplePos[k]);
        Block blk{0.5f * (lo2 + hi2), 0.0};
        for (std::size_t k = b0; k < b1; ++k) blk.radius = std::max(blk.radius, static_cast<double>(glm::length(samplePos[k] - blk.centre)));
        blocks.push_back(blk);
    }
    // And the blocks in groups of kBlock with a circle round theirs: a
    // group that cannot come closer than the best so far is passed over whole.
    std::vector<Block> groups;
    for (std::size_t g0 = 0; g0 < blocks.size(); g0 += kBlock) {
        const std::size_t g1 = std::min(blocks.size(), g0 + kBlock);
        const std::size_t k0 = g0 * kBlock, k1 = std::min(samplePos.size(), g1 * kBlock);
        glm::vec2 lo2 = samplePos[k0], hi2 = lo2;
        for (std::size_t k = k0; k < k1; ++k) lo2 = glm::min(lo2, samplePos[k]), hi2 = glm::max(hi2, samplePos[k]);
        Block grp{0.5f * (lo2 + hi2), 0.0};
        for (std::size_t k = k0; k < k1; ++k) grp.radius = std::max(grp.radius, static_cast<double>(glm::length(samplePos[k] - grp.centre)));
        groups.push_back(grp);
    }
    tbb::parallel_for(std::size_t{0}, crowd.size(), [&](std::size_t i) {
        Bystander& b = crowd[i];
        for (std::size_t blk = 0; blk < blocks.size(); ++blk) {
            if (blk % kBlock == 0) {
                // Every sample of the group is at least this far (the same margin as a block's).
                const Block& grp = groups[blk / kBlock];
                const double scale = static_cast<double>(glm::length(grp.centre)) + static_cast<double>(glm::length(b.spot));
                const double bound = static_cast<double>(glm::length(grp.centre - b.spot)) - grp.radius - 1e-3 - 1e-5 * scale;
                if (bound > b.passDistance) {
                    blk += kBlock - 1;
                    continue;
                }
            }
            // A sample of the block is at least this far (a margin for the float rounding).
            const double scale = static_cast<double>(glm::length(blocks[blk].centre)) + static_cast<double>(glm::length(b.spot));
            const double bound = static_cast<double>(glm::length(blocks[blk].centre - b.spot)) - blocks[blk].radius - 1e-3 - 1e-5 * scale;
            if (bound > b.passDistance) continue;
            const std::size_t k1 = std::min(samplePos.size(), (blk + 1) * kBlock);
            for (std::size_t k = blk * kBlock; k < k1; ++k) {
                const double d = static_cast<double>(glm::length(samplePos[k] - b.spot));
                if (d < b.passDistance) b.passDistance = d, b.passTime = sampleTime[k];
            }
        }
        b.near = b.passDistance < own.reach;
    });
    for (const auto& b : crowd) ownStats.ratNear += b.near ? 1 : 0;
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < crowd.size(); ++i) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return crowd[a].passTime < crowd[b].passTime; });

    std::vector<Push> log;  // every push, for the scene's contacts
    int done = 0;
    // The ways out that keep the rat off each near person's feet, worked
    // out in parallel a block of people at a time (in the order the rat
    // reaches them); the crowd then decides among them one person after another.
    constexpr std::size_t kBlockPeople = 256;
    // The next block's are worked out while this block's people decide
    // (clearWays reads a person's spot, placement and closest approach,
    // which no decision changes; each writes its own clearOf), so a core
    // idle during the decisions has work; a decision's own batches run
    // isolated, never waiting on a block's people.
    std::vector<std::vector<ClearWay>> clearOf(crowd.size());
    auto blockWays = [&](std::size_t o0) {
        const std::size_t o1 = std::min(order.size(), o0 + kBlockPeople);
        tbb::parallel_for(o0, o1, [&](std::size_t o) {
            const Bystander& q = crowd[order[o]];
            if (q.near) clearOf[order[o]] = clearWays(q, until);
        });
    };
    tbb::task_group ahead;
    struct WaitAhead {
        tbb::task_group& group;
        ~WaitAhead() {
            try {
                group.wait();
            } catch (...) {  // leaving already (cancelled, or thrown): what it threw is dropped
            }
        }
    } waitAhead{ahead};  // (every way out of the loop waits for it; the loop's own waits rethrow)
    for (std::size_t oi = 0; oi < order.size(); ++oi) {
        if (oi % kBlockPeople == 0) {
            if (oi == 0) blockWays(0);
            else ahead.wait();
            if (oi + kBlockPeople < order.size()) ahead.run([&blockWays, next = oi + kBlockPeople] { blockWays(next); });
        }
        const std::size_t i = order[oi];
        const std::vector<ClearWay> ways1 = std::move(clearOf[i]);
        Bystander& b = crowd[i];
        if (!reportProgress(progress, static_cast<double>(done++) / static_cast<double>(crowd.size()), "compose")) {
            return cancelled();
        }
        if (!b.near || !b.plan.empty()) continue;  // far off, or already pushed out of the way
        // The {run, AVOID} patches of the nearest configurations, placed
        // where the person stands and tried against the rat's actual run
        // (it may curve) and the neighbours: candidates minus colliding ones.
        struct Option {
            double score = -std::numeric_limits<double>::max();
            std::vector<ActionInstance> plan;
            double start = 0, clearance = 0;
            std::vector<Push> pushes;
        } best;
        // Clear of the rat by a safe margin; bumping a neighbour as
        // the spec likes it (0: avoid it, 1: seek it); the latest
        // start (people react at the last moment).
        const double bumpBonus = 0.2 * own.bumps - 0.05;
        std::vector<std::pair<double, std::size_t>> bases;  // (score without bumps, candidate)
        for (std::size_t c = 0; c < ways1.size(); ++c) {
            const double ts = b.passTime - ways1[c].patch.lead;
            bases.push_back({std::min(ways1[c].clear, 0.25) + 0.01 * (ts - b.passTime) + 1e-4 * unit(rng), c});
        }
        // The body tests in the order of the best score each could reach,
        // until none left can beat the best found: the candidate of the
        // highest score, the first of equals, as a pass over all in order.
        std::stable_sort(bases.begin(), bases.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
        std::size_t bestC = SIZE_MAX;
        std::vector<std::size_t> order1(ways1.size());  // per candidate: its place in `bases`
        // One candidate's body tests against the crowd as it stands (read
        // only: each candidate starts from the same crowd, so candidates can
        // be tried in parallel). Empty `plan`: it bumps someone it may not.
        struct Tried {
            std::vector<ActionInstance> plan;
            std::vector<Push> pushes;
        };
        // Per way: the neighbours firstTouch keeps for its plans against
        // the crowd as it stands (the same at every lead: the plans from
        // the way's start on share their actions and roots), with those
        // instances to tell a plan that differs (its last idle left out
        // near the scene's end).
        struct Kept {
            bool made = false;
            std::vector<std::pair<int, RootXf>> from;  // the plan's instances from the way's start on
            std::vector<std::size_t> neighbours;
            std::unique_ptr<ApartMemo> memo;  // firstTouch's bits for its plans and them (none: too many slots)
        };
        std::vector<Kept> keptOf(ways.size());
        auto keptFor = [&](const std::vector<ActionInstance>& plan, double ts, std::size_t way) -> const Kept* {
            Kept& k = keptOf[way];
            const auto k0 = playingAt(plan, ts);
            auto same = [&] {
                if (k.from.size() != plan.size() - k0) return false;
                for (std::size_t j = k0; j < plan.size(); ++j) {
                    const auto& [action, root] = k.from[j - k0];
                    if (action != plan[j].action || root.pos != plan[j].root.pos || root.heading != plan[j].root.heading) return false;
                }
                return true;
            };
            if (!k.made) {
                k.made = true;
                for (std::size_t j = k0; j < plan.size(); ++j) k.from.emplace_back(plan[j].action, plan[j].root);
                keptNeighbours(CrowdView(crowd), i, plan, ts, SIZE_MAX, k.neighbours);
                if (!k.neighbours.empty()) k.memo = apartMemo(crowd, plan, k0, k.neighbours);
            }
            return same() ? &k : nullptr;
        };
        auto tryCandidate = [&](std::size_t c, std::vector<ActionInstance> plan, const Kept* kept) {
            Tried out;
            const RatPatch& patch = ways1[c].patch;
            const double ts = b.passTime - patch.lead;
            const double settled = until;  // everyone stands still afterwards: touching later counts too
            const auto [other, when] = firstTouch(CrowdView(crowd), i, plan, ts, settled, SIZE_MAX, kept ? &kept->neighbours : nullptr,
                                                  kept ? kept->memo.get() : nullptr);
            if (other >= 0) {
                CrowdView trial(crowd);
                trial.set(i, plan);
                const detail::BodyPose mine = bodyIn(plan, b.at, when);
                auto chain = push(trial, static_cast<std::size_t>(other), i, mine.root * lib.rootAt(mine.action, mine.tau),
                                  when, until, 1);
                if (!chain) return out;
                // With the pushed ones moving, the rest of the way out
                // touches nobody, the pushed one included once the
                // contact is over.
                for (const auto& m : *chain) trial.set(m.who, m.plan);
                if (firstTouch(trial, i, plan, when, settled, static_cast<std::size_t>(other)).first >= 0) return out;
                if (firstTouch(trial, i, plan, when + kContactWindow, settled).first >= 0) return out;
                out.pushes = std::move(*chain);
            }
            out.plan = std::move(plan);
            return out;
        };
        // The candidates in `bases` order. The result is the candidate of
        // the highest score, the first of equals, among those whose trial
        // keeps a plan: whatever order they are tried in, as long as every
        // one that could still win is tried. A way out whose neighbours
        // firstTouch keeps none of (keptFor) touches nobody: its trial
        // keeps its plan with no bump, so it is taken at its base score
        // here. The others are tried a batch at a time, the batch's body
        // tests in parallel (the same best, the same bytes, whatever the
        // number of threads; a batch may test a few candidates that can
        // no longer win).
        std::vector<std::size_t> batch;  // candidates
        std::vector<std::vector<ActionInstance>> plans;
        std::vector<const Kept*> kept;
        std::vector<Tried> tried;
        auto take = [&](std::size_t c, double score, std::vector<ActionInstance>&& plan, std::vector<Push>&& pushes) {
            if (score > best.score || (score == best.score && c < bestC)) {
                best = {score, std::move(plan), b.passTime - ways1[c].patch.lead, ways1[c].clear, std::move(pushes)};
                bestC = c;
            }
        };
        auto runBatch = [&] {
            tried.assign(batch.size(), {});
            tbb::this_task_arena::isolate([&] {
                tbb::parallel_for(
                    std::size_t{0}, batch.size(), [&](std::size_t k) { tried[k] = tryCandidate(batch[k], std::move(plans[k]), kept[k]); },
                    tbb::simple_partitioner{});
            });
            for (std::size_t k = 0; k < batch.size(); ++k) {
                Tried& r = tried[k];
                if (r.plan.empty()) continue;  // it bumps someone it may not
                const double base = bases[order1[batch[k]]].first;
                take(batch[k], base + (r.pushes.empty() ? 0.0 : bumpBonus), std::move(r.plan), std::move(r.pushes));
            }
            batch.clear(), plans.clear(), kept.clear();
        };
        for (std::size_t q = 0; q < bases.size(); ++q) {
            const auto& [base, c] = bases[q];
            const double reach = base + std::max(0.0, bumpBonus);  // the most it can score
            if (reach < best.score) break;                          // nor can any after it
            if (reach == best.score && c > bestC) continue;         // cannot win
            const RatPatch& patch = ways1[c].patch;
            const auto& way = ways[static_cast<std::size_t>(patch.way)];
            const double ts = b.passTime - patch.lead;
            auto plan = planMove(b.at, ts, way, 0.0, b.at * lib.rootAt(way.front(), 0).inverse(), false, until);
            const auto* near = keptFor(plan, ts, static_cast<std::size_t>(patch.way));
            if (near && near->neighbours.empty()) {
                take(c, base, std::move(plan), {});
                continue;
            }
            order1[c] = q;
            batch.push_back(c), plans.push_back(std::move(plan)), kept.push_back(near);
            if (batch.size() == kCandidateBatch) runBatch();
        }
        if (!batch.empty()) runBatch();
        if (!best.plan.empty()) {
            b.plan = std::move(best.plan);
            refreshDiscs(b);
            ++ownStats.ratAvoided;
            ++stats.patchesUsed;
            // clearWays measured it up to kClearScored: beyond, measured in full.
            const double clearance = best.clearance < kClearScored ? best.clearance : ratClearance(b, b.plan);
            ownStats.ratClearance = ownStats.ratClearance < 0 ? clearance : std::min(ownStats.ratClearance, clearance);
            for (auto& m : best.pushes) {
                if (crowd[m.who].near) ++ownStats.ratPushed;
                commit(crowd, std::move(m), log);
            }
            continue;
        }
        // No way out: it reels back as the rat runs into its feet (a push
        // from the rat, a little before it arrives).
        bool reeled = false;
        for (double lead : {0.1, 0.3, 0.5}) {
            const double t = std::max(0.2, b.passTime - lead);
            auto chain = push(CrowdView(crowd), i, SIZE_MAX, creatureAt(ratBody, t), t, until, 1);
            if (!chain) continue;
            for (auto& m : *chain) commit(crowd, std::move(m), log);
            reeled = true;
            break;
        }
        ++(reeled ? ownStats.ratStartled : ownStats.ratRunOver);
    }

    // The timeline: the rat first, then everyone, standing where they have no plan.
    auto& rat = scene.characters[static_cast<std::size_t>(addCharacter("rat", 1))];
    rat.body = "rat";
    rat.keys = keys;
    rat.preset = "creature";
    std::vector<int> index(crowd.size());
    for (std::size_t k = 0; k < crowd.size(); ++k) {
        auto& b = crowd[k];
        const int c = addCharacter("person-" + std::to_string(k + 1), 0);
        index[k] = c;
        track(c) = b.plan.empty() ? standing(b.at, until) : b.plan;
    }
    // The bumps as contacts (who pushed whom, when), for metrics and viewers.
    for (const auto& m : log) {
        if (m.by == SIZE_MAX) continue;  // reeled back from the rat: no one pushed it
        const detail::BodyPose pusher = bodyIn(crowd[m.by].plan, crowd[m.by].at, m.time);
        HitEvent h;
        h.time = m.time;
        h.attacker = index[m.by];
        h.defender = index[m.who];
        h.attackAction = pusher.action;
        h.effector = kTorso, h.target = kTorso;  // body against body
        h.speed = 1.0;                           // a walking-pace shove (m/s)
        h.impulse = detail::InteractionEngine::impulse(h.speed, kTorso);
        scene.hits.push_back(h);
    }
    scene.marks.push_back({"trail", own.ratPath});
    return {};
}

namespace {

Status parseRat(const prep::JsonReader& rd, const Json& j, RatSpec& s) {
    if (auto f = rd.field(j, "", "rat", false); !f) return f.error();
    else if (*f) {
        const Json& r = **f;
        if (!r.is_object()) return rd.error("/rat", "must be an object {path, speed, start}");
        for (auto it = r.begin(); it != r.end(); ++it) {
            if (it.key() != "path" && it.key() != "speed" && it.key() != "start") return rd.error("/rat/" + it.key(), "unknown field");
        }
        FRAY_TRY(pf, rd.field(r, "/rat", "path"));
        if (!pf->is_array()) return rd.error("/rat/path", "must be an array of [x, z] points (the rat's trajectory)");
        if (pf->size() > 10000) return rd.error("/rat/path", "has more than 10000 points");
        double length = 0;
        for (std::size_t i = 0; i < pf->size(); ++i) {
            const std::string p = "/rat/path/" + std::to_string(i);
            const Json& q = (*pf)[i];
            if (!q.is_array() || q.size() != 2) return rd.error(p, "must be [x, z]");
            FRAY_TRY(x, rd.number(q[0], p + "/0"));
            FRAY_TRY(z, rd.number(q[1], p + "/1"));
            if (!(std::fabs(x) <= 1e4) || !(std::fabs(z) <= 1e4)) return rd.error(p, "is too far out");
            const glm::vec2 v(static_cast<float>(x), static_cast<float>(z));
            if (!s.ratPath.empty()) length += static_cast<double>(glm::length(v - s.ratPath.back()));
            s.ratPath.push_back(v);
        }
        if (s.ratPath.size() < 2 || length < 0.5) {
            return rd.error("/rat/path", "the rat's trajectory is empty: draw at least two points, 0.5 m apart or more");
        }
        if (auto st = optionalNumberIn(rd, r, "/rat", "speed", 0.3, 10, "m/s", s.ratSpeed, true); !st) return st.error();
        if (auto st = optionalNumberIn(rd, r, "/rat", "start", 0, 600, "s", s.ratStart, true); !st) return st.error();
    }
    if (auto st = optionalInt(rd, j, "crowd", 1, 20000, s.crowd); !st) return st.error();
    if (auto st = optionalNumber(rd, j, "band", 0, 100, "m", s.band); !st) return st.error();
    if (auto st = optionalNumber(rd, j, "spacing", 0.5, 20, "m", s.spacing); !st) return st.error();
    if (auto st = optionalNumber(rd, j, "reach", 0, 10, "m", s.reach); !st) return st.error();
    if (auto f = rd.field(j, "", "bumps", false); !f) return f.error();
    else if (*f) {
        FRAY_TRY(x, rd.number(**f, "/bumps"));
        if (!(x >= 0 && x <= 1)) return rd.error("/bumps", "must be in [0, 1] (0: people avoid bumping into each other, 1: they seek it)");
        s.bumps = x;
    }
    return {};
}

Status checkRat(const prep::JsonReader& rd, const RatSpec& s) {
    if (s.ratPath.empty()) return rd.error("/rat", "a rat scene needs the rat's trajectory: \"rat\": {\"path\": [[x, z], ...]}");
    return {};
}

constexpr const char* kFields[] = {"rat", "crowd", "band", "spacing", "reach", "bumps"};

}  // namespace

const SceneKindModule& ratKind() {
    static const SceneKindModule kind = kindModule<RatComposer, RatSpec, parseRat, checkRat>(false, kFields);
    return kind;
}

}  // namespace fray::sim::detail

namespace fray::sim {

Result<std::vector<RatAvoidPatch>> ratAvoidPatches(const ActionLibrary& lib, const ComposeSpec& spec) {
    using detail::RatComposer;
    if (!spec.part<RatSpec>()) return makeError(ErrorKind::InvalidInput, "ratAvoidPatches needs a spec of kind \"rat\"");
    const PatchLibrary none;
    ComposeStats st;
    RatComposer c(lib, none, spec, st);
    if (c.hold < 0) return makeError("the project has no idle action (characters need one to wait)");
    if (!c.findWays()) return makeError(RatComposer::kNoWays);
    c.holdRootInverse = lib.rootAt(c.hold, 0).inverse();
    c.makeRatPatches();
    std::vector<RatAvoidPatch> out;
    for (int l = -c.ratLaterals; l <= c.ratLaterals; ++l) {
        for (int f = 0; f < RatComposer::kRatFacings; ++f) {
            for (const auto& p : c.ratTable[c.ratCell(l, f)]) {
                out.push_back({l * RatComposer::kRatLateralStep, RatComposer::ratFacingAt(f), c.ways[static_cast<std::size_t>(p.way)], p.lead,
                               p.clearance});
            }
        }
    }
    return out;
}

}  // namespace fray::sim
