// The rat scene: people step out of the way of a rat and bump into their neighbours (SPEC 4.5).
#include <atomic>
#include <cstring>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "compose_grid.h"
#include "compose_kinds.h"
#include "fray/sim/compose/rat.h"

namespace fray::sim::detail {

// Also serves ratAvoidPatches (below).
struct RatComposer : KindComposer<RatSpec, RatStats> {
    using KindComposer::KindComposer;

    // ---- rat: people step out of the way of a rat running along the user's
    // trajectory (SPEC 4.5), and bump into their neighbours doing so. The rat
    // is a one-joint creature with no captured actions, so its {run, AVOID}
    // patches are generated here for the scene's rat speed (makeRatPatches),
    // not read from the project's patch library. A bump pushes the neighbour
    // into the forced reaction that best matches its posture and the push,
    // the response rule of patch generation ({any, AVOID, PUSHED}), applied
    // where the neighbours actually stand.
    struct Bystander {
        glm::vec2 spot{0.0f};
        RootXf at;                           // standing placement
        double passTime = 0, passDistance = 1e9;  // the rat's closest approach
        bool near = false;
        std::vector<ActionInstance> plan;    // empty: stands all along
        detail::CoreDiscs::Disc standHull;   // standing: a disc round its core discs at every sample of the idle (coreHulls)
        // Its plan's discs round its pelvis paths and round its core hulls
        // (pathDiscOf, hullsDiscOf from its first instance): firstTouch's
        // first test, kept with the plan (refreshDiscs).
        detail::CoreDiscs::Disc pathAll, hullsAll;
        RootXf standRoot;  // at * holdRootInverse: where its standing clip is placed
    };

    // The crowd as a trial sees it: everyone's plan, with the few plans the
    // trial changes laid over it (no copy of the crowd and its plans per
    // trial: at 10,000 people that copy was the composition's quadratic pass).
    struct CrowdView {
        const std::vector<Bystander>* base = nullptr;
        std::vector<std::pair<std::size_t, std::vector<ActionInstance>>> changed;
        explicit CrowdView(const std::vector<Bystander>& crowd) : base(&crowd) {}
        const Bystander& operator[](std::size_t o) const { return (*base)[o]; }
        std::size_t size() const { return base->size(); }
        const std::vector<ActionInstance>& plan(std::size_t o) const {
            for (const auto& [who, p] : changed) {
                if (who == o) return p;
            }
            return (*base)[o].plan;
        }
        bool isChanged(std::size_t o) const {
            for (const auto& [who, p] : changed) {
                if (who == o) return true;
            }
            return false;
        }
        void set(std::size_t o, std::vector<ActionInstance> p) {
            for (auto& [who, q] : changed) {
                if (who == o) {
                    q = std::move(p);
                    return;
                }
            }
            changed.emplace_back(o, std::move(p));
        }
    };
    // The crowd's spots (they never move), for the neighbours of a body test.
    FloorGrid spotGrid{3.0f};
    // Per person: the others standing within 3 m, ascending (found once with spotGrid).
    std::vector<std::vector<std::size_t>> within3m;
    void findNeighbours(const std::vector<Bystander>& crowd) {
        within3m.assign(crowd.size(), {});
        for (std::size_t self = 0; self < crowd.size(); ++self) {  // (the grid's query is not thread-safe)
            // The grid's query is a superset; the exact test keeps the same ones as a pass over everyone.
            for (int o : spotGrid.near(crowd[self].spot, 3.05f)) {
                const auto k = static_cast<std::size_t>(o);
                if (k != self && glm::length(crowd[k].spot - crowd[self].spot) < 3.0f) within3m[self].push_back(k);
            }
        }
    }
    // The farthest the standing clip (hold, looped) takes the pelvis from where it stands (m).
    float holdWander = 0;
    // Per action: a disc round its pelvis path in the clip's frame (rootAt
    // interpolates between samples: the samples bound it; a millimetre more
    // covers the rounding): Composer::pelvisPathDiscs.
    std::vector<detail::CoreDiscs::Disc> pelvisPaths;
    // Per action: a disc round the core-box discs (CoreDiscs) of all its
    // samples, in the clip's frame (a millimetre more covers the rounding).
    // Apart from it by a margin, a body is apart from the discs of every
    // sample, so coreBodiesOverlap's answer is known without placing the
    // other body (firstTouch's test before the pelvis).
    std::vector<detail::CoreDiscs::Disc> coreHulls;
    void measureCoreHulls() {
        coreHulls.assign(static_cast<std::size_t>(lib.size()), {});
        const FloorRotation none(0.0);
        for (int a = 0; a < lib.size(); ++a) {
            const int n = act(a).sampleCount;
            std::vector<detail::CoreDiscs::Disc> local;
            glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
            for (int k = 0; k < n; ++k) {
                // At the identity placement, placed() is the sample's disc in the clip's frame.
                local.push_back(discs->placed(detail::BodyPose{a, k / kSampleRate, RootXf{}}, none));
                lo = glm::min(lo, local.back().centre), hi = glm::max(hi, local.back().centre);
            }
            auto& h = coreHulls[static_cast<std::size_t>(a)];
            h.centre = n > 0 ? 0.5f * (lo + hi) : glm::vec2(0.0f);
            for (const auto& d : local) h.radius = std::max(h.radius, glm::length(d.centre - h.centre) + d.radius);
            h.radius += 1e-3f;
        }
    }
    // Per action: the box round the floor boxes of its feet and shins at
    // every sample, in the clip's frame (clearWays' first test).
    std::vector<SweptBox> footHulls;
    void measureFootHulls() {
        footHulls.assign(static_cast<std::size_t>(lib.size()), SweptBox::empty());
        for (int a = 0; a < lib.size(); ++a) {
            for (int k = 0; k < act(a).sampleCount; ++k) {
                const Obb* boxes = lib.boxesAt(a, k);
                for (int seg : {kLeftFoot, kRightFoot, kLeftShin, kRightShin}) footHulls[static_cast<std::size_t>(a)].add(floorBox(boxes[seg]));
            }
        }
    }
    detail::CoreDiscs::Disc placedHull(int action, const RootXf& root) const {
        const auto& h = coreHulls[static_cast<std::size_t>(action)];
        return {root.pos + FloorRotation(root.heading)(h.centre), h.radius};
    }
    // Certainly apart from every sample's disc inside the hull `h`: CoreDiscs::apart with
    // a centimetre more (the discs' placement rounds differently from the hull's).
    static bool apartFromHull(const detail::CoreDiscs::Disc& me, const detail::CoreDiscs::Disc& h) {
        const glm::dvec2 d = glm::dvec2(me.centre) - glm::dvec2(h.centre);
        const double scale = std::fabs(static_cast<double>(me.centre.x)) + std::fabs(static_cast<double>(me.centre.y)) +
                             std::fabs(static_cast<double>(h.centre.x)) + std::fabs(static_cast<double>(h.centre.y));
        const double r = static_cast<double>(me.radius) + static_cast<double>(h.radius) + 2e-3 + 2e-5 * scale + 0.01;
        return glm::dot(d, d) > r * r;
    }

    void measureHoldWander() {
        const auto& h = act(hold);
        const glm::vec2 p0 = lib.rootAt(hold, 0).pos;
        holdWander = 0;
        // rootAt interpolates between samples: the samples bound it.
        for (int k = 0; k < h.sampleCount; ++k) {
            holdWander = std::max(holdWander, glm::length(lib.rootAt(hold, k / kSampleRate).pos - p0));
        }
    }

