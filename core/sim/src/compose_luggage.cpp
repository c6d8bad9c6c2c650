// Luggage: an item passed along a chain of porters, each recycled after handing it on (SPEC 4.5).
#include "compose_kinds.h"
#include "fray/sim/compose/luggage.h"

namespace fray::sim::detail {

namespace {

struct LuggageComposer : KindComposer<LuggageSpec> {
    using KindComposer::KindComposer;

    // A porter who has handed the item on walks 2.5-4 m away, in the first
    // direction (away from the carrier first) whose walk touches nobody.
    bool stepAside(int c, int carrier) {
        const RootXf g = leaves(c);
        glm::vec2 away = g.pos - leaves(carrier).pos;
        if (glm::length(away) < 1e-3f) away = -headingVector(g.heading);
        away = glm::normalize(away);
        for (float dist : {2.5f, 4.0f}) {
            for (double turn : {0.0, 0.8, -0.8, 1.6, -1.6, 2.4, -2.4}) {
                const glm::vec2 dir = rotateFloor(away, turn);
                RootXf spot;
                spot.pos = g.pos + dir * dist;
                spot.heading = angleOf(-dir);
                std::vector<ActionInstance> walk;
                auto [end, when] = locomote(c, -1, g, freeAt(c), track(c).back().action, spot, 0.0, walk);
                if (walk.empty() || glm::length(end.pos - g.pos) < 1.0f || penetrates(walk, c)) continue;
                // Room to wait there: nobody within 1 m of the spot.
                bool room = true;
                for (int o = 0; o < static_cast<int>(scene.characters.size()) && room; ++o) {
                    if (o != c && !track(o).empty()) room = rectDistance(bodyBox(o, when), end.pos) >= 1.0f;
                }
                if (!room) continue;
                for (auto& w : walk) track(c).push_back(w);
                stats.locomotionSteps += static_cast<int>(walk.size());
                return true;
            }
        }
        return false;
    }

    // ---- luggage: an item passed along a chain of porters; whoever has handed
    // it on is recycled as a later receiver.
    // Receiver rc walks over to the hand-over's goal, planned backward from
    // it: it sets off as late as it can (never before it is free) and arrives
    // when the carrier is ready at t0; re-planned until the timing settles.
    // Straight there, or round the others by a point 2 m off to either side
    // of the goal. False when no way gets there untouched.
    bool walkOver(int rc, int carrier, const RootXf& goal, double t0, std::vector<ActionInstance>& walk, double& arrive) {
        const RootXf from = leaves(rc);
        const glm::vec2 back = glm::length(from.pos - goal.pos) > 1e-3f ? glm::normalize(from.pos - goal.pos) : glm::vec2(0, 1);
        for (double turn : {0.0, 1.0, -1.0, 2.0, -2.0}) {
            RootXf end;
            double when = 0, shift = std::max(freeAt(rc), t0 - 3.0);
            RootXf via;
            via.pos = goal.pos + rotateFloor(back, turn) * 2.0f;
            via.heading = angleOf(goal.pos - via.pos);
            for (int pass = 0; pass < 4; ++pass) {
                walk.clear();
                RootXf mid = from;
                double midTime = 0;
                if (turn != 0.0) std::tie(mid, midTime) = locomote(rc, carrier, from, 0.0, track(rc).back().action, via, shift, walk);
                std::tie(end, when) = locomote(rc, carrier, mid, midTime, walk.empty() ? track(rc).back().action : walk.back().action,
                                               goal, shift, walk);
                const double next = std::max(freeAt(rc), t0 - when);
                if (std::fabs(next - shift) < 1e-9) break;
                shift = next;
            }
            for (auto& w : walk) w.start += shift, w.end += shift;
            if (glm::length(end.pos - goal.pos) > 0.3f || penetrates(walk, rc)) continue;
            arrive = shift + when;
            stats.maxJunctionError = std::max(stats.maxJunctionError, static_cast<double>(glm::length(end.pos - goal.pos)));
            return true;
        }
        return false;
    }

    // The waiting porters stand in a row beside the first receiver rc, each
    // where its body touches nobody for the first hand-over.
    Status lineUp(const std::vector<int>& porters, int rc) {
        const RootXf r = leaves(rc);
        int row = 1;
        for (int c : porters) {
            if (!track(c).empty()) continue;
            for (int tries = 0; tries < 40; ++tries, ++row) {
                RootXf spot = r;
                spot.pos = r.pos - headingVector(r.heading) * (1.2f * static_cast<float>(row)) +
                           rotateFloor(glm::vec2(1.5f, 0.0f), r.heading);
                const ActionInstance wait{hold, 0.0, 0.0, freeAt(rc), spot * lib.rootAt(hold, 0).inverse(), false, false};
                if (penetrates({wait}, c)) continue;
                track(c).push_back(wait);
                ++row;
                break;
            }
            if (track(c).empty()) return makeError("luggage: no room for porter " + std::to_string(c + 1) + " to wait");
        }
        return {};
    }

