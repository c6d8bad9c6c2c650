// One vs one: two characters fight on, patch after patch (SPEC 4.5).
#include "compose_kinds.h"
#include "fray/sim/compose/one_vs_one.h"

namespace fray::sim::detail {

namespace {

struct OneVsOneComposer : KindComposer<OneVsOneSpec> {
    using KindComposer::KindComposer;

    // ---- one vs one: two characters fight on, patch after patch.
    Status run(const ProgressFn& progress) {
        const std::array<int, 2> who = {addCharacter("a", 0), addCharacter("b", 1)};
        int prev = -1;
        std::array<int, 2> roleOf = {0, 1};  // scene character -> role in the previous patch
        while (true) {
            const double ta = freeAt0(who[0]), tb = freeAt0(who[1]);
            const double t = std::max(ta, tb);
            if (prev >= 0 && t >= spec.duration) break;
            struct Choice {
                std::size_t patch;
                int roles;  // 0: a plays character 1
            };
            std::vector<Choice> cands;
            if (prev >= 0) {
                for (const auto& l : patches.temporal()[static_cast<std::size_t>(prev)]) {
                    if (l.shared == -1 && allowed[static_cast<std::size_t>(l.to)]) {
                        // a's role in prev maps through the link's roles.
                        const int aRole = roleOf[0] ^ l.roles;
                        cands.push_back({static_cast<std::size_t>(l.to), aRole});
                    }
                }
            }
            const bool linked = !cands.empty();
            if (!linked) {
                // Recycling: patches starting from the standard pose nearest to where the two are now.
                PatchConfig now{};
                if (prev >= 0) now = configOf(leaves(who[0]), leaves(who[1]));
                for (int roles = 0; roles < 2; ++roles) {
                    const PatchConfig c = roles ? PatchConfig{now.r, now.theta2, now.theta1, 0} : now;
                    const int pose = prev >= 0 ? nearestStartingPose(c) : -1;
                    for (std::size_t i = 0; i < patches.patches().size(); ++i) {
                        if (!allowed[i]) continue;
                        if (pose >= 0 && patches.initialPose()[i] != pose) continue;
                        cands.push_back({i, roles});
                    }
                }
            }
            if (cands.empty()) return makeError("one-vs-one: no patch can follow at " + std::to_string(t) + " s");
            int best = -1;
            double bestS = -std::numeric_limits<double>::max();
            for (std::size_t k = 0; k < cands.size(); ++k) {
                const auto& c = cands[k];
                const double s = score(c.patch, 0, userPreference(patches.patches()[c.patch], c.roles, t));
                if (s > bestS) bestS = s, best = static_cast<int>(k);
            }
            const Choice ch = cands[static_cast<std::size_t>(best)];
            const Patch& p = patches.patches()[ch.patch];
            (linked ? stats.temporalLinks : stats.recycled) += 1;
            // Scene character of each role.
            const std::array<int, 2> sc = ch.roles == 0 ? who : std::array<int, 2>{who[1], who[0]};
            double start = t;
            RootXf xf;
            if (prev < 0) {
                xf = RootXf{};
            } else {
                // The later character anchors the patch; the earlier walks into
                // place (one step usually) and both wait for each other.
                const int anchorRole = freeAt(sc[0]) >= freeAt(sc[1]) ? 0 : 1;
                const int anchor = sc[static_cast<std::size_t>(anchorRole)];
                const int mover = sc[static_cast<std::size_t>(1 - anchorRole)];
                xf = leaves(anchor) * p.tracks[static_cast<std::size_t>(anchorRole)].front().root.inverse();
                const RootXf goal = xf * p.tracks[static_cast<std::size_t>(1 - anchorRole)].front().root;
                std::vector<ActionInstance> walk;
                auto [end, when] = locomote(mover, anchor, leaves(mover), freeAt(mover), track(mover).back().action, goal, 0.0, walk);
                for (auto& w : walk) track(mover).push_back(w);
                stats.locomotionSteps += static_cast<int>(walk.size());
                stats.maxJunctionError = std::max(stats.maxJunctionError, static_cast<double>(glm::length(end.pos - goal.pos)));
                start = std::max(freeAt(anchor) - p.tracks[static_cast<std::size_t>(anchorRole)].front().start,
                                 when - p.tracks[static_cast<std::size_t>(1 - anchorRole)].front().start);
            }
            for (int r = 0; r < 2; ++r) {
                const int c = sc[static_cast<std::size_t>(r)];
                if (!track(c).empty()) waitUntil(c, start + p.tracks[static_cast<std::size_t>(r)].front().start);
                placeTrack(p, r, c, start, xf);
            }
            placeHits(p, sc, start);
            used(ch.patch);
            prev = static_cast<int>(ch.patch);
            roleOf = ch.roles == 0 ? std::array<int, 2>{0, 1} : std::array<int, 2>{1, 0};
            if (!reportProgress(progress, std::min(t / spec.duration, 1.0), "compose")) return cancelled();
            if (stats.patchesUsed > 10000) break;
        }
        return {};
    }
};
}  // namespace

const SceneKindModule& oneVsOneKind() {
    static const SceneKindModule kind = kindModule<OneVsOneComposer, OneVsOneSpec, noFields<OneVsOneSpec>, noCheck<OneVsOneSpec>>(true, {});
    return kind;
}

}  // namespace fray::sim::detail