    static double distanceToPolyline(glm::vec2 p, const std::vector<glm::vec2>& line) {
        double best = std::numeric_limits<double>::max();
        for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, distanceToSegment(p, line[i], line[i + 1]));
        return best;
    }

    // The rat's keys: it waits at the first point until ratStart, then runs
    // the polyline at ratSpeed, facing along it (corners rounded over 0.3 m).
    std::vector<RootKey> ratKeys() const {
        const auto& P = own.ratPath;
        std::vector<double> cum{0.0};
        for (std::size_t i = 0; i + 1 < P.size(); ++i) cum.push_back(cum.back() + static_cast<double>(glm::length(P[i + 1] - P[i])));
        const double length = cum.back();
        auto at = [&](double s) {
            s = std::clamp(s, 0.0, length);
            std::size_t i = static_cast<std::size_t>(std::upper_bound(cum.begin(), cum.end(), s) - cum.begin());
            i = std::clamp<std::size_t>(i, 1, P.size() - 1);
            const double seg = cum[i] - cum[i - 1];
            const float u = seg > 0 ? static_cast<float>((s - cum[i - 1]) / seg) : 0.0f;
            return P[i - 1] + u * (P[i] - P[i - 1]);
        };
        std::vector<RootKey> keys;
        double heading = 0;
        auto key = [&](double t, double s) {
            const glm::vec2 d = at(s + 0.15) - at(s - 0.15);
            if (glm::length(d) > 1e-4f) heading = angleOf(d);
            keys.push_back({t, {at(s), heading}});
        };
        if (own.ratStart > 0) key(0.0, 0.0);
        constexpr double kKeyStep = 0.1;  // s
        const int steps = static_cast<int>(std::ceil(length / own.ratSpeed / kKeyStep));
        for (int k = 0; k <= steps; ++k) {
            const double s = std::min(length, k * kKeyStep * own.ratSpeed);
            key(own.ratStart + s / own.ratSpeed, s);
        }
        return keys;
    }

    // lib.sampleAt(action, t), inline: the floor of t * kSampleRate (+1e-9)
    // by truncation (clip times are finite and far inside an int), clamped.
    int sampleOf(int action, double t) const {
        const double x = t * kSampleRate + 1e-9;
        int s = static_cast<int>(x);
        if (static_cast<double>(s) > x) --s;
        return std::clamp(s, 0, act(action).sampleCount - 1);
    }
    // instanceIndexAt for a plan (not empty; its instances in time order):
    // the last that starts at or before t, or the first. Plans hold a few
    // instances, so from the end.
    static std::size_t playingAt(const std::vector<ActionInstance>& plan, double t) {
        std::size_t k = plan.size() - 1;
        while (k > 0 && plan[k].start > t) --k;
        return k;
    }
    // The standing clip's first root, inverted: someone standing at `at` plays it from `at * holdRootInverse`.
    RootXf holdRootInverse;
    // The body of someone standing (the clip looped from `root`) at time t.
    detail::BodyPose standingBody(const RootXf& root, double t) const {
        const double tau = std::fmod(std::max(t, 0.0), act(hold).duration);
        return {hold, tau, root};
    }
    // The body of someone following `plan` (or standing at `at` when it is empty) at time t.
    detail::BodyPose bodyIn(const std::vector<ActionInstance>& plan, const RootXf& at, double t) const {
        if (plan.empty()) return standingBody(at * holdRootInverse, t);
        const auto& inst = plan[playingAt(plan, t)];
        return {inst.action, inst.clipTimeAt(t), inst.root};
    }

    // The floor boxes of the feet and shins of someone following `plan`
    // (standing at `at` when it is empty) at every sample from 0.6 s before
    // the rat's closest approach `pass` to 0.6 s after it.
    using FootBoxes = std::vector<std::array<SweptBox, 4>>;
    FootBoxes footBoxes(const std::vector<ActionInstance>& plan, const RootXf& at, double pass) const {
        FootBoxes out;
        for (double t = pass - 0.6; t <= pass + 0.6; t += 1.0 / kSampleRate) {
            const detail::BodyPose body = bodyIn(plan, at, t);
            const Obb* boxes = lib.boxesAt(body.action, lib.sampleAt(body.action, body.tau));
            const FloorRotation rot(body.root.heading);
            auto& feet = out.emplace_back();
            int k = 0;
            for (int seg : {kLeftFoot, kRightFoot, kLeftShin, kRightShin}) feet[static_cast<std::size_t>(k++)] = placedFloorBox(boxes[seg], body.root, rot);
        }
        return out;
    }
    // floorBox(box.placed(root)), by the same operations on what it reads
    // (the centre, the axes' x and z), the rotation of root computed once by the caller.
    static SweptBox placedFloorBox(const Obb& box, const RootXf& root, const FloorRotation& rot) {
        const glm::vec3 centre = rot(box.centre) + glm::vec3(root.pos.x, 0.0f, root.pos.y);
        glm::vec2 h(0.0f);
        for (int a = 0; a < 3; ++a) {
            const glm::vec3 axis = rot(box.axes[a]);
            h.x += std::fabs(axis.x) * box.half[a];
            h.y += std::fabs(axis.z) * box.half[a];
        }
        const glm::vec2 c(centre.x, centre.z);
        return {c - h, c + h};
    }

    // Closest the rat's body (ratAt(t): its root) comes to those boxes (m;
    // negative: it runs into them). Stops as soon as it is below `enough`.
    template <class RatAt>
    static double clearanceOf(const FootBoxes& feet, RatAt&& ratAt, double pass, double enough = -1e9) {
        double best = std::numeric_limits<double>::max();
        double t = pass - 0.6;
        for (const auto& sample : feet) {
            const RootXf r = ratAt(t);
            const glm::vec2 fwd = headingVector(r.heading);
            std::array<glm::vec2, 3> rat{};
            int k = 0;
            for (float along : {0.0f, 0.5f, 1.0f}) rat[static_cast<std::size_t>(k++)] = r.pos + fwd * (along * kRatLength);
            // rectDistance squared: the root of the least square is the least distance.
            float least = std::numeric_limits<float>::max();
            for (const SweptBox& box : sample) {
                for (const glm::vec2& p : rat) {
                    const glm::vec2 d = glm::max(glm::max(box.lo - p, p - box.hi), glm::vec2(0.0f));
                    least = std::min(least, glm::dot(d, d));
                }
            }
            best = std::min(best, static_cast<double>(std::sqrt(least)) - 0.04);  // the rat's girth
            if (best < enough) break;
            t += 1.0 / kSampleRate;
        }
        return best;
    }

    // Closest the rat's body comes to the feet and shins of someone following
    // `plan` while it passes them (m; negative: it runs into them).
    double ratClearance(const Bystander& b, const std::vector<ActionInstance>& plan) const {
        return clearanceOf(footBoxes(plan, b.at, b.passTime), [&](double t) { return creatureAt(ratBody, t); }, b.passTime);
    }

