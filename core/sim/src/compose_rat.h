#pragma once
// The rat scene's composer (SPEC 4.5), shared by compose_rat.cpp (its run, the
// kind module and ratAvoidPatches) and compose_rat_ways.cpp (the rat patches, the
// ways out and the neighbour test). Small helpers the inner loops call stay here,
// inline.
#include <atomic>
#include <cstring>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "compose_grid.h"
#include "compose_kinds.h"
#include "fray/sim/compose/rat.h"

namespace fray::sim::detail {

// Also serves ratAvoidPatches (compose_rat.cpp).
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

    void makeRatPatches();

    // The patches of the cells nearest a bystander's configuration (the two
    // nearest lateral offsets by the two nearest facings), each way and lead once.
    std::vector<RatPatch> ratCandidates(const Bystander& b) const;

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
    std::vector<ClearWay> clearWays(const Bystander& b, double until) const;

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
                        std::size_t ignore, std::vector<std::size_t>& close) const;

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
                                         const std::vector<std::size_t>& close) const;

    // `kept`, when given: keptNeighbours' answer for these arguments, worked
    // out already; `memo`, when given, made for `kept` and the plan's
    // instances (the crowd as it stands, unchanged: no trial).
    std::pair<int, double> firstTouch(const CrowdView& crowd, std::size_t self, const std::vector<ActionInstance>& plan,
                                      double from, double until, std::size_t ignore = SIZE_MAX,
                                      const std::vector<std::size_t>* kept = nullptr, const ApartMemo* memo = nullptr) const;

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

    Status run(const ProgressFn& progress);
};

}  // namespace fray::sim::detail
