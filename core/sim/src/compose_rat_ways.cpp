// The rat scene's ways out: the rat patches (makeRatPatches, ratCandidates), the
// ways that clear the rat (clearWays) and the neighbour test (keptNeighbours,
// apartMemo, firstTouch). The composer is in compose_rat.h.
#include "compose_rat.h"

namespace fray::sim::detail {

void RatComposer::makeRatPatches() {
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

std::vector<RatComposer::RatPatch> RatComposer::ratCandidates(const Bystander& b) const {
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

std::vector<RatComposer::ClearWay> RatComposer::clearWays(const Bystander& b, double until) const {
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

void RatComposer::keptNeighbours(const CrowdView& crowd, std::size_t self, const std::vector<ActionInstance>& plan, double from,
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

std::unique_ptr<RatComposer::ApartMemo> RatComposer::apartMemo(const std::vector<Bystander>& crowd, const std::vector<ActionInstance>& plan,
                                                              std::size_t k0, const std::vector<std::size_t>& close) const {
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

std::pair<int, double> RatComposer::firstTouch(const CrowdView& crowd, std::size_t self, const std::vector<ActionInstance>& plan,
                                               double from, double until, std::size_t ignore, const std::vector<std::size_t>* kept,
                                               const ApartMemo* memo) const {
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

}  // namespace fray::sim::detail