    // Ways out of the rat's path: an avoid or a step that can start from
    // standing, alone or followed by a second one that continues it in the
    // motion graph (a guard step moves 0.3 m; two get the feet clear of a
    // rat running right under someone). One representative per variant
    // class and start node. False when there are none.
    static constexpr const char* kNoWays = "rat: the project has no avoid or step action (people need one to get out of the rat's way)";
    bool findWays() {
        std::map<std::pair<int, int>, int> reps;
        for (int a = 0; a < lib.size(); ++a) {
            const auto& A = act(a);
            if (!A.is(kAvoid | kStep) || A.is(kReactive | kAttack | kRun | kWalk) || A.has("carry")) continue;
            reps.emplace(std::make_pair(lib.variantClass()[static_cast<std::size_t>(a)], lib.startNode()[static_cast<std::size_t>(a)]), a);
        }
        ways.clear();
        for (int pass = 0; pass < 2 && ways.empty(); ++pass) {
            for (const auto& [key, a] : reps) {
                if (pass == 0 && !lib.continuesInto(hold, a)) continue;
                ways.push_back({a});
                for (const auto& [key2, b] : reps) {
                    if (lib.continuesInto(a, b) && glm::length(act(b).end.pos) > 0.1f) ways.push_back({a, b});
                }
            }
        }
        sameStart.clear();
        for (std::size_t w = 0; w < ways.size(); ++w) {
            std::size_t first = w;
            while (first > 0 && ways[first - 1].front() == ways[w].front()) --first;
            sameStart.push_back(first);
        }
        return !ways.empty();
    }

    // {run, AVOID} patches (SPEC 4.5, the rat scene's third PatternList): the
    // rat runs straight at the scene's speed past someone standing in the
    // guard `lateral` m to the side of its line (positive: on its left) and
    // turned `facing` from its heading; every way out, started `lead` s
    // before the rat's closest approach, that keeps the rat clear of the feet
    // and shins is a patch. The initial conditions are the SPEC grid (0.2 m,
    // 20 degrees, 0.1 s). The rat has no captured actions to make patches
    // from, so its run is made for the scene's speed and the table is
    // generated per scene (in parallel; each cell on its own, so the same
    // table every time). The composer looks each bystander up in it.
    struct RatPatch {
        int way = 0;           // index into `ways`
        double lead = 0;       // s
        double clearance = 0;  // m, against the straight rat
        int step = 0;          // lead / kRatLeadStep
        double score() const { return std::min(clearance, 0.25) - 0.01 * lead; }  // clear by a safe margin, at the last moment
    };
    static constexpr double kRatLateralStep = 0.2, kRatLeadStep = 0.1;
    static constexpr int kRatFacings = 18;  // 20 degrees apart
    int ratLaterals = 0;                    // cells either side of the line
    std::vector<std::vector<RatPatch>> ratTable;  // per (lateral, facing) cell, best first
    std::vector<std::vector<int>> ways;      // ways out: one or two avoiding or stepping actions
    std::vector<std::size_t> sameStart;      // per way: the first way that starts with the same action (they follow one another)
    int ratSteps = 1;                        // above every patch's lead step

    static glm::vec2 leftOf(double heading) { return headingVector(heading + 0.5 * std::numbers::pi); }
    static double ratFacingAt(int f) { return wrapAngle((f - kRatFacings / 2) * 2 * std::numbers::pi / kRatFacings); }
    std::size_t ratCell(int lateral, int facing) const {
        return static_cast<std::size_t>((lateral + ratLaterals) * kRatFacings + facing);
    }

    void makeRatPatches() {
        ratLaterals = static_cast<int>(std::ceil(own.reach / kRatLateralStep - 1e-9)) + 1;  // a cell beyond reach, to look up either side
        ratTable.assign(static_cast<std::size_t>((2 * ratLaterals + 1) * kRatFacings), {});
        constexpr double kPass = 3.0;  // patch time of the rat's closest approach
        // footBoxes' sample times, and an order from the closest approach
        // outwards: the least distance comes early, and a sample whose box
        // round the four is no closer is passed over (the same least
        // distance, so the same clearance whenever it reaches kRatClear).
        std::vector<double> times;
        for (double t = kPass - 0.6; t <= kPass + 0.6; t += 1.0 / kSampleRate) times.push_back(t);
        std::vector<std::size_t> outwards;
        for (std::size_t d = 0; outwards.size() < times.size(); ++d) {
            const std::size_t mid = times.size() / 2;
            if (mid + d < times.size()) outwards.push_back(mid + d);
            if (d > 0 && d <= mid) outwards.push_back(mid - d);
        }
        auto square = [](const SweptBox& r, const glm::vec2& p) {
            const glm::vec2 d = glm::max(glm::max(r.lo - p, p - r.hi), glm::vec2(0.0f));
            return glm::dot(d, d);
        };
        auto distance = [](float squared) { return static_cast<double>(std::sqrt(squared)) - 0.04; };  // the rat's girth
        tbb::parallel_for(0, kRatFacings, [&](int f) {
            const RootXf at{glm::vec2(0.0f), ratFacingAt(f)};
            for (std::size_t w = 0; w < ways.size(); ++w) {
                const auto& way = ways[w];
                const RootXf root = at * lib.rootAt(way.front(), 0).inverse();
                double duration = 0;
                for (int a : way) duration += act(a).duration;
                for (int k = 1; k * kRatLeadStep <= std::min(duration + 0.6, kPass - 0.2) + 1e-9; ++k) {
                    const double lead = k * kRatLeadStep;
                    const FootBoxes feet = footBoxes(planMove(at, kPass - lead, way, 0.0, root, false, kPass + 1.0), at, kPass);
                    std::vector<SweptBox> around(feet.size(), SweptBox::empty());
                    for (std::size_t i = 0; i < feet.size(); ++i) {
                        for (const SweptBox& box : feet[i]) around[i].add(box);
                    }
                    for (int l = -ratLaterals; l <= ratLaterals; ++l) {
                        // The person stands l * 0.2 m to the left of the rat's line.
                        const glm::vec2 line = -static_cast<float>(l * kRatLateralStep) * leftOf(0.0);
                        // clearanceOf(feet, the straight rat, kPass, kRatClear), the samples in `outwards` order.
                        double clear = std::numeric_limits<double>::max();
                        for (const std::size_t i : outwards) {
                            if (i >= feet.size()) continue;
                            const RootXf r{line + headingVector(0.0) * static_cast<float>(own.ratSpeed * (times[i] - kPass)), 0.0};
                            const glm::vec2 fwd = headingVector(r.heading);
                            std::array<glm::vec2, 3> rat{};
                            int q = 0;
                            for (float along : {0.0f, 0.5f, 1.0f}) rat[static_cast<std::size_t>(q++)] = r.pos + fwd * (along * kRatLength);
                            float bound = std::numeric_limits<float>::max();
                            for (const glm::vec2& p : rat) bound = std::min(bound, square(around[i], p));
                            if (distance(bound) >= clear) continue;
                            float least = std::numeric_limits<float>::max();
                            for (const SweptBox& box : feet[i]) {
                                for (const glm::vec2& p : rat) least = std::min(least, square(box, p));
                            }
                            clear = std::min(clear, distance(least));
                            if (clear < kRatClear) break;
                        }
                        if (clear >= kRatClear) ratTable[ratCell(l, f)].push_back({static_cast<int>(w), lead, clear, k});
                    }
                }
            }
        });
        ratSteps = 1;
        for (const auto& cell : ratTable) {
            for (const RatPatch& p : cell) ratSteps = std::max(ratSteps, p.step + 1);
        }
        for (auto& cell : ratTable) {
            std::stable_sort(cell.begin(), cell.end(), [](const RatPatch& a, const RatPatch& b) { return a.score() > b.score(); });
            ownStats.ratPatches += static_cast<int>(cell.size());
        }
    }