    Status run(const ProgressFn& progress) {
        std::vector<std::size_t> handoffs;  // patches where character 1 hands and character 2 receives
        for (std::size_t i = 0; i < patches.patches().size(); ++i) {
            if (!allowed[i]) continue;
            const auto& p = patches.patches()[i];
            auto has = [&](int role, const char* annotation) {
                return std::any_of(p.tracks[static_cast<std::size_t>(role)].begin(), p.tracks[static_cast<std::size_t>(role)].end(),
                                   [&](const ActionInstance& inst) { return act(inst.action).has(annotation); });
            };
            if (has(0, "hand") && has(1, "receive") && act(p.tracks[0].front().action).has("carry")) handoffs.push_back(i);
        }
        if (handoffs.empty()) return makeError("luggage: the patch library has no patch where character 1 hands and character 2 receives");
        nearDistance = 0.25f;
        standWhenDone = true;
        if (own.porters < 2) return makeError("luggage: needs at least 2 porters");
        std::vector<int> porters;
        for (int k = 0; k < own.porters; ++k) porters.push_back(addCharacter("porter-" + std::to_string(k + 1), 0));
        // The first hand-over at the origin; the other porters wait in a row behind the receiver.
        int prev = -1, carrier = porters[0], aside = -1, retries = 0;
        std::vector<Pass> passes;
        std::vector<double> lastUsed(porters.size(), -1.0);  // per porter index
        auto porterIndex = [&](int c) { return static_cast<int>(std::find(porters.begin(), porters.end(), c) - porters.begin()); };
        for (int k = 0; k < own.handoffs; ++k) {
            const double t0 = track(carrier).empty() ? 0.0 : freeAt(carrier);
            if (t0 >= spec.duration) break;
            const RootXf at = track(carrier).empty() ? RootXf{} : leaves(carrier);
            std::vector<std::size_t> cands;
            if (prev >= 0) {
                for (const auto& l : patches.temporal()[static_cast<std::size_t>(prev)]) {
                    if (l.shared == 1 && l.roles == 1 && std::binary_search(handoffs.begin(), handoffs.end(), static_cast<std::size_t>(l.to))) {
                        cands.push_back(static_cast<std::size_t>(l.to));
                    }
                }
            }
            const bool linked = !cands.empty();
            if (!linked) cands = handoffs;
            // The receiver: the porter free for longest (never the carrier);
            // when that one has failed to reach the carrier twice, the next.
            std::vector<int> free;
            for (std::size_t j = 0; j < porters.size(); ++j) {
                if (porters[j] != carrier) free.push_back(static_cast<int>(j));
            }
            std::stable_sort(free.begin(), free.end(), [&](int x, int y) {
                return lastUsed[static_cast<std::size_t>(x)] < lastUsed[static_cast<std::size_t>(y)];
            });
            const int receiver = free[std::min(static_cast<std::size_t>(retries / 2), free.size() - 1)];
            const int rc = porters[static_cast<std::size_t>(receiver)];
            struct Option {
                double score;
                std::size_t patch;
            };
            std::vector<Option> options;
            for (std::size_t i : cands) {
                const Patch& p = patches.patches()[i];
                options.push_back({score(i, 0, 0) + (track(carrier).empty() || lib.startNode()[static_cast<std::size_t>(p.tracks[0].front().action)] ==
                                                                               lib.endNode()[static_cast<std::size_t>(track(carrier).back().action)]
                                                          ? 1.0
                                                          : 0.0),
                                   i});
            }
            std::stable_sort(options.begin(), options.end(), [](const Option& x, const Option& y) { return x.score > y.score; });
            // The other porters, standing where they wait: the hand-over must not
            // touch them (the last giver steps aside once this one is placed).
            Print others;
            for (int c : porters) {
                if (c != carrier && c != rc && c != aside && !track(c).empty()) others.add(bodyBox(c, std::max(t0, freeAt(c))));
            }
            bool placed = false;
            for (std::size_t o = 0; o < options.size() && o < 60 && !placed; ++o) {
                const Patch& p = patches.patches()[options[o].patch];
                const RootXf xf = at * p.tracks[0].front().root.inverse();
                Print print = footprint(p, 0, xf);
                for (const auto& b : footprint(p, 1, xf).parts) print.add(b);
                if (!others.parts.empty() && others.overlaps(print, 0.0f)) continue;
                const RootXf goal = xf * p.tracks[1].front().root;
                // To take this option back: the tracks' lengths before it.
                const std::size_t kept[] = {track(carrier).size(), track(rc).size(), aside >= 0 ? track(aside).size() : 0};
                const int keptSteps = stats.locomotionSteps;
                const double keptJunction = stats.maxJunctionError;
                // The receiver walks over from where it is (it starts next to the goal the first time).
                std::vector<ActionInstance> walk;
                double arrive = t0;
                if (!track(rc).empty()) {
                    if (!walkOver(rc, carrier, goal, t0, walk, arrive)) continue;
                    if (!walk.empty()) waitUntil(rc, walk.front().start);
                }
                const double start = std::max(t0, arrive);
                if (!track(carrier).empty()) waitUntil(carrier, start);
                for (auto& w : walk) track(rc).push_back(w);
                if (!track(rc).empty()) waitUntil(rc, start);
                placeTrack(p, 0, carrier, start, xf);
                placeTrack(p, 1, rc, start, xf);
                // The previous giver steps out of the way now that this
                // hand-over is known (its walk is checked against it) and
                // waits there to be recycled. Where it cannot, or where the
                // hand-over would touch someone on the move (the footprint
                // test above sees where people stand, not where they walk):
                // the next option instead.
                const auto added = [&](int c, std::size_t from) {
                    return std::vector<ActionInstance>(track(c).begin() + static_cast<std::ptrdiff_t>(from), track(c).end());
                };
                const bool clear = (aside < 0 || aside == rc || stepAside(aside, carrier)) &&
                                   !penetrates(added(carrier, kept[0]), carrier) && !penetrates(added(rc, kept[1]), rc);
                if (!clear) {
                    track(carrier).resize(kept[0]);
                    track(rc).resize(kept[1]);
                    if (aside >= 0) track(aside).resize(kept[2]);
                    stats.locomotionSteps = keptSteps;
                    stats.maxJunctionError = keptJunction;
                    continue;
                }
                stats.locomotionSteps += static_cast<int>(walk.size());
                passes.push_back({carrier, rc, start, start + p.duration});
                used(options[o].patch);
                (linked ? stats.temporalLinks : stats.recycled) += 1;
                prev = static_cast<int>(options[o].patch);
                lastUsed[static_cast<std::size_t>(porterIndex(carrier))] = start;
                lastUsed[static_cast<std::size_t>(receiver)] = start;
                placed = true;
            }
            if (!placed) {
                // Nobody can reach the carrier where it stands: it carries on a
                // step (or turns) and the hand-over is tried again from there.
                auto when = [&] {
                    char buf[32];
                    std::snprintf(buf, sizeof buf, "%.2f s", t0);
                    return std::string(buf);
                };
                if (++retries > 6 || track(carrier).empty()) {
                    return makeError("luggage: no porter can reach porter " + std::to_string(porterIndex(carrier) + 1) + " to take the item at " +
                                     when() + " (it moved on and was tried again 6 times; try another seed or fewer porters)");
                }
                // A carrying walk or turn that continues its last action; where
                // none does (it has put the item down), any carrying action
                // that does (picking it up again).
                int step = -1;
                for (const bool moving : {true, false}) {
                    for (int i = 0; i < lib.size(); ++i) {
                        const auto& a = act(i);
                        if (!a.has("carry") || (moving && !(a.is(kWalk) || a.is(kTurn))) || a.has("hand") || a.has("receive")) continue;
                        if (lib.startNode()[static_cast<std::size_t>(i)] != lib.endNode()[static_cast<std::size_t>(track(carrier).back().action)]) continue;
                        if (step < 0 || (rng() & 1)) step = i;
                    }
                    if (step >= 0) break;
                }
                if (step < 0) {
                    return makeError("luggage: porter " + std::to_string(receiver + 1) + " cannot reach the hand-over at " + when() +
                                     ", and the carrier has no carrying step that continues its '" + act(track(carrier).back().action).name +
                                     "' (try another seed)");
                }
                // The last giver leaves first (it stands where the carrier
                // would go), and the others wait where they are (their idles
                // written now) while the carrier moves.
                if (aside >= 0 && aside != rc && stepAside(aside, carrier)) aside = -1;
                const ActionInstance move{step, t0, 0.0, t0 + act(step).duration, leaves(carrier), false, false};
                for (int c : porters) {
                    if (c != carrier && !track(c).empty()) waitUntil(c, move.end);
                }
                if (!penetrates({move}, carrier)) track(carrier).push_back(move);
                --k;
                continue;
            }
            retries = 0;
            aside = carrier;
            carrier = rc;
            if (k == 0) {
                if (auto st = lineUp(porters, rc); !st) return st.error();
            }
            if (!reportProgress(progress, static_cast<double>(k + 1) / own.handoffs, "compose")) return cancelled();
        }
        // The last giver steps aside too (it would stand in the last carrier's way).
        if (aside >= 0 && aside != carrier) stepAside(aside, carrier);
        double end = 0;
        for (int c : porters) end = std::max(end, freeAt(c));
        for (int c : porters) waitUntil(c, end);
        addBag(passes, porters[0], end);
        return {};
    }

