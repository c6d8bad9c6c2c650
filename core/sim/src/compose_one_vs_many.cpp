// One vs many: the main character meets the enemies one after another (SPEC 4.5).
#include "compose_kinds.h"
#include "fray/sim/compose/one_vs_many.h"

namespace fray::sim::detail {

namespace {

struct OneVsManyComposer : KindComposer<OneVsManySpec> {
    using KindComposer::KindComposer;

    // ---- one vs many: the main character meets the enemies one after another.
    Status run(const ProgressFn& progress) {
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
            // The main character may first take one locomotion step (turn,
            // step) so the patch fits beside those already down.
            struct Option {
                double score;
                std::size_t patch;
                int move;
            };
            std::vector<Option> options;
            std::vector<int> moves0 = {-1};
            moves0.insert(moves0.end(), locomotion.begin(), locomotion.end());
            const auto obstacleBoxes = obstacles(t0, mainC);
            for (int mv : moves0) {
                RootXf from = at;
                double tm = t0;
                if (mv >= 0) {
                    from = at * act(mv).end;
                    tm = t0 + act(mv).duration;
                    if (blocked(mainC, -1, at.pos, from.pos, tm) ||
                        blocked(mainC, -1, at.pos, (at * lib.rootAt(mv, 0.5 * act(mv).duration)).pos, t0) ||
                        penetrates({ActionInstance{mv, t0, 0.0, tm, at, false, false}}, mainC)) {
                        continue;
                    }
                }
                const int lastA = mv >= 0 ? mv : lastMain;
                for (std::size_t i : cands) {
                    const Patch& p = patches.patches()[i];
                    const RootXf xf = from * p.tracks[0].front().root.inverse();
                    if (collides(p, xf, obstacleBoxes)) continue;
                    const double s = score(i, densityAround(xf.apply(p.tracks[1].front().root.pos), tm), userPreference(p, 0, tm)) +
                                     (lib.startNode()[static_cast<std::size_t>(p.tracks[0].front().action)] ==
                                              lib.endNode()[static_cast<std::size_t>(lastA)] ? 1.0 : 0.0) -
                                     (mv >= 0 ? 5.0 : 0.0);
                    options.push_back({s, i, mv});
                }
            }
            std::stable_sort(options.begin(), options.end(), [](const Option& x, const Option& y) { return x.score > y.score; });
            // The best option whose newcomer can walk in.
            int bestI = -1, bestMove = -1;
            std::vector<ActionInstance> entry;
            const int enemy = addCharacter("enemy-" + std::to_string(k + 1), 1);
            for (std::size_t o = 0; o < options.size() && o < 40 && bestI < 0; ++o) {
                const Patch& p = patches.patches()[options[o].patch];
                const int mv = options[o].move;
                const RootXf from = mv >= 0 ? at * act(mv).end : at;
                const double t = mv >= 0 ? t0 + act(mv).duration : t0;
                const RootXf xf = from * p.tracks[0].front().root.inverse();
                if (auto walk = planEntry(enemy, mainC, p, 1, t, xf, from.pos)) {
                    bestI = static_cast<int>(options[o].patch), bestMove = mv, entry = std::move(*walk);
                }
            }
            if (bestI < 0) scene.characters.pop_back();
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
};

Status parseOneVsMany(const prep::JsonReader& rd, const Json& j, OneVsManySpec& s) {
    return optionalInt(rd, j, "enemies", 1, 1000, s.enemies);
}

constexpr const char* kFields[] = {"enemies"};

}  // namespace

const SceneKindModule& oneVsManyKind() {
    static const SceneKindModule kind = kindModule<OneVsManyComposer, OneVsManySpec, parseOneVsMany, noCheck<OneVsManySpec>>(true, kFields);
    return kind;
}

}  // namespace fray::sim::detail