    // The patches of the cells nearest a bystander's configuration (the two
    // nearest lateral offsets by the two nearest facings), each way and lead once.
    std::vector<RatPatch> ratCandidates(const Bystander& b) const {
        const RootXf r = creatureAt(ratBody, b.passTime);
        const double lateral = static_cast<double>(glm::dot(b.spot - r.pos, leftOf(r.heading))) / kRatLateralStep;
        const double facing = (wrapAngle(b.at.heading - r.heading) + std::numbers::pi) / (2 * std::numbers::pi / kRatFacings);
        const int l0 = static_cast<int>(std::floor(lateral)), f0 = static_cast<int>(std::floor(facing));
        std::vector<RatPatch> out;
        // (way, lead) once: the cells share the 0.1 s lead grid exactly (lead = step * 0.1).
        std::vector<char> seen(ways.size() * static_cast<std::size_t>(ratSteps), 0);
        for (int l : {l0, l0 + 1}) {
            if (l < -ratLaterals || l > ratLaterals) continue;
            for (int f : {f0, f0 + 1}) {
                for (const RatPatch& p : ratTable[ratCell(l, ((f % kRatFacings) + kRatFacings) % kRatFacings)]) {
                    char& s = seen[static_cast<std::size_t>(p.way) * static_cast<std::size_t>(ratSteps) + static_cast<std::size_t>(p.step)];
                    if (!s) s = 1, out.push_back(p);
                }
            }
        }
        return out;
    }

    // A way out of one person that keeps the rat clear of the feet and shins:
    // its candidate (way, lead) and exactly min(ratClearance's value for its
    // plan, kClearScored), what its score reads.
    static constexpr double kClearScored = 0.25;
    struct ClearWay {
        RatPatch patch;
        double clear = 0;
    };
    // The ways out of bystander b (its candidates, in order) that start at
    // 0.2 s or later and keep the rat kRatClear from the feet and shins,
    // with their clearance: what the composer's loop over candidates tests
    // first, for the same values. It depends on the person's own plan and the
    // rat alone, never on the crowd, so the near people's are worked out in
    // parallel before anyone is placed. Cheaper than ratClearance per
    // candidate: the rat's body at each sample of the window is placed once;
    // the foot boxes of an (instance, sample) once per person (the plans of a
    // way share their instances' actions and roots, only the lead changes
    // which sample plays when); and a sample is skipped when the box around
    // all four cannot come closer than the best so far (a lower bound, so the
    // minimum, and the value, are the same).
    std::vector<ClearWay> clearWays(const Bystander& b, double until) const {
        constexpr double dt = 1.0 / kSampleRate;
        std::vector<double> times;                  // footBoxes' sample times
        std::vector<std::array<glm::vec2, 3>> rat;  // the rat's tail, middle and nose then
        for (double t = b.passTime - 0.6; t <= b.passTime + 0.6; t += dt) {
            const RootXf r = creatureAt(ratBody, t);
            const glm::vec2 fwd = headingVector(r.heading);
            std::array<glm::vec2, 3> pts{};
            int k = 0;
            for (float along : {0.0f, 0.5f, 1.0f}) pts[static_cast<std::size_t>(k++)] = r.pos + fwd * (along * kRatLength);
            times.push_back(t);
            rat.push_back(pts);
        }
        // rectDistance squared: the square root is monotone, so the least
        // distance is the root of the least square (one root, the same value).
        auto square = [](const SweptBox& r, const glm::vec2& p) {
            const glm::vec2 d = glm::max(glm::max(r.lo - p, p - r.hi), glm::vec2(0.0f));
            return glm::dot(d, d);
        };
        auto distance = [](float squared) { return static_cast<double>(std::sqrt(squared)) - 0.04; };  // the rat's girth
        struct Slot {
            int action = -1;
            RootXf root;
            std::vector<std::array<SweptBox, 5>> boxes;  // per sample: feet, shins, and the box around the four
            std::vector<char> have;
            SweptBox hull;              // round the feet and shins at every sample (footHulls placed, with a margin)
            std::vector<double> apart;  // per rat sample: the distance from the rat to `hull` (NaN: not measured yet)
        };
        // The standing idle, then per way its plan's instances 1-3 (kept per
        // thread from person to person, emptied: no clearWays runs inside another on a thread).
        thread_local std::vector<Slot> slots;
        slots.resize(1 + 4 * ways.size());
        for (Slot& slot : slots) slot.action = -1;
        std::array<SweptBox, 5> scratch{};
        // The slot of an instance, or none when the slot holds another instance.
        auto slotOf = [&](std::size_t slot, const ActionInstance& inst) -> Slot* {
            Slot* s = slot < slots.size() ? &slots[slot] : nullptr;
            if (s && s->action < 0) {
                s->action = inst.action;
                s->root = inst.root;
                s->boxes.resize(static_cast<std::size_t>(act(inst.action).sampleCount));
                s->have.assign(s->boxes.size(), 0);
                // placedBox holds the placed boxes' floor boxes (a rectangle
                // round the rotated rectangle); the margin covers the rounding.
                s->hull = placedBox(footHulls[static_cast<std::size_t>(inst.action)], inst.root);
                const float margin = 1e-3f + 1e-5f * (std::fabs(inst.root.pos.x) + std::fabs(inst.root.pos.y));
                s->hull.lo -= glm::vec2(margin), s->hull.hi += glm::vec2(margin);
                s->apart.assign(rat.size(), std::numeric_limits<double>::quiet_NaN());
            }
            const bool same = s && s->action == inst.action && s->root.pos == inst.root.pos && s->root.heading == inst.root.heading;
            return same ? s : nullptr;
        };
        auto boxesOf = [&](Slot* s, const ActionInstance& inst, int sample) -> const std::array<SweptBox, 5>& {
            auto fill = [&](std::array<SweptBox, 5>& out) {
                const Obb* boxes = lib.boxesAt(inst.action, sample);
                const FloorRotation rot(inst.root.heading);
                int k = 0;
                out[4] = SweptBox::empty();
                for (int seg : {kLeftFoot, kRightFoot, kLeftShin, kRightShin}) {
                    out[static_cast<std::size_t>(k)] = placedFloorBox(boxes[seg], inst.root, rot);
                    out[4].add(out[static_cast<std::size_t>(k++)]);
                }
            };
            if (!s) {
                fill(scratch);  // not the slot's instance: placed afresh
                return scratch;
            }
            const auto i = static_cast<std::size_t>(sample);
            if (!s->have[i]) fill(s->boxes[i]), s->have[i] = 1;
            return s->boxes[i];
        };
        std::vector<ClearWay> out;
        SmallPlan plan;
        for (const RatPatch& patch : ratCandidates(b)) {
            const auto& way = ways[static_cast<std::size_t>(patch.way)];
            const double ts = b.passTime - patch.lead;
            if (ts < 0.2) continue;
            const RootXf root = b.at * lib.rootAt(way.front(), 0).inverse();
            plan.clear();
            planMoveInto(plan, b.at, ts, way, 0.0, root, false, until);
            // Only min(clearance, kClearScored) counts for the score: a sample
            // no closer than that changes nothing (the chosen way's own
            // clearance is measured again in full, for the stats).
            double best = kClearScored;
            std::size_t k = 0;  // instanceIndexAt(plan, t): the times increase
            std::size_t slotK = SIZE_MAX;  // the instance whose slot `s` is
            Slot* s = nullptr;
            for (std::size_t i = 0; i < rat.size(); ++i) {
                const double t = times[i];
                while (k + 1 < plan.size() && plan[k + 1].start <= t) ++k;
                const ActionInstance& inst = plan[k];
                if (k != slotK) {
                    // (The ways that begin with the same action share its instance: the same action at the same root.)
                    const std::size_t w = k == 1 ? sameStart[static_cast<std::size_t>(patch.way)] : static_cast<std::size_t>(patch.way);
                    s = slotOf(k == 0 ? 0 : (k <= 3 ? 1 + 4 * w + k - 1 : SIZE_MAX), inst);
                    slotK = k;
                }
                if (s) {
                    // Nothing of the instance at any sample comes closer than the best so far.
                    double& apart = s->apart[i];
                    if (std::isnan(apart)) {
                        float least = std::numeric_limits<float>::max();
                        for (const glm::vec2& p : rat[i]) least = std::min(least, square(s->hull, p));
                        apart = distance(least);
                    }
                    if (apart >= best) continue;
                }
                const auto& boxes = boxesOf(s, inst, sampleOf(inst.action, inst.clipTimeAt(t)));
                float bound = std::numeric_limits<float>::max();
                for (const glm::vec2& p : rat[i]) bound = std::min(bound, square(boxes[4], p));
                if (distance(bound) >= best) continue;  // no box of the four comes closer than the best so far
                float least = std::numeric_limits<float>::max();
                for (std::size_t seg = 0; seg < 4; ++seg) {
                    for (const glm::vec2& p : rat[i]) least = std::min(least, square(boxes[seg], p));
                }
                best = std::min(best, distance(least));
                if (best < kRatClear) break;
            }
            if (best >= kRatClear) out.push_back({patch, best});
        }
        return out;
    }