    // A hand-over of the luggage: giver, receiver and the patch's time span.
    struct Pass {
        int giver = 0, receiver = 0;
        double start = 0, end = 0;
    };

    // The item itself, as a one-joint body ("bag") held between its holder's
    // hands, across the body: the first porter holds it from the start, and it
    // changes hands in each hand-over where the two porters' hands come
    // closest, passing from one pair of hands to the other over kPassTime
    // (hands that do not quite meet do not make it jump).
    void addBag(const std::vector<Pass>& passes, int first, double end) {
        const ScenePoser poser(scene, lib);
        std::vector<glm::vec3> world;
        auto hands = [&](int c, double t) {
            const auto& joints = lib.motion(act(track(c).front().action).motion).joints;
            poser.worldPositions(c, t, world);
            if (!joints.hasHands()) return world[0];
            return 0.5f * (world[static_cast<std::size_t>(joints.leftHand)] + world[static_cast<std::size_t>(joints.rightHand)]);
        };
        std::vector<std::pair<double, int>> holders{{0.0, first}};  // from this time on, this porter
        for (const auto& p : passes) {
            double best = p.start, bestD = std::numeric_limits<double>::max();
            for (double t = p.start; t <= p.end + 1e-9; t += 1.0 / kSampleRate) {
                const double d = static_cast<double>(glm::length(hands(p.giver, t) - hands(p.receiver, t)));
                if (d < bestD) bestD = d, best = t;
            }
            holders.emplace_back(best, p.receiver);
        }
        SceneCharacter bag;
        bag.name = "bag";
        bag.body = "bag";
        bag.side = 1;
        bag.preset = "prop";
        constexpr double kKeyRate = 15;  // keys per second
        constexpr double kPassTime = 0.5;  // s
        auto across = [&](int c, double t) {  // the bag's axis along the holder's left-right
            const auto& inst = playingAt(c, t);
            return wrapAngle(inst.placementAt(lib, inst.clipTimeAt(t)).heading + std::numbers::pi / 2);
        };
        std::size_t h = 0;
        for (int k = 0; k <= static_cast<int>(std::ceil(end * kKeyRate)); ++k) {
            const double t = std::min(end, k / kKeyRate);
            while (h + 1 < holders.size() && holders[h + 1].first - 0.5 * kPassTime <= t) ++h;
            const int c = holders[h].second;
            glm::vec3 mid = hands(c, t);
            double heading = across(c, t);
            if (h > 0 && t < holders[h].first + 0.5 * kPassTime) {
                // Passing: from the giver's hands to the receiver's.
                const int giver = holders[h - 1].second;
                const double x = std::clamp((t - (holders[h].first - 0.5 * kPassTime)) / kPassTime, 0.0, 1.0);
                const float w = static_cast<float>(x * x * (3.0 - 2.0 * x));
                const glm::vec3 from = hands(giver, t);
                mid = from + w * (mid - from);
                heading = lerp(RootXf{{}, across(giver, t)}, RootXf{{}, heading}, static_cast<double>(w)).heading;
            }
            const glm::vec2 centre(mid.x, mid.z);
            bag.keys.push_back({t, {centre - headingVector(heading) * (0.5f * kBagLength), heading}, std::max(0.0f, mid.y)});
        }
        scene.characters.push_back(std::move(bag));
    }
};

Status parseLuggage(const prep::JsonReader& rd, const Json& j, LuggageSpec& s) {
    if (auto st = optionalInt(rd, j, "porters", 2, 100, s.porters); !st) return st.error();
    return optionalInt(rd, j, "handoffs", 1, 10000, s.handoffs);
}

constexpr const char* kFields[] = {"porters", "handoffs"};

}  // namespace

const SceneKindModule& luggageKind() {
    static const SceneKindModule kind = kindModule<LuggageComposer, LuggageSpec, parseLuggage, noCheck<LuggageSpec>>(true, kFields);
    return kind;
}

}  // namespace fray::sim::detail