    // When a plan moves the body: from its first action that is not an idle
    // to the end of its last one; {+inf, -inf} for someone who only stands.
    std::pair<double, double> movingWindow(const std::vector<ActionInstance>& plan) const {
        std::pair<double, double> w{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
        for (const auto& inst : plan) {
            if (act(inst.action).is(kIdle)) continue;
            w.first = std::min(w.first, inst.start);
            w.second = std::max(w.second, inst.end);
        }
        return w;
    }

    // Core bodies placed (CoreBody::boxes, shrunk by kTouchShrink), kept
    // per thread in a table by (action, sample, root): the same pose places
    // the same boxes, and firstTouch meets the same poses again and again
    // (a neighbour's idle, a way out's samples at every lead). `generation`
    // tells this composition's entries from another's.
    struct PlacedCore {
        std::uint64_t generation = 0;
        int action = -1, sample = -1;
        glm::vec2 pos{0.0f};
        double heading = 0;
        std::array<Obb, kCoreSegments.size()> boxes;
        std::array<float, kCoreSegments.size()> radii;
    };
    static inline std::atomic<std::uint64_t> generations{0};
    std::uint64_t generation = ++generations;
    static constexpr std::size_t kPlacedSlots = 2048;
    using PlacedTable = std::vector<PlacedCore>;
    static PlacedTable& placedTable() {
        thread_local PlacedTable table(kPlacedSlots);
        return table;
    }
    std::size_t placedSlot(const detail::BodyPose& pose, int sample) const {
        std::uint64_t h = generation * 0x9E3779B97F4A7C15ull;
        std::uint32_t x, z;
        std::uint64_t hd;
        std::memcpy(&x, &pose.root.pos.x, 4), std::memcpy(&z, &pose.root.pos.y, 4), std::memcpy(&hd, &pose.root.heading, 8);
        for (const std::uint64_t v : {static_cast<std::uint64_t>(static_cast<std::uint32_t>(pose.action)),
                                      static_cast<std::uint64_t>(static_cast<std::uint32_t>(sample)), static_cast<std::uint64_t>(x),
                                      static_cast<std::uint64_t>(z), hd}) {
            h = (h ^ v) * 0x100000001b3ull;
        }
        return static_cast<std::size_t>((h ^ (h >> 31)) % kPlacedSlots);
    }
    bool holds(const PlacedCore& e, const detail::BodyPose& pose, int sample) const {
        return e.generation == generation && e.action == pose.action && e.sample == sample && e.pos == pose.root.pos &&
               std::memcmp(&e.heading, &pose.root.heading, 8) == 0;
    }
    void fillPlaced(PlacedCore& e, const detail::CoreBody& body, int sample) const {
        const detail::BodyPose& pose = body.pose();
        e.boxes = body.boxes();
        e.radii = body.radii();
        e.generation = generation, e.action = pose.action, e.sample = sample, e.pos = pose.root.pos, e.heading = pose.root.heading;
    }
    // coreBodiesOverlap(a, b) for two bodies whose pelvises are within the
    // pelvis reach (the caller's test, the same as its first), their boxes
    // from the table or placed into it.
    bool coresOverlap(const detail::CoreBody& a, const detail::CoreBody& b) const {
        PlacedTable& table = placedTable();
        const int sa = sampleOf(a.pose().action, a.pose().tau), sb = sampleOf(b.pose().action, b.pose().tau);
        const std::size_t ia = placedSlot(a.pose(), sa), ib = placedSlot(b.pose(), sb);
        PlacedCore& ea = table[ia];
        if (!holds(ea, a.pose(), sa)) fillPlaced(ea, a, sa);
        PlacedCore spare;  // both in one slot: b's beside it
        PlacedCore* eb = &table[ib];
        if (ib == ia && !holds(*eb, b.pose(), sb)) eb = &spare;
        if (!holds(*eb, b.pose(), sb)) fillPlaced(*eb, b, sb);
        for (std::size_t i = 0; i < ea.boxes.size(); ++i) {
            for (std::size_t j = 0; j < eb->boxes.size(); ++j) {
                const glm::vec3 c = eb->boxes[j].centre - ea.boxes[i].centre;
                const float r = ea.radii[i] + eb->radii[j];
                if (glm::dot(c, c) <= r * r && overlapsBeyondSpheres(ea.boxes[i], eb->boxes[j])) return true;
            }
        }
        return false;
    }

    // A disc round the pelvis paths (pelvisPaths) of the instances of `p`
    // from k0 on (standing at `spot`: holdWander round it).
    detail::CoreDiscs::Disc pathDiscOf(const std::vector<ActionInstance>& p, std::size_t k0, const glm::vec2& spot) const {
        using Disc = detail::CoreDiscs::Disc;
        if (p.empty()) return Disc{spot, holdWander};
        auto placed = [&](std::size_t k) {
            const Disc& path = pelvisPaths[static_cast<std::size_t>(p[k].action)];
            return Disc{p[k].root.pos + FloorRotation(p[k].root.heading)(path.centre), path.radius};
        };
        SweptBox around = SweptBox::empty();
        for (std::size_t k = k0; k < p.size(); ++k) {
            const Disc d = placed(k);
            around.add({d.centre, d.centre});
        }
        Disc out{0.5f * (around.lo + around.hi), 0.0f};
        for (std::size_t k = k0; k < p.size(); ++k) {
            const Disc d = placed(k);
            out.radius = std::max(out.radius, glm::length(d.centre - out.centre) + d.radius);
        }
        return out;
    }
    // A disc round the core hulls (coreHulls) of the instances of `p` from k0 on (standing: `standing`).
    detail::CoreDiscs::Disc hullsDiscOf(const std::vector<ActionInstance>& p, std::size_t k0, const detail::CoreDiscs::Disc& standing) const {
        using Disc = detail::CoreDiscs::Disc;
        if (p.empty()) return standing;
        SweptBox around = SweptBox::empty();
        for (std::size_t k = k0; k < p.size(); ++k) {
            const Disc d = placedHull(p[k].action, p[k].root);
            around.add({d.centre, d.centre});
        }
        Disc out{0.5f * (around.lo + around.hi), 0.0f};
        for (std::size_t k = k0; k < p.size(); ++k) {
            const Disc d = placedHull(p[k].action, p[k].root);
            out.radius = std::max(out.radius, glm::length(d.centre - out.centre) + d.radius);
        }
        out.radius += 1e-3f;
        return out;
    }
    void refreshDiscs(Bystander& o) const {
        o.pathAll = pathDiscOf(o.plan, 0, o.spot);
        o.hullsAll = hullsDiscOf(o.plan, 0, o.standHull);
    }

    // First time someone following `plan` from `from` to `until` touches
    // another bystander's body: {who, when}; {-1, 0} when nobody. Two people
    // standing still do not start touching, so once this plan has settled only
    // the others' moving windows are sampled.
    // The neighbours firstTouch looks at, ascending: those within 3 m (but
    // `ignore`) whose pelvis can come within the pelvis reach of its pelvis
    // from `from` on and whose core hulls meet its. It reads the plan's
    // instances from the one playing at `from` on (their actions and roots
    // only), so the ways out of a person at every lead share it.
    void keptNeighbours(const CrowdView& crowd, std::size_t self, const std::vector<ActionInstance>& plan, double from,
                        std::size_t ignore, std::vector<std::size_t>& close) const {
        constexpr float kReach = 1.2f;  // coreBodiesOverlap's pelvis reach
        // Those within 3 m, ascending (the grid's query is a superset; the
        // same test as a pass over everyone then keeps the same ones).
        close.clear();
        for (const std::size_t k : within3m[self]) {
            if (k != ignore) close.push_back(k);
        }
        // Drop those who never come within the pelvis reach of its pelvis
        // from `from` on: the discs round the pelvis paths of its instances
        // from then and round all of theirs (or their spot and holdWander)
        // are apart (so neither loop below would find them touching).
        using Disc = detail::CoreDiscs::Disc;
        const std::size_t k0 = plan.empty() ? 0 : playingAt(plan, from);
        const Disc mine = pathDiscOf(plan, k0, crowd[self].spot);
        // Likewise the discs round the core discs of every sample of the
        // instances (coreHulls): apart, no sample of theirs meets one of its.
        const Disc myHulls = hullsDiscOf(plan, k0, crowd[self].standHull);
        std::erase_if(close, [&](std::size_t o) {
            // (The crowd's own plans' discs are kept with them; a trial's are made here.)
            const bool changed = crowd.isChanged(o);
            const Disc theirs = changed ? pathDiscOf(crowd.plan(o), 0, crowd[o].spot) : crowd[o].pathAll;
            const float scale = std::fabs(mine.centre.x) + std::fabs(mine.centre.y) + std::fabs(theirs.centre.x) + std::fabs(theirs.centre.y);
            if (glm::length(mine.centre - theirs.centre) > kReach + mine.radius + theirs.radius + 0.02f + 1e-5f * scale) return true;
            return apartFromHull(myHulls, changed ? hullsDiscOf(crowd.plan(o), 0, crowd[o].standHull) : crowd[o].hullsAll);
        });
    }

    // What is known without the moment for one person's ways out that
    // share their instances from the way's start on (every lead of a way:
    // the same actions at the same roots) against the neighbours firstTouch
    // keeps for them, the crowd as it stands: per (instance, sample) of the
    // plan, a bit per neighbour and instance of theirs (a slot) that is set
    // when that instance of theirs cannot touch the person's body at that
    // sample, whatever its own sample: the person's core disc then
    // (CoreDiscs::placed: its action, sample and root alone) is apart from
    // the instance's core hull (hullApart's test), or no core sphere of the
    // person's meets one of the instance's swept spheres (CoreSpheres::apart: then
    // coresOverlap meets no pair of boxes to test). A set bit passes over
    // the pair as hullApart or coresOverlap would have, so firstTouch finds
    // the same first touch; the bits are worked out once for every lead
    // instead of once a moment, as the tests meet the samples, by whichever
    // thread gets there (the same value either way).
    struct ApartMemo {
        static constexpr std::uint64_t kDone = std::uint64_t{1} << 63;
        static constexpr std::size_t kMaxSlots = 63;
        std::vector<std::size_t> first;     // per instance from the way's start on: its first entry
        std::vector<std::size_t> slotBase;  // per kept neighbour: its first slot
        std::unique_ptr<std::atomic<std::uint64_t>[]> bits;  // 0: not worked out yet; else kDone | the slots apart
        // Per slot: its instance's core hull (placedHull; standing: standHull) and swept spheres placed.
        struct Slot {
            detail::CoreDiscs::Disc hull;
            detail::CoreSpheres::Placed swept;
        };
        std::vector<Slot> slots;
    };
    ApartMemo::Slot memoSlot(int action, const RootXf& root, const detail::CoreDiscs::Disc& hull) const {
        return {hull, spheres->swept(action, root)};
    }
    // The memo for plans whose instances from k0 on are those of `plan`
    // against the neighbours `close` of the crowd as it stands; none when
    // they have more than kMaxSlots instances in all.
    std::unique_ptr<ApartMemo> apartMemo(const std::vector<Bystander>& crowd, const std::vector<ActionInstance>& plan, std::size_t k0,
                                         const std::vector<std::size_t>& close) const {
        auto m = std::make_unique<ApartMemo>();
        std::size_t slots = 0;
        for (const std::size_t o : close) {
            m->slotBase.push_back(slots);
            slots += crowd[o].plan.empty() ? 1 : crowd[o].plan.size();
        }
        if (slots > ApartMemo::kMaxSlots) return nullptr;
        for (const std::size_t o : close) {
            const auto& theirs = crowd[o].plan;
            if (theirs.empty()) m->slots.push_back(memoSlot(hold, crowd[o].standRoot, crowd[o].standHull));
            for (const ActionInstance& inst : theirs) m->slots.push_back(memoSlot(inst.action, inst.root, placedHull(inst.action, inst.root)));
        }
        std::size_t entries = 0;
        for (std::size_t j = k0; j < plan.size(); ++j) {
            m->first.push_back(entries);
            entries += static_cast<std::size_t>(act(plan[j].action).sampleCount);
        }
        m->bits = std::make_unique<std::atomic<std::uint64_t>[]>(entries);
        for (std::size_t e = 0; e < entries; ++e) m->bits[e].store(0, std::memory_order_relaxed);
        return m;
    }

    // `kept`, when given: keptNeighbours' answer for these arguments, worked
    // out already; `memo`, when given, made for `kept` and the plan's
    // instances (the crowd as it stands, unchanged: no trial).
    std::pair<int, double> firstTouch(const CrowdView& crowd, std::size_t self, const std::vector<ActionInstance>& plan,
                                      double from, double until, std::size_t ignore = SIZE_MAX,
                                      const std::vector<std::size_t>* kept = nullptr, const ApartMemo* memo = nullptr) const {
        constexpr float kShrink = kTouchShrink;
        constexpr double dt = 1.0 / kSampleRate;
        thread_local std::vector<std::size_t> close;  // (no firstTouch runs inside another on a thread)
        if (kept) close = *kept;
        else keptNeighbours(crowd, self, plan, from, ignore, close);
        constexpr float kReach = 1.2f;  // coreBodiesOverlap's pelvis reach
        auto bodyOf = [&](std::size_t o, double t) {
            const auto& theirs = crowd.plan(o);
            return detail::CoreBody(lib, theirs.empty() ? standingBody(crowd[o].standRoot, t) : bodyIn(theirs, crowd[o].at, t), kShrink);
        };
        // The pelvis test, then the discs round the core boxes (the same answer as the boxes alone).
        auto overlap = [&](const detail::CoreBody& a, const detail::CoreDiscs::Disc& aDisc, const detail::CoreBody& b) {
            const glm::vec2 d = a.pelvis() - b.pelvis();
            if (glm::dot(d, d) > kReach * kReach) return false;
            if (detail::CoreDiscs::apart(aDisc, discs->placed(b))) return false;
            return coresOverlap(a, b);  // coreBodiesOverlap(a, b, kReach)
        };
        // Someone's pelvis at t is certainly beyond the pelvis reach of p:
        // standing, it keeps within holdWander of its spot; following a plan,
        // within the disc round its instance's pelvis path (pelvisPaths).
        auto surelyApart = [&](std::size_t o, double t, const glm::vec2& p) {
            const auto& theirs = crowd.plan(o);
            glm::vec2 centre = crowd[o].spot;
            float wander = holdWander;
            if (!theirs.empty()) {
                const ActionInstance& inst = theirs[playingAt(theirs, t)];
                const detail::CoreDiscs::Disc& path = pelvisPaths[static_cast<std::size_t>(inst.action)];
                centre = inst.root.pos + FloorRotation(inst.root.heading)(path.centre);
                wander = path.radius;
            }
            const float far = kReach + wander + 0.01f + 1e-5f * (std::fabs(centre.x) + std::fabs(centre.y));
            return glm::length(p - centre) > far;
        };
        // Their core discs at t are certainly apart from `meDisc`: the disc round
        // every sample's of the action they play at t (or their idle) is.
        auto hullApart = [&](std::size_t o, double t, const detail::CoreDiscs::Disc& meDisc) {
            const auto& theirs = crowd.plan(o);
            if (theirs.empty()) return apartFromHull(meDisc, crowd[o].standHull);
            const ActionInstance& inst = theirs[playingAt(theirs, t)];
            return apartFromHull(meDisc, placedHull(inst.action, inst.root));
        };
        auto touches = [&](std::size_t o, double t) {
            const detail::CoreBody me(lib, bodyIn(plan, crowd[self].at, t), kShrink);
            if (surelyApart(o, t, me.pelvis())) return false;
            const detail::CoreDiscs::Disc meDisc = discs->placed(me);
            if (hullApart(o, t, meDisc)) return false;
            return overlap(me, meDisc, bodyOf(o, t));
        };
        using Disc = detail::CoreDiscs::Disc;
        if (close.empty()) return {-1, 0.0};
        // Per instance of the plan, the disc round its core hulls (coreHulls);
        // per neighbour left who stands, whether it is apart from theirs
        // (standHull): a moment whose instance is apart from everyone's is
        // passed over without placing its body (hullApart's test, for the
        // whole instance at once).
        thread_local std::vector<Disc> ownHulls;
        thread_local std::vector<char> standApart;  // [neighbour * plan.size() + instance]
        ownHulls.clear(), standApart.assign(close.size() * plan.size(), 0);
        for (const ActionInstance& inst : plan) ownHulls.push_back(placedHull(inst.action, inst.root));
        for (std::size_t c = 0; c < close.size(); ++c) {
            if (!crowd.plan(close[c]).empty()) continue;
            for (std::size_t k = 0; k < plan.size(); ++k) standApart[c * plan.size() + k] = apartFromHull(ownHulls[k], crowd[close[c]].standHull);
        }
        // Is neighbour close[c] at t certainly apart from the instance k of the plan?
        auto instanceApart = [&](std::size_t c, std::size_t k, double t) {
            const auto& theirs = crowd.plan(close[c]);
            if (theirs.empty()) return standApart[c * plan.size() + k] != 0;
            const std::size_t j = playingAt(theirs, t);
            // (The memo holds the same placedHull.)
            if (memo) return apartFromHull(ownHulls[k], memo->slots[memo->slotBase[c] + j].hull);
            return apartFromHull(ownHulls[k], placedHull(theirs[j].action, theirs[j].root));
        };
        auto ownInstance = [&](double t) { return playingAt(plan, t); };
        // The memo's bits for the moment t, instance k of the plan: 0 when
        // there is no memo for it (nothing known), else kDone | the slots apart.
        const std::size_t memoBase = memo ? plan.size() - memo->first.size() : 0;  // the plan's instance of memo->first[0]
        auto apartBits = [&](std::size_t k, double t) -> std::uint64_t {
            if (!memo || k < memoBase) return 0;
            const ActionInstance& inst = plan[k];
            const double tau = inst.clipTimeAt(t);
            const int sample = sampleOf(inst.action, tau);
            std::atomic<std::uint64_t>& e = memo->bits[memo->first[k - memoBase] + static_cast<std::size_t>(sample)];
            std::uint64_t v = e.load(std::memory_order_relaxed);
            if (v) return v;
            // discs->placed(me) for the body bodyIn gives at t: it reads the action, sample and root alone.
            const FloorRotation rot(inst.root.heading);
            const detail::CoreDiscs::Disc meDisc = discs->placed(detail::BodyPose{inst.action, tau, inst.root}, rot);
            // And its core spheres.
            const detail::CoreSpheres::Placed mine = spheres->placed(inst.action, sample, inst.root, rot);
            v = ApartMemo::kDone;
            for (std::size_t q = 0; q < memo->slots.size(); ++q) {
                const ApartMemo::Slot& slot = memo->slots[q];
                if (apartFromHull(meDisc, slot.hull) || detail::CoreSpheres::apart(mine, slot.swept)) v |= std::uint64_t{1} << q;
            }
            e.store(v, std::memory_order_relaxed);
            return v;
        };
        // Is neighbour close[c] at t certainly not touching, by the memo's bits?
        auto slotApart = [&](std::uint64_t bits, std::size_t c, double t) {
            const auto& theirs = crowd.plan(close[c]);
            const std::size_t slot = memo->slotBase[c] + (theirs.empty() ? 0 : playingAt(theirs, t));
            return ((bits >> slot) & 1) != 0;
        };
        const double settle = std::min(until, std::max(from, movingWindow(plan).second) + dt);
        for (double t = from; t <= settle + 1e-9; t += dt) {
            std::uint64_t bits = 0;
            if (!plan.empty()) {
                const std::size_t k = ownInstance(t);
                bool anyone = false;
                for (std::size_t c = 0; c < close.size() && !anyone; ++c) anyone = !instanceApart(c, k, t);
                if (!anyone) continue;
                // Nobody can touch it at this sample: no body to place.
                bits = apartBits(k, t);
                if (bits) {
                    anyone = false;
                    for (std::size_t c = 0; c < close.size() && !anyone; ++c) anyone = !slotApart(bits, c, t);
                    if (!anyone) continue;
                }
            }
            // Its own body once per moment (its boxes placed only when someone is near).
            const detail::CoreBody me(lib, bodyIn(plan, crowd[self].at, t), kShrink);
            const detail::CoreDiscs::Disc meDisc = discs->placed(me);
            for (std::size_t c = 0; c < close.size(); ++c) {
                const std::size_t o = close[c];
                if (bits ? slotApart(bits, c, t) : hullApart(o, t, meDisc)) continue;
                if (surelyApart(o, t, me.pelvis())) continue;
                if (overlap(me, meDisc, bodyOf(o, t))) return {static_cast<int>(o), t};
            }
        }
        std::pair<int, double> first{-1, std::numeric_limits<double>::infinity()};
        for (std::size_t c = 0; c < close.size(); ++c) {
            const std::size_t o = close[c];
            const auto [w0, w1] = movingWindow(crowd.plan(o));
            for (double t = std::max(settle, w0 - dt); t <= std::min({until, w1 + dt, first.second}) + 1e-9; t += dt) {
                if (!plan.empty()) {
                    const std::size_t k = ownInstance(t);
                    if (instanceApart(c, k, t)) continue;
                    if (const std::uint64_t bits = apartBits(k, t); bits && slotApart(bits, c, t)) continue;  // touches would say no
                }
                if (touches(o, t)) {
                    first = {static_cast<int>(o), t};
                    break;
                }
            }
        }
        return first.first >= 0 ? first : std::pair<int, double>{-1, 0.0};
    }

    // `idle` played from its start over and over from `from` until `until`,
    // placed at `root`: one looped instance (ActionInstance::loop), so
    // someone standing for minutes costs one instance, not one a time round.
    // None when there is no time to stand.
    std::optional<ActionInstance> loopedIdle(int idle, double from, double until, const RootXf& root) const {
        if (from >= until - 1e-6) return std::nullopt;
        const double d = act(idle).duration;
        // Whole repetitions until within 1e-6 s of `until`, the last cut at `until`.
        const double n = std::max(1.0, std::ceil((until - 1e-6 - from) / d));
        ActionInstance inst{idle, from, 0.0, std::min(until, from + n * d), root, false, false};
        inst.loop = d;
        return inst;
    }

    // Stands in the guard at `at` from 0 until `until` (the clip from its start each time round).
    std::vector<ActionInstance> standing(const RootXf& at, double until) const {
        std::vector<ActionInstance> plan;
        if (auto inst = loopedIdle(hold, 0.0, until, at * lib.rootAt(hold, 0).inverse())) plan.push_back(*inst);
        return plan;
    }

    // Stands until `from`, plays `actions` one after another (the first from
    // clip time `offset`, placed at `root`), then stands where they leave off until `until`.
    std::vector<ActionInstance> planMove(const RootXf& at, double from, const std::vector<int>& actions, double offset,
                                         const RootXf& root, bool forced, double until) const {
        std::vector<ActionInstance> plan;
        plan.reserve(actions.size() + 2);  // standing, the actions, the idle after: one allocation
        planMoveInto(plan, at, from, actions, offset, root, forced, until);
        return plan;
    }
    // The same plan into `plan` (a vector, or a SmallPlan for a way out: no heap).
    template <class Plan>
    void planMoveInto(Plan& plan, const RootXf& at, double from, const std::vector<int>& actions, double offset,
                      const RootXf& root, bool forced, double until) const {
        if (auto inst = loopedIdle(hold, 0.0, from, at * lib.rootAt(hold, 0).inverse())) plan.push_back(*inst);  // standing(at, from)
        double t = from;
        RootXf place = root;
        for (std::size_t k = 0; k < actions.size(); ++k) {
            const double off = k == 0 ? offset : 0.0;
            const double end = t + act(actions[k]).duration - off;
            plan.push_back({actions[k], t, off, end, place, forced && k == 0, false});
            place = place * act(actions[k]).end;
            t = end;
        }
        const int idle = idleAfter(actions.back());
        if (auto inst = loopedIdle(idle, t, until, place * lib.rootAt(idle, 0).inverse())) plan.push_back(*inst);
    }
    // A way out's plan on the stack: standing, at most kMaxWayActions actions, the idle after.
    static constexpr std::size_t kMaxWayActions = 2;
    struct SmallPlan {
        std::array<ActionInstance, kMaxWayActions + 2> inst{};
        std::size_t n = 0;
        void clear() { n = 0; }
        void push_back(const ActionInstance& a) { inst[n++] = a; }
        std::size_t size() const { return n; }
        const ActionInstance& operator[](std::size_t k) const { return inst[k]; }
    };

    // Someone pushed into a reaction: by a bystander (index) or the rat (SIZE_MAX), when, and their new plan.
    struct Push {
        std::size_t who = 0, by = SIZE_MAX;
        double time = 0;
        std::vector<ActionInstance> plan;
    };

    // Pushes bystander q at time t away from `pusher` (bystander `by`, or the
    // rat when SIZE_MAX): the forced reaction matching its posture and the
    // push. Its neighbours may be pushed on in turn (depth levels). Returns the
    // changed plans, or nothing when the push would put anyone in the rat's
    // way or into someone who is already moving.
    std::optional<std::vector<Push>> push(const CrowdView& crowd, std::size_t q, std::size_t by, const RootXf& pusher,
                                          double t, double until, int depth) const {
        const Bystander& b = crowd[q];
        if (!crowd.plan(q).empty()) return std::nullopt;  // it has moved, or will: its plan stands
        // Near the trajectory and not yet out of the way: it must get out of
        // the way itself before the rat has passed (pushed later, it would
        // have stood in the rat's way).
        if (by != SIZE_MAX && b.near && t >= b.passTime + 0.6) return std::nullopt;
        const detail::BodyPose body = bodyIn(crowd.plan(q), b.at, t);
        const auto reaction = rules->react({body.action, t, body.tau, body.root}, pusher, t, false, pushedPool);
        if (reaction.action < 0) return std::nullopt;
        auto plan = planMove(b.at, t, {reaction.action}, reaction.offset, reaction.root, true, until);
        // Pushed by someone else, it must not reel into the rat's way (pushed by the rat, it is in it).
        if (by != SIZE_MAX && b.near && t < b.passTime + 0.6 && ratClearance(b, plan) < kRatClear) return std::nullopt;
        std::vector<Push> changes;
        CrowdView trial = crowd;
        trial.set(q, plan);
        const double settled = until;  // both stand still afterwards: touching later counts too
        const auto [other, when] = firstTouch(trial, q, plan, t, settled, by);
        if (other >= 0) {
            if (depth <= 0) return std::nullopt;
            const detail::BodyPose mine = bodyIn(plan, b.at, when);
            auto more = push(trial, static_cast<std::size_t>(other), q, mine.root * lib.rootAt(mine.action, mine.tau), when,
                             until, depth - 1);
            if (!more) return std::nullopt;
            for (const auto& m : *more) trial.set(m.who, m.plan);
            if (firstTouch(trial, q, plan, when, settled, static_cast<std::size_t>(other)).first >= 0) return std::nullopt;
            if (firstTouch(trial, q, plan, when + kContactWindow, settled, by).first >= 0) return std::nullopt;
            changes = std::move(*more);
        }
        changes.push_back({q, by, t, std::move(plan)});
        return changes;
    }

    // Takes a push into the crowd's plans (and the log of contacts).
    void commit(std::vector<Bystander>& crowd, Push&& m, std::vector<Push>& log) {
        Bystander& o = crowd[m.who];
        o.plan = m.plan;
        refreshDiscs(o);
        if (m.by != SIZE_MAX) ++ownStats.bumps;
        log.push_back(std::move(m));
    }

    static constexpr double kRatClear = 0.08;
    static constexpr std::size_t kCandidateBatch = 8;  // candidates whose body tests run in parallel at a time
    static constexpr double kContactWindow = 0.2;  // s a bump may keep two bodies touching (MetricsOptions::hitWindow)  // m between the rat and an avoider's feet and shins
    std::optional<detail::InteractionEngine> rules;  // forced reactions of the pushed
    static constexpr float kTouchShrink = 0.82f;     // firstTouch's, as the composer's penetration test
    std::optional<detail::CoreDiscs> discs;          // firstTouch's first test
    std::optional<detail::CoreSpheres> spheres;      // the memo's sphere test (ApartMemo)
    int pushedPool = 0;
    SceneCharacter ratBody;  // the rat's keys

    Status run(const ProgressFn& progress) {
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
};

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
