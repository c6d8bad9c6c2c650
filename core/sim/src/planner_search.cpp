// Tree expansion's rules and search (SPEC 2.1-2.4): advancing a group from
// one node to the next (hits, forced reactions, catches, checkpoints), edge
// scores, the pruning criteria, and min-max with alpha-beta over the next
// decisions, the root in parallel.
#include <bit>
#include <cmath>
#include <numeric>
#include <optional>
#include <deque>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "planner_state.h"

namespace fray::sim::planner {

namespace {

// The opponent's placed core body at one of the penetration test's times,
// and, once its boxes are placed, their centres and bounding radii laid out
// lane by lane (x, y, z, r; the unused lanes far away), so one candidate box
// is tested against all of its spheres at once: the same float operations
// as the box-by-box test, so the same answers.
// A body's placed core boxes are a function of its clip, the clip's sample
// and its placement (and the shrink): the opponent's body at the penetration
// test's times is the same for every node below its launch, at the node
// times that fall on the same sample. A per-thread direct-mapped table of
// them (about 200 kB, made on first use; keys compared bit for bit, a miss
// places them afresh).
struct BodyCache {
    struct Entry {
        int action = -1, sample = 0;
        RootXf root;
        float shrink = 0;
        std::array<Obb, kCoreSegments.size()> boxes;
        std::array<float, kCoreSegments.size()> radii{};
    };
    static constexpr std::size_t kSize = 512;
    std::vector<Entry> slots;
    static bool same(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
    // The placed boxes and radii of `body` (CoreBody::boxes' values).
    const Entry& of(const ActionLibrary& lib, const detail::CoreBody& body, float shrink) {
        const auto& pose = body.pose();
        const int sample = lib.sampleAt(pose.action, pose.tau);
        std::uint64_t h = static_cast<std::uint64_t>(static_cast<std::uint32_t>(pose.action)) * 0x9e3779b97f4a7c15ull;
        h ^= static_cast<std::uint64_t>(static_cast<std::uint32_t>(sample)) + 0x7f4a7c15ull + (h << 6) + (h >> 2);
        h ^= (static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(pose.root.pos.x)) << 32 | std::bit_cast<std::uint32_t>(pose.root.pos.y)) * 0xff51afd7ed558ccdull;
        h ^= std::bit_cast<std::uint64_t>(pose.root.heading) * 0xc4ceb9fe1a85ec53ull;
        if (slots.empty()) slots.resize(kSize);
        Entry& e = slots[static_cast<std::size_t>(h ^ (h >> 29)) & (kSize - 1)];
        if (e.action != pose.action || e.sample != sample || !same(e.root.pos.x, pose.root.pos.x) ||
            !same(e.root.pos.y, pose.root.pos.y) || std::bit_cast<std::uint64_t>(e.root.heading) != std::bit_cast<std::uint64_t>(pose.root.heading) ||
            !same(e.shrink, shrink)) {
            e.boxes = body.boxes();
            e.radii = body.radii();
            e.action = pose.action, e.sample = sample, e.root = pose.root, e.shrink = shrink;
        }
        return e;
    }
};

struct OpponentBody {
    static constexpr std::size_t kLanes = 8;
    detail::CoreBody body;
    std::array<Obb, kCoreSegments.size()> boxes;  // body.boxes(), once laid out
    std::array<float, kLanes> x{}, y{}, z{}, r{};
    bool laidOut = false;
    float shrink;
    OpponentBody(const ActionLibrary& lib, const detail::BodyPose& pose, float s) : body(lib, pose, s), shrink(s) {}
    // cache: where to look the boxes up (null: placed here).
    void layOut(const ActionLibrary& lib, BodyCache* cache) {
        const std::array<float, kCoreSegments.size()>* radii = nullptr;
        if (cache) {
            const auto& e = cache->of(lib, body, shrink);
            boxes = e.boxes;
            radii = &e.radii;
        } else {
            boxes = body.boxes();
            radii = &body.radii();
        }
        for (std::size_t j = 0; j < kLanes; ++j) {
            const bool used = j < boxes.size();
            x[j] = used ? boxes[j].centre.x : 1e18f;
            y[j] = used ? boxes[j].centre.y : 1e18f;
            z[j] = used ? boxes[j].centre.z : 1e18f;
            r[j] = used ? (*radii)[j] : 0.0f;
        }
        laidOut = true;
    }
    // Bit j set: box j's bounding sphere meets the sphere (centre, radius),
    // that is !(|box j's centre - centre|^2 > (radius + r_j)^2) as the
    // scalar test computes it.
    unsigned spheresMeet(const glm::vec3& centre, float radius) const {
#if defined(__SSE2__)
        unsigned mask = 0;
        const __m128 cx = _mm_set1_ps(centre.x), cy = _mm_set1_ps(centre.y), cz = _mm_set1_ps(centre.z);
        const __m128 rad = _mm_set1_ps(radius);
        for (std::size_t h = 0; h < kLanes; h += 4) {
            const __m128 dx = _mm_sub_ps(_mm_loadu_ps(&x[h]), cx);
            const __m128 dy = _mm_sub_ps(_mm_loadu_ps(&y[h]), cy);
            const __m128 dz = _mm_sub_ps(_mm_loadu_ps(&z[h]), cz);
            const __m128 d2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
            const __m128 rr = _mm_add_ps(rad, _mm_loadu_ps(&r[h]));
            mask |= static_cast<unsigned>(_mm_movemask_ps(_mm_cmpngt_ps(d2, _mm_mul_ps(rr, rr)))) << h;
        }
        return mask;
#else
        unsigned mask = 0;
        for (std::size_t j = 0; j < kLanes; ++j) {
            const glm::vec3 c = glm::vec3(x[j], y[j], z[j]) - centre;
            const float rr = radius + r[j];
            if (!(glm::dot(c, c) > rr * rr)) mask |= 1u << j;
        }
        return mask;
#endif
    }
};



bool bodiesPenetrate(const Context& ctx, const RootXf& place, int action, double tau, const CharState& other, double t) {
    return detail::coreBodiesOverlap(*ctx.lib, {action, tau, place}, detail::bodyAt(playing(other), std::min(t, other.end)),
                                     kPenetrationShrink, kPenetrationReach);
}

// Legal choices of `who` at a node (SPEC 2.1) and the pruning criteria
// (SPEC 2.4) as predicates, so the frontier can test them lazily.
class Pruner {
public:
    // bodies: where to keep the opponent's placed bodies (reused storage), else the pruner's own.
    // cache: the thread's table of placed bodies (null: none).
    Pruner(const Context& ctx, const GroupState& g, int who, bool root, std::vector<OpponentBody>* bodies = nullptr,
           BodyCache* cache = nullptr)
        : ctx_(ctx), g_(g), who_(who), opponentBodies_(bodies ? *bodies : ownBodies_), bodyCache_(cache) {
        opponentBodies_.clear();
        const auto& spec = specOf(ctx, who);
        const auto& s = g.c[static_cast<std::size_t>(who)];
        // Inside the tree with no stage, the variant-folded list is ready
        // made (on a stage the folding comes after the stage's filter).
        const auto& member = ctx.members[static_cast<std::size_t>(who)];
        bool folded = !root && ctx.opt->variants && !ctx.opt->arena.bounded();
        // The member's list itself unless this node changes it (no copy per node).
        list_ = &(folded ? member.folded : member.legal)[static_cast<std::size_t>(s.action)];
        const bool changes = list_->empty() || ctx.opt->arena.bounded() || (!root && ctx.opt->variants && !folded);
        if (changes) {
            base_ = *list_;
            list_ = &base_;
        }
        if (base_.empty() && changes) {
            folded = false;
            // No legal action: an idle/guard one of its set (else any).
            fallback_ = true;
            for (int a : spec.allowed) {
                if (act(ctx, a).is(kIdle) && !act(ctx, a).is(kReactive)) base_.push_back(a);
            }
            if (base_.empty()) {
                for (int a : spec.allowed) {
                    if (!act(ctx, a).is(kReactive)) base_.push_back(a);
                }
            }
            if (base_.empty()) base_ = spec.allowed;
        }
        if (ctx.opt->arena.bounded()) keepInsideArena(s);
        if (!root && ctx.opt->variants && !folded && base_.size() > 1) {
            // One representative (the first) per variant class: a class is
            // seen when its stamp holds this call's number.
            thread_local std::vector<std::uint64_t> seenAt;
            thread_local std::uint64_t call = 0;
            ++call;
            seenAt.resize(ctx.lib->variantClass().size() + 1, 0);
            std::erase_if(base_, [&](int a) {
                auto& stamp = seenAt[static_cast<std::size_t>(ctx.lib->variantClass()[static_cast<std::size_t>(a)])];
                if (stamp == call) return true;
                stamp = call;
                return false;
            });
        }
        if (!root && !ctx.treePins.empty()) keepPinned();
        opp_ = ctx.opt->pruning ? opponentOf(ctx, g, who, g.time) : -1;
        if (opp_ >= 0) {
            const auto& o = g.c[static_cast<std::size_t>(opp_)];
            start_ = s.root * act(ctx, s.action).end;
            startRotation_ = FloorRotation(start_.heading);
            r_ = static_cast<double>(glm::length(placement(ctx, o, g.time).pos - start_.pos));
            const auto& oa = act(ctx, o.action);
            oppAttacking_ = oa.is(kAttack) && !o.attackDone && clipTime(o, g.time) < oa.activeEnd / kSampleRate &&
                            r_ <= spec.weights.defenceRange;
        }
    }
    bool fallback() const { return fallback_; }
    bool active() const { return opp_ >= 0; }
    const std::vector<int>& base() const { return *list_; }
    // The member's list itself (Member::legal or folded) when this node
    // did not change it, else null.
    const std::vector<int>* memberList() const { return list_ == &base_ ? nullptr : list_; }

    // 1. The bodies do not penetrate (over the time both actions are known).
    bool penetrationFree(int a, bool lastFrameOnly) const {
        const auto& o = g_.c[static_cast<std::size_t>(opp_)];
        const double T = std::clamp(o.end - g_.time, 1.0 / kSampleRate, act(ctx_, a).duration);
        if (lastFrameOnly) return !bodiesPenetrate(ctx_, start_, a, T, o, g_.time + T);
        // Every candidate is tested at the same times against the same
        // opponent: its placed body at the k-th time is kept for the next.
        std::size_t k = 0;
        const auto ak = static_cast<std::size_t>(a);
        const std::size_t pelvisBegin = ctx_.testPelvisBegin[ak];
        const std::size_t pelvisCount = ctx_.testPelvisBegin[ak + 1] - pelvisBegin;
        for (double tau = 0; tau <= T + 1e-9; tau += kPenetrationStep, ++k) {
            if (k == opponentBodies_.size()) {
                opponentBodies_.emplace_back(*ctx_.lib, detail::bodyAt(playing(o), std::min(g_.time + tau, o.end)),
                                             kPenetrationShrink);
            }
            if (k >= pelvisCount) {  // (the table covers every time the loop reaches)
                const detail::CoreBody me(*ctx_.lib, {a, tau, start_}, startRotation_, ctx_.lib->rootAt(a, tau).pos,
                                          kPenetrationShrink);
                if (detail::coreBodiesOverlap(me, opponentBodies_[k].body, kPenetrationReach)) return false;
                continue;
            }
            // detail::coreBodiesOverlap with the boxes from the table, each
            // box's axes placed only when its bounding sphere meets one of
            // the opponent's (the same centres, radii and tests).
            OpponentBody& them = opponentBodies_[k];
            const glm::vec2 d = start_.pos + startRotation_(ctx_.testPelvis[pelvisBegin + k]) - them.body.pelvis();
            if (glm::dot(d, d) > kPenetrationReach * kPenetrationReach) continue;
            const auto& body = ctx_.testBodies[pelvisBegin + k];
            if (!them.laidOut) them.layOut(*ctx_.lib, bodyCache_);
            const auto& theirs = them.boxes;
            for (std::size_t i = 0; i < body.boxes.size(); ++i) {
                const Obb& mine = body.boxes[i];
                const glm::vec3 centre = mine.placedCentre(start_, startRotation_);
                unsigned meet = them.spheresMeet(centre, body.radii[i]);
                if (meet == 0) continue;
                // Any overlapping pair answers, whichever is found first. The
                // box's axes are placed (as Obb::placed places them) when a
                // test first needs each.
                std::array<glm::vec3, 3> axes;
                unsigned placedAxes = 0;
                const auto axis = [&](int n) -> const glm::vec3& {
                    const auto j = static_cast<std::size_t>(n);
                    if (!(placedAxes >> j & 1u)) axes[j] = startRotation_(mine.axes[n]), placedAxes |= 1u << j;
                    return axes[j];
                };
                for (; meet != 0; meet &= meet - 1) {
                    if (overlapsBeyondSpheresWith(centre, axis, mine.half, theirs[static_cast<std::size_t>(std::countr_zero(meet))])) return false;
                }
            }
        }
        return true;
    }
    // 2. Ends facing the opponent.
    bool facing(int a) const {
        if (!specOf(ctx_, who_).weights.faceOpponent) return true;
        const auto& o = g_.c[static_cast<std::size_t>(opp_)];
        const double d = act(ctx_, a).duration;
        const auto k = static_cast<std::size_t>(a);
        const glm::vec2 end = start_.pos + startRotation_(ctx_.endAt[k].pos);
        // Most candidates outlast the opponent's action: its end placement once.
        if (g_.time + d >= o.end && !oppEnd_) oppEnd_ = placement(ctx_, o, o.end).pos;
        const glm::vec2 to = (g_.time + d >= o.end ? *oppEnd_ : placement(ctx_, o, g_.time + d).pos) - end;
        if (glm::dot(to, to) < 1e-6f) return true;
        // Within 90 degrees of its facing there: no angle needed.
        return glm::dot(to, startRotation_(ctx_.endFacing[k])) >= 0.0f;
    }
    // 3. In distance: no attack beyond attackRange, no defence beyond defenceRange.
    bool inDistance(int a) const {
        const auto& x = act(ctx_, a);
        const auto& w = specOf(ctx_, who_).weights;
        // An attack is out of distance past its own reach (plus a step's
        // worth of the opponent's body depth), and never past attackRange.
        if (x.is(kAttack) && r_ > std::min(w.attackRange, x.reach + kReachMargin)) return false;
        if (x.is(kDefence) && r_ > w.defenceRange) return false;
        return true;
    }
    // 4. Required: while the opponent attacks (and can still land), only defences.
    bool required(int a) const { return !oppAttacking_ || act(ctx_, a).is(kDefence); }
    bool cheapCriteria(int a) const { return facing(a) && inDistance(a) && required(a); }

    // The full rule: criteria in priority order, each skipped when it would
    // leave nothing (criterion 1 first falls back to its last-frame form).
    void prune(std::vector<int>& out, Stats& stats) const {
        out = base();
        stats.choices += static_cast<std::int64_t>(out.size());
        if (!active()) return;
        const std::size_t before = out.size();
        // When some candidate passes every criterion the rule keeps exactly
        // those: the costly penetration test is then needed only for the
        // candidates that pass the cheap ones.
        std::vector<int> all;
        for (int a : out) {
            if (cheapCriteria(a) && penetrationFree(a, false)) all.push_back(a);
        }
        if (!all.empty()) {
            out.swap(all);
            stats.pruned += static_cast<std::int64_t>(before - out.size());
            return;
        }
        auto apply = [&](auto&& keep) {
            std::vector<int> kept;
            for (int a : out) {
                if (keep(a)) kept.push_back(a);
            }
            if (kept.empty()) return false;
            out.swap(kept);
            return true;
        };
        if (!apply([&](int a) { return penetrationFree(a, false); })) apply([&](int a) { return penetrationFree(a, true); });
        apply([&](int a) { return facing(a); });
        apply([&](int a) { return inDistance(a); });
        apply([&](int a) { return required(a); });
        stats.pruned += static_cast<std::int64_t>(before - out.size());
    }

private:
    // The stage (SimOptions::arena). A candidate is judged by how far
    // out it would get before it could come back: its end's distance from
    // the centre, plus, when it ends heading away, part of a turning circle
    // at its speed (v^2 / 4 m/s^2 lateral acceleration: about 2 m for a run,
    // 0.5 m for a walk), and near the edge the best such value up to three
    // clips later (running turns take several clips; judging one clip alone
    // let runners leave the stage clip by clip). Candidates within the inner
    // edge stay; when none is, those within 0.25 m of the best.
    double arenaReach(const RootXf& at, int action) const {
        const auto& a = act(ctx_, action);
        const RootXf e = at * a.end;
        const glm::vec2 out = e.pos - ctx_.opt->arena.centre;
        const double d = static_cast<double>(glm::length(out));
        const double v = static_cast<double>(glm::length(a.end.pos)) / std::max(a.duration, 1e-3);
        const double turn = std::clamp(v * v / 4.0, 0.3, 3.0);
        const double c = d > 1e-6 ? static_cast<double>(glm::dot(headingVector(e.heading), out)) / d : 0.0;
        return d + turn * 0.5 * (1.0 + c);
    }
    // Best arenaReach over up to kArenaLookAhead further clips after
    // `action` (ending at `at`): a beam search through Next() keeping the
    // kArenaBeam most promising clips per step, so a fighting node's hundreds
    // of successors cost hundreds of evaluations, not millions.
    double lookAhead(const RootXf& at, int action, const std::vector<int>& allowed) const {
        struct Step {
            RootXf end;
            int action;
            double reach;
        };
        std::vector<Step> frontier{{at, action, 0.0}}, next;
        double best = 1e300;
        for (int depth = 0; depth < kArenaLookAhead && !frontier.empty(); ++depth) {
            next.clear();
            for (const Step& f : frontier) {
                for (int b : ctx_.lib->next()[static_cast<std::size_t>(f.action)]) {
                    if (act(ctx_, b).is(kReactive) || !std::binary_search(allowed.begin(), allowed.end(), b)) continue;
                    const double r = arenaReach(f.end, b);
                    best = std::min(best, r);
                    next.push_back({f.end * act(ctx_, b).end, b, r});
                }
            }
            const std::size_t keep = std::min<std::size_t>(next.size(), kArenaBeam);
            std::partial_sort(next.begin(), next.begin() + static_cast<std::ptrdiff_t>(keep), next.end(),
                              [](const Step& x, const Step& y) { return x.reach < y.reach || (x.reach == y.reach && x.action < y.action); });
            next.resize(keep);
            frontier.swap(next);
        }
        return best;
    }
    // Pins in the look-ahead (Context::treePins): at the pin's node only the
    // pinned actions the list holds (none: the list as it is).
    void keepPinned() {
        const ActionPin* pin = ctx_.treePins[static_cast<std::size_t>(who_)];
        if (!pin || !PinGuide::pinNode(*pin, g_, who_)) return;
        std::vector<int> kept;
        std::copy_if(list_->begin(), list_->end(), std::back_inserter(kept),
                     [&](int a) { return std::binary_search(pin->actions.begin(), pin->actions.end(), a); });
        if (kept.empty()) return;
        base_.swap(kept);
        list_ = &base_;
    }
    void keepInsideArena(const CharState& s) {
        const RootXf from = s.root * act(ctx_, s.action).end;
        const double inner = std::max(ctx_.opt->arena.radius - kArenaMargin, 0.0);
        const auto& allowed = specOf(ctx_, who_).allowed;
        std::vector<double> reach(base_.size());
        for (std::size_t i = 0; i < base_.size(); ++i) {
            reach[i] = arenaReach(from, base_[i]);
            if (reach[i] <= inner) continue;
            reach[i] = std::min(reach[i], lookAhead(from * act(ctx_, base_[i]).end, base_[i], allowed));
        }
        const double best = *std::min_element(reach.begin(), reach.end());
        const double limit = best <= inner ? inner : best + 0.25;
        std::vector<int> kept;
        for (std::size_t i = 0; i < base_.size(); ++i)
            if (reach[i] <= limit) kept.push_back(base_[i]);
        base_.swap(kept);
    }

    const Context& ctx_;
    const GroupState& g_;
    int who_;
    const std::vector<int>* list_ = nullptr;  // the candidates: a member's list, or base_
    std::vector<int> base_;
    bool fallback_ = false;
    int opp_ = -1;
    RootXf start_;
    FloorRotation startRotation_{0.0};
    mutable std::vector<OpponentBody> ownBodies_;
    std::vector<OpponentBody>& opponentBodies_;
    BodyCache* bodyCache_;
    mutable std::optional<glm::vec2> oppEnd_;  // the opponent where its action ends (facing)
    double r_ = 0;
    bool oppAttacking_ = false;
};

// Candidate actions of `who` at node time t after pruning. Returns whether it
// had to fall back (no legal action: idle/guard).
bool candidates(const Context& ctx, const GroupState& g, int who, std::vector<int>& out, Stats& stats) {
    const Pruner pruner(ctx, g, who, true);
    pruner.prune(out, stats);
    return pruner.fallback();
}

struct Child {
    int action = 0;
    GroupState state;
    Value acc;
    Value edge;  // the edge score of the launch (acc is the parent's plus or minus it)
    double order = 0;
};

bool isMax(const Context& ctx, int who, int rootSide) { return specOf(ctx, who).side == rootSide; }

// The child reached by `who` launching `action` from g, with the path sums.
void makeChild(const Context& ctx, const GroupState& g, int who, int action, const Value& acc, bool mx, Child& ch,
               PlacementMemo& oppAt) {
    ch.action = action;
    ch.state = g;
    launch(ctx, ch.state, who, action, g.time);
    Events ev;
    advance(ctx, ch.state, ev, nullptr);
    const Value e = edgeScore(ctx, g, ch.state, who, action, ev, oppAt);
    noteReads(ctx, g, ch.state, who, action);  // incremental re-planning (PlanCache)
    ch.edge = e;
    ch.acc.comp = acc.comp + (mx ? e.comp : -e.comp);
    ch.acc.coop = acc.coop + e.coop;
    ch.order = mx ? ch.acc.comp + ch.acc.coop : -(ch.acc.comp - ch.acc.coop);
}

// Better for the chooser of this node (SPEC 2.2 back-up rules).
bool better(bool mx, const Value& a, const Value& b) {
    return mx ? (a.comp + a.coop > b.comp + b.coop) : (a.comp - a.coop < b.comp - b.coop);
}

// An upper bound of the edge score `who` would get by launching `action` at
// g in a duel scored by blows (Context::boundedFrontier): its combination
// and recency terms, the fastest blow it can land and nothing else (the
// movement and stage terms are never positive, a blow received only costs).
// A small slack covers the different order of the floating-point sums.
// (With the recency given: the static key order below computes it with none.)
double edgeBound(const Context& ctx, int who, int action, double recent, int theirs) {
    const auto& w = specOf(ctx, who).weights;
    const auto& x = act(ctx, action);
    double bound = -w.wRecency * recent;
    if (ctx.combo) {
        bound += w.wCombo * static_cast<double>((*ctx.combo)[static_cast<std::size_t>(action) * static_cast<std::size_t>(ctx.comboN) +
                                                  static_cast<std::size_t>(theirs)]);
    }
    if (x.is(kAttack) && x.effector >= 0) bound += (x.is(kKick) ? w.wHitLong : w.wHitShort) * ctx.maxHitSpeed[static_cast<std::size_t>(action)];
    return bound;
}
double edgeBound(const Context& ctx, const GroupState& g, int who, int action) {
    return edgeBound(ctx, who, action, recency(ctx, g.c[static_cast<std::size_t>(who)], action),
                     g.c[static_cast<std::size_t>(1 - who)].action);
}
double withSlack(double bound) { return bound + 1e-6 * (1.0 + std::fabs(bound)); }

// Candidates in the order std::stable_sort would put them by descending key,
// where some keys are known at first only as upper bounds: the first in
// that order is the top of a heap (largest key, then first position), and a
// bound on top is replaced by its exact key before anything is taken. A
// bound is never below its key, so nothing is taken out of order, and only
// the keys that can come first are computed.
struct Pending {
    double key = 0;
    int pos = 0;
    bool bound = false;  // key is an upper bound: the exact one is not computed yet
};
// (Both parts always evaluated: no branch to mispredict inside the heap's loops.)
inline bool pendingBefore(const Pending& x, const Pending& y) {
    return static_cast<bool>(static_cast<unsigned>(x.key > y.key) | (static_cast<unsigned>(x.key == y.key) & static_cast<unsigned>(x.pos < y.pos)));
}
// std heap order: the top is the element no other comes before (a function
// object, so the heap's comparisons inline).
struct HeapLess {
    bool operator()(const Pending& x, const Pending& y) const { return pendingBefore(y, x); }
};
inline constexpr HeapLess heapLess{};

// A node's state compared and hashed bit for bit (the same bits, the same
// node: every rule of the search is a function of the state).
bool sameBits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool sameBits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
bool sameState(const GroupState& x, const GroupState& y) {
    if (x.n != y.n || !sameBits(x.time, y.time)) return false;
    for (int i = 0; i < x.n; ++i) {
        const auto& a = x.c[static_cast<std::size_t>(i)];
        const auto& b = y.c[static_cast<std::size_t>(i)];
        if (a.action != b.action || !sameBits(a.start, b.start) || !sameBits(a.offset, b.offset) || !sameBits(a.end, b.end) ||
            !sameBits(a.root.pos.x, b.root.pos.x) || !sameBits(a.root.pos.y, b.root.pos.y) ||
            !sameBits(a.root.heading, b.root.heading) || a.checkpoint != b.checkpoint || a.attackDone != b.attackDone ||
            a.caught != b.caught || a.reacting != b.reacting || a.recent != b.recent || a.recentCount != b.recentCount) {
            return false;
        }
    }
    return true;
}
struct StateHash {
    static std::uint64_t mix(std::uint64_t h, std::uint64_t x) { return (h ^ (x + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2))) * 0x100000001b3ull; }
    std::size_t operator()(const GroupState& g) const {
        std::uint64_t h = mix(static_cast<std::uint64_t>(g.n), std::bit_cast<std::uint64_t>(g.time));
        for (int i = 0; i < g.n; ++i) {
            const auto& c = g.c[static_cast<std::size_t>(i)];
            h = mix(h, static_cast<std::uint64_t>(c.action));
            h = mix(h, std::bit_cast<std::uint64_t>(c.start));
            h = mix(h, std::bit_cast<std::uint64_t>(c.offset));
            h = mix(h, std::bit_cast<std::uint64_t>(c.root.heading));
            h = mix(h, (static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(c.root.pos.x)) << 32) |
                           std::bit_cast<std::uint32_t>(c.root.pos.y));
            h = mix(h, static_cast<std::uint64_t>(static_cast<std::uint16_t>(c.recent[0])) |
                           (static_cast<std::uint64_t>(static_cast<std::uint16_t>(c.recent[1])) << 16));
        }
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

// Doubles an open-addressing table (linear probing; a slot with index 0 is
// empty; at least `least` slots, a power of two) and puts its slots back by
// their hash.
template <class Slot>
void growSlots(std::vector<Slot>& slots, std::size_t least) {
    std::vector<Slot> old(std::max(least, 2 * slots.size()));
    old.swap(slots);
    const std::size_t mask = slots.size() - 1;
    for (const Slot& s : old) {
        if (s.index == 0) continue;
        std::size_t i = static_cast<std::size_t>(s.hash) & mask;
        while (slots[i].index != 0) i = (i + 1) & mask;
        slots[i] = s;
    }
}

// What a bounded frontier node (boundedFrontier) found, for when the search
// meets the same state again in this decision (different actions that end
// in the same blow lead to the same node; about 40 % of the demo duel's
// frontier visits): its candidates in key order as far as it went, each
// with its key, whether it passed pruning and its edge score. A later visit
// replays the loop over them with its own path sum and window, and runs the
// node afresh when it needs a candidate the first visit did not reach.
struct FrontierStep {
    double key = 0;
    Value e;                // the edge score (when examined and legal)
    bool examined = false;  // false: only its key is known (the first visit stopped at it)
    bool legal = false;
};
struct FrontierMemo {
    struct Entry {
        std::uint32_t begin = 0, count = 0;
        bool complete = false;  // every candidate is in the steps
    };
    // An open-addressing table (linear probing, power-of-two size, at most
    // half full) of slots holding a state's full hash and its place in
    // states/entries: a miss usually costs one slot, a hit one state compare.
    struct Slot {
        std::uint64_t hash = 0;
        std::uint32_t index = 0;  // 1 + the place in states and entries; 0: empty
    };
    std::vector<Slot> slots;
    std::vector<GroupState> states;
    std::vector<Entry> entries;
    std::vector<FrontierStep> steps;

    static std::uint64_t hashOf(const GroupState& g) {
        // StateHash's value with its bits spread to the low ones the table indexes by.
        std::uint64_t x = static_cast<std::uint64_t>(StateHash{}(g));
        x = (x ^ (x >> 33)) * 0xff51afd7ed558ccdull;
        return x ^ (x >> 33);
    }
    // The entry of g, or null.
    const Entry* find(const GroupState& g, std::uint64_t h) const {
        if (slots.empty()) return nullptr;
        const std::size_t mask = slots.size() - 1;
        for (std::size_t i = static_cast<std::size_t>(h) & mask;; i = (i + 1) & mask) {
            const Slot& s = slots[i];
            if (s.index == 0) return nullptr;
            if (s.hash == h && sameState(states[s.index - 1], g)) return &entries[s.index - 1];
        }
    }
    // The entry of g, added (empty) when new.
    Entry& at(const GroupState& g, std::uint64_t h) {
        if (2 * (states.size() + 1) > slots.size()) grow();
        const std::size_t mask = slots.size() - 1;
        for (std::size_t i = static_cast<std::size_t>(h) & mask;; i = (i + 1) & mask) {
            Slot& s = slots[i];
            if (s.index == 0) {
                states.push_back(g);
                entries.emplace_back();
                s = {h, static_cast<std::uint32_t>(states.size())};
                return entries.back();
            }
            if (s.hash == h && sameState(states[s.index - 1], g)) return entries[s.index - 1];
        }
    }

    // Empty, keeping the storage (the table's slots emptied).
    void clear() {
        std::fill(slots.begin(), slots.end(), Slot{});
        states.clear();
        entries.clear();
        steps.clear();
    }

private:
    void grow() { growSlots(slots, 1024); }
};

// Storage one search reuses from node to node (no allocation per node once
// warm): per remaining depth the inner node's children and their order, the
// opponent's placed bodies of its pruner; a frontier's keys and child.
// A bounded frontier's first keys are its candidates' bounds (edgeBound),
// which are, but for the recency term, functions of the candidate list, the
// opponent's action and whether the opponent can still land a blow. For each
// such triple met, the keys with no recency term in the frontier's order
// (key descending, then position), and the list's positions by name; a node
// then needs the keys of the few candidates whose names are recent.
struct StaticKeys {
    std::vector<Pending> order;                        // keys without recency, first in order first
    std::vector<std::pair<std::int16_t, int>> byName;  // (Context::nameId, position), ascending
};
class StaticKeyTable {
public:
    // The keys of `list`, a member's list of `who`, against their action `theirs`.
    const StaticKeys& of(const Context& ctx, const std::vector<int>& list, int who, int theirs, bool oppCanHit) {
        std::uint64_t h = static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(&list)) * 0x9e3779b97f4a7c15ull;
        h ^= (static_cast<std::uint64_t>(static_cast<std::uint32_t>(theirs)) << 1 | (oppCanHit ? 1u : 0u)) * 0xff51afd7ed558ccdull;
        h ^= h >> 32;
        if (2 * (keys_.size() + 1) > slots_.size()) grow();
        const std::size_t mask = slots_.size() - 1;
        for (std::size_t i = static_cast<std::size_t>(h) & mask;; i = (i + 1) & mask) {
            Slot& s = slots_[i];
            if (s.index == 0) {
                s = {&list, theirs, oppCanHit, static_cast<std::uint32_t>(keys_.size() + 1), h};
                build(ctx, list, who, theirs, oppCanHit, keys_.emplace_back());
                return keys_.back();
            }
            if (s.hash == h && s.list == &list && s.theirs == theirs && s.oppCanHit == oppCanHit) return keys_[s.index - 1];
        }
    }

private:
    // An open-addressing table (linear probing, at most half full) of the
    // lists met; the keys in a deque (they stay where they are).
    struct Slot {
        const std::vector<int>* list = nullptr;
        int theirs = 0;
        bool oppCanHit = false;
        std::uint32_t index = 0;  // 1 + the place in keys_; 0: empty
        std::uint64_t hash = 0;
    };
    void grow() { growSlots(slots_, 256); }
    static void build(const Context& ctx, const std::vector<int>& list, int who, int theirs, bool oppCanHit, StaticKeys& out) {
        out.order.resize(list.size());
        out.byName.resize(list.size());
        for (std::size_t i = 0; i < list.size(); ++i) {
            const int a = list[i];
            const auto& x = act(ctx, a);
            const bool exactKey = !(x.is(kAttack) && x.effector >= 0) && !oppCanHit;
            // As the frontier computes a key whose recency is 0.
            const double bound = edgeBound(ctx, who, a, 0.0, theirs);
            out.order[i] = {exactKey ? withSlack(bound) : bound, static_cast<int>(i), exactKey};
            out.byName[i] = {static_cast<std::int16_t>(ctx.nameId[static_cast<std::size_t>(a)]), static_cast<int>(i)};
        }
        std::sort(out.order.begin(), out.order.end(), pendingBefore);
        std::sort(out.byName.begin(), out.byName.end());
    }
    std::vector<Slot> slots_;
    std::deque<StaticKeys> keys_;
};

struct SearchScratch {
    std::vector<std::vector<Child>> children;
    std::vector<std::vector<Pending>> pending;
    std::vector<std::vector<OpponentBody>> bodies;
    Child child;
    FrontierMemo frontier;
    StaticKeyTable staticKeys;
    BodyCache bodyCache;
    std::vector<std::uint32_t> recentAt;  // per list position: the node number while its name is recent
    std::uint32_t node = 0;
    void reserveDepth(int depth) {
        const auto n = static_cast<std::size_t>(std::max(depth, 1)) + 1;
        if (children.size() < n) children.resize(n), pending.resize(n), bodies.resize(n);
    }
};

// A frontier node of a duel scored by blows (Context::boundedFrontier), under
// alpha-beta. The chooser maximises its own edge score e, so each candidate
// gets a cheap key first: e itself when nothing can land in the interval
// (neither a blow of its own nor one of the opponent's: the edge is the
// launch and the movement, no hit search), else an upper bound (movement at
// most 0, the fastest blow its effector can land, nothing received).
// Candidates are then taken best key first: a key no better than the best
// edge found cannot win, so it and the rest are skipped without their
// pruning tests. Once the best found is outside the window (at most alpha
// at a max node, at least beta at a min node), a key that cannot bring it
// back in ends the node too, with that key as its fail-soft bound. Only the
// value changes with the order (the fail-soft bound of a cutoff or of a
// node outside the window), never an exact minimax value inside the window,
// so root choices are those of the plain frontier. Returns nothing when no candidate passes every
// criterion (the caller then applies the full rule with its fallbacks).
std::optional<Value> boundedFrontier(const Context& ctx, const GroupState& g, int who, bool mx, const Pruner& pruner,
                                     double alpha, double beta, const Value& acc, Stats& stats, PlacementMemo& oppAt,
                                     SearchScratch& scratch) {
    const int opp = 1 - who;
    const auto& o = g.c[static_cast<std::size_t>(opp)];
    const auto& oa = act(ctx, o.action);
    const bool oppCanHit = oa.is(kAttack) && oa.effector >= 0 && !o.attackDone &&
                           o.start + oa.activeEnd / kSampleRate - o.offset >= g.time;
    FrontierMemo& memo = scratch.frontier;
    // The value of an examined legal step, as the loop below computes it.
    auto stepValue = [&](const FrontierStep& st) {
        return Value{acc.comp + (mx ? st.e.comp : -st.e.comp), acc.coop + st.e.coop};
    };
    const std::uint64_t stateHash = ctx.opt->reuseNodes ? FrontierMemo::hashOf(g) : 0;
    if (const FrontierMemo::Entry* found = ctx.opt->reuseNodes ? memo.find(g, stateHash) : nullptr) {
        // Replay: the same candidates in the same order with this visit's
        // path sum and window; the same counts as running the node again.
        Value best;
        bool have = false;
        bool done = false;
        std::int64_t leaves = 0, cutoffs = 0;
        const auto& entry = *found;
        std::uint32_t i = 0;
        for (; i < entry.count && !done; ++i) {
            const FrontierStep& st = memo.steps[entry.begin + i];
            if (have && (mx ? acc.comp + st.key <= best.comp : acc.comp - st.key >= best.comp)) {
                done = true;
                break;
            }
            if (have && (mx ? acc.comp + st.key <= alpha : acc.comp - st.key >= beta)) {
                best.comp = mx ? acc.comp + st.key : acc.comp - st.key;  // as the run below stops
                done = true;
                break;
            }
            if (!st.examined) break;  // the first visit did not get this far
            if (!st.legal) continue;
            ++leaves;
            const Value v = stepValue(st);
            if (!have || better(mx, v, best)) best = v, have = true;
            if (mx ? best.comp >= beta : best.comp <= alpha) {
                ++cutoffs;
                done = true;
            }
        }
        if (done || (i == entry.count && entry.complete)) {
            stats.leaves += leaves;
            stats.cutoffs += cutoffs;
            if (!have) return std::nullopt;
            return best;
        }
        // Otherwise the node runs again below (and records further).
    }
    const auto recordBegin = static_cast<std::uint32_t>(memo.steps.size());
    // Keys: the edge score itself when nothing can land (computed only when
    // it may come first: its bound until then), else the bound (final).
    // When the candidates are a member's list, the keys without recency come
    // in order from the StaticKeyTable and the heap holds only the recent
    // candidates' keys and the exact keys; otherwise the heap holds every key.
    // Either way the next key is the first of all pending ones in the order.
    std::vector<Pending>& keys = scratch.pending[0];
    const auto& base = pruner.base();
    const StaticKeys* fixed = nullptr;
    std::size_t next = 0;  // the next of fixed->order
    const std::uint32_t node = ++scratch.node;
    if (const auto* list = pruner.memberList()) {
        fixed = &scratch.staticKeys.of(ctx, *list, who, o.action, oppCanHit);
        if (scratch.recentAt.size() < base.size()) scratch.recentAt.resize(base.size(), 0);
        if (node == 0) std::fill(scratch.recentAt.begin(), scratch.recentAt.end(), 0u), scratch.node = 1;
        const std::uint32_t mark = scratch.node;
        keys.clear();
        const auto& me = g.c[static_cast<std::size_t>(who)];
        for (int r = 0; r < me.recentCount; ++r) {
            const std::int16_t name = me.recent[static_cast<std::size_t>(r)];
            if (std::find(me.recent.begin(), me.recent.begin() + r, name) != me.recent.begin() + r) continue;
            auto it = std::lower_bound(fixed->byName.begin(), fixed->byName.end(), std::pair<std::int16_t, int>{name, 0});
            for (; it != fixed->byName.end() && it->first == name; ++it) {
                const int pos = it->second;
                const int a = base[static_cast<std::size_t>(pos)];
                const auto& x = act(ctx, a);
                const bool exactKey = !(x.is(kAttack) && x.effector >= 0) && !oppCanHit;
                const double bound = edgeBound(ctx, g, who, a);
                keys.push_back({exactKey ? withSlack(bound) : bound, pos, exactKey});
                scratch.recentAt[static_cast<std::size_t>(pos)] = mark;
            }
        }
    } else {
        keys.resize(base.size());  // (written in place: no growth check per key)
        for (std::size_t i = 0; i < base.size(); ++i) {
            const int a = base[i];
            const auto& x = act(ctx, a);
            const bool attack = x.is(kAttack) && x.effector >= 0;
            const bool exactKey = !attack && !oppCanHit;
            const double bound = edgeBound(ctx, g, who, a);
            keys[i] = {exactKey ? withSlack(bound) : bound, static_cast<int>(i), exactKey};
        }
    }
    std::make_heap(keys.begin(), keys.end(), heapLess);
    const std::uint32_t mark = scratch.node;
    // The static keys still pending, past those of recent candidates.
    auto fixedLeft = [&] {
        if (!fixed) return false;
        while (next < fixed->order.size() && scratch.recentAt[static_cast<std::size_t>(fixed->order[next].pos)] == mark) ++next;
        return next < fixed->order.size();
    };
    Value best;
    bool have = false;
    Child& ch = scratch.child;
    for (;;) {
        Pending k;
        if (fixedLeft() && (keys.empty() || pendingBefore(fixed->order[next], keys.front()))) {
            k = fixed->order[next++];
        } else if (!keys.empty()) {
            std::pop_heap(keys.begin(), keys.end(), heapLess);
            k = keys.back();
            keys.pop_back();
        } else {
            break;
        }
        const int action = base[static_cast<std::size_t>(k.pos)];
        if (k.bound) {
            // Only the exact key needs the launched state.
            // (No checkpoints to update: alpha-beta runs without cooperative terms.)
            GroupState after = g;
            launch(ctx, after, who, action, g.time);
            after.time = std::min(after.c[0].end, after.c[1].end);
            keys.push_back({edgeScore(ctx, g, after, who, action, Events{}, oppAt).comp, k.pos, false});
            std::push_heap(keys.begin(), keys.end(), heapLess);
            continue;
        }
        const bool exact = !(act(ctx, action).is(kAttack) && act(ctx, action).effector >= 0) && !oppCanHit;
        FrontierStep& step = memo.steps.emplace_back();
        step.key = k.key;
        if (have && (mx ? acc.comp + k.key <= best.comp : acc.comp - k.key >= best.comp)) break;
        // Outside the window already (best at most alpha, here at a max node)
        // and no remaining key can bring it back in: the node fails low with
        // the remaining keys' bound as its fail-soft value (an upper bound).
        if (have && (mx ? acc.comp + k.key <= alpha : acc.comp - k.key >= beta)) {
            best.comp = mx ? acc.comp + k.key : acc.comp - k.key;
            break;
        }
        step.examined = true;
        if (!pruner.cheapCriteria(action) || !pruner.penetrationFree(action, false)) continue;
        step.legal = true;
        ++stats.leaves;
        Value v;
        if (exact) {
            v.comp = mx ? acc.comp + k.key : acc.comp - k.key;
            v.coop = acc.coop;
            step.e = {k.key, 0.0};
        } else {
            makeChild(ctx, g, who, action, acc, mx, ch, oppAt);
            v = ch.acc;
            step.e = ch.edge;
        }
        if (!have || better(mx, v, best)) best = v, have = true;
        if (mx ? best.comp >= beta : best.comp <= alpha) {
            ++stats.cutoffs;
            break;
        }
    }
    if (!ctx.opt->reuseNodes) {
        memo.steps.clear();
        if (!have) return std::nullopt;
        return best;
    }
    auto& entry = memo.at(g, stateHash);
    entry.begin = recordBegin;
    entry.count = static_cast<std::uint32_t>(memo.steps.size()) - recordBegin;
    entry.complete = keys.empty() && !fixedLeft();
    if (!have) return std::nullopt;
    return best;
}

// Min-max over the next `depth` decisions. With alpha-beta (competitive
// scenes only: the cooperative back-up rules are not zero-sum) the window
// [alpha, beta] bounds S_comp; the frontier is evaluated lazily so a cutoff
// saves the remaining edges, and inner nodes try their children in the order
// of their immediate scores.
Value search(const Context& ctx, const GroupState& g, int depth, double alpha, double beta, const Value& acc,
             int rootSide, Stats& stats, SearchScratch& scratch) {
    ++stats.nodes;
    if (stats.leaves > stats.budget) {
        stats.exhausted = true;
        return acc;
    }
    const int who = chooserOf(g);
    const bool mx = isMax(ctx, who, rootSide);
    const bool ab = ctx.opt->alphaBeta && !ctx.cooperative;
    const auto level = static_cast<std::size_t>(std::max(depth, 1));
    // (The table of placed bodies only where the storage outlives the decision.)
    const Pruner pruner(ctx, g, who, false, &scratch.bodies[level], ctx.memory ? &scratch.bodyCache : nullptr);
    PlacementMemo oppAt;
    if (depth <= 1) {
        if (ab && ctx.boundedFrontier && pruner.active()) {
            if (auto v = boundedFrontier(ctx, g, who, mx, pruner, alpha, beta, acc, stats, oppAt, scratch)) return *v;
        }
        // Frontier: when some action passes every criterion, the pruned set
        // is exactly those actions, so each is tested only when reached and a
        // cutoff skips the rest. Otherwise the full rule with its fallbacks.
        Child& ch = scratch.child;
        Value best;
        bool have = false;
        auto visit = [&](int a) {
            makeChild(ctx, g, who, a, acc, mx, ch, oppAt);
            ++stats.leaves;
            if (!have || better(mx, ch.acc, best)) best = ch.acc, have = true;
            if (ab && (mx ? best.comp >= beta : best.comp <= alpha)) {
                ++stats.cutoffs;
                return false;
            }
            return true;
        };
        if (pruner.active()) {
            for (int a : pruner.base()) {
                if (!pruner.cheapCriteria(a) || !pruner.penetrationFree(a, false)) continue;
                if (!visit(a)) return best;
            }
            if (have) return best;
        }
        std::vector<int> cands;
        Stats ignored;
        pruner.prune(cands, ignored);
        for (int a : cands) {
            if (!visit(a)) break;
        }
        return have ? best : acc;
    }
    // Inner node: children in the order of their immediate scores. Under
    // alpha-beta a cutoff skips the rest, so when some action passes every
    // criterion (the pruned set is then exactly those) the penetration test
    // waits until a child is reached; otherwise the full rule.
    std::vector<Child>& children = scratch.children[level];
    std::vector<Pending>& pending = scratch.pending[level];
    Value best;
    bool have = false;
    // Searches one child; false on a cutoff.
    auto visit = [&](const Child& c) {
        const Value v = search(ctx, c.state, depth - 1, alpha, beta, c.acc, rootSide, stats, scratch);
        if (!have || better(mx, v, best)) best = v, have = true;
        if (ab) {
            if (mx) alpha = std::max(alpha, v.comp);
            else beta = std::min(beta, v.comp);
            if (alpha >= beta) {
                ++stats.cutoffs;
                return false;
            }
        }
        return true;
    };
    if (ab && pruner.active()) {
        // The children in the order of their immediate scores, made only
        // when they can come next: in a duel scored by blows each starts
        // with the bound of its order (edgeBound); otherwise all are made.
        children.clear();
        pending.clear();
        for (int a : pruner.base()) {
            if (!pruner.cheapCriteria(a)) continue;
            const int pos = static_cast<int>(children.size());
            Child& c = children.emplace_back();
            if (ctx.boundedFrontier) {
                // The order of makeChild with the bound for the edge score
                // (no cooperative terms under alpha-beta; the sums are
                // monotone in it, so this bounds the order).
                const double e = withSlack(edgeBound(ctx, g, who, a));
                const double comp = acc.comp + (mx ? e : -e);
                const double coop = acc.coop;
                c.action = a;
                pending.push_back({mx ? comp + coop : -(comp - coop), pos, true});
            } else {
                makeChild(ctx, g, who, a, acc, mx, c, oppAt);
                pending.push_back({c.order, pos, false});
            }
        }
        std::make_heap(pending.begin(), pending.end(), heapLess);
        while (!pending.empty()) {
            std::pop_heap(pending.begin(), pending.end(), heapLess);
            const Pending k = pending.back();
            Child& c = children[static_cast<std::size_t>(k.pos)];
            if (k.bound) {
                makeChild(ctx, g, who, c.action, acc, mx, c, oppAt);
                pending.back() = {c.order, k.pos, false};
                std::push_heap(pending.begin(), pending.end(), heapLess);
                continue;
            }
            pending.pop_back();
            if (!pruner.penetrationFree(c.action, false)) continue;
            if (!visit(c)) break;
        }
        if (have) return best;
    }
    std::vector<int> cands;
    Stats ignored;  // choices and pruning are counted at the real decisions
    pruner.prune(cands, ignored);
    if (cands.empty()) return acc;
    children.resize(cands.size());
    for (std::size_t i = 0; i < cands.size(); ++i) makeChild(ctx, g, who, cands[i], acc, mx, children[i], oppAt);
    std::stable_sort(children.begin(), children.end(), [](const Child& a, const Child& b) { return a.order > b.order; });
    for (const auto& c : children) {
        if (!visit(c)) break;
    }
    return have ? best : acc;
}

}  // namespace

// Context::memory: per thread, the searches' storage.
struct SearchMemory {
    tbb::enumerable_thread_specific<SearchScratch> threads;
};
std::shared_ptr<SearchMemory> makeSearchMemory() { return std::make_shared<SearchMemory>(); }

// The real choice of the character due at g.time. The first child (best by
// its immediate score) is searched with the full window; its value bounds
// the others, which then run in parallel with that fixed bound. A child that
// does not beat the bound cannot be chosen, one that does has an exact value:
// the choice is the same whatever the thread timing. With a root beam
// (SimOptions::rootBeam) the deepest pass searches only the children the
// pass before ranked best; which ones is fixed by that pass's values, so the
// choice is still the same whatever the thread timing.
int decide(const Context& ctx, const GroupState& g, int depth, Stats& stats, bool& fellBack, const CandidateFilter* filter) {
    const int who = chooserOf(g);
    const int rootSide = specOf(ctx, who).side;
    ++stats.nodes;
    std::vector<int> cands;
    fellBack = candidates(ctx, g, who, cands, stats);
    if (filter) (*filter)(cands);
    if (cands.empty()) return -1;
    if (cands.size() == 1) return cands[0];
    std::vector<Child> children(cands.size());
    PlacementMemo oppAt;
    for (std::size_t i = 0; i < cands.size(); ++i) makeChild(ctx, g, who, cands[i], Value{}, true, children[i], oppAt);
    if (depth <= 1) {
        stats.leaves += static_cast<std::int64_t>(children.size());
        std::size_t best = 0;
        for (std::size_t i = 1; i < children.size(); ++i) {
            if (better(true, children[i].acc, children[best].acc)) best = i;
        }
        return children[best].action;
    }
    std::stable_sort(children.begin(), children.end(), [](const Child& a, const Child& b) { return a.order > b.order; });
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const bool ab = ctx.opt->alphaBeta && !ctx.cooperative;
    // Iterative deepening under a leaf budget: when a deeper search would
    // visit too many leaves (long runs of one character's decisions, where
    // alpha-beta cannot cut), the last complete depth decides. Each root child
    // has its own share of the budget, so the outcome does not depend on
    // thread timing.
    const std::int64_t share = std::max<std::int64_t>(2000, ctx.opt->leafBudget / static_cast<std::int64_t>(children.size()));
    // Each deeper pass searches the children in the order of the last pass's
    // values, so the bound comes from the likely best child. The choice is
    // the same as in the immediate-score order: among the exact values the
    // best wins, ties going to the child first in that order; a child before
    // the bound's child in it is searched just below the bound, so a tie
    // with the bound is exact too.
    std::vector<std::size_t> order(children.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::size_t chosen = 0;
    // Root beam (SimOptions::rootBeam): the last pass searches only the
    // first `live` children of `order`, those the pass before ranked best.
    std::size_t live = children.size();
    const auto beam = static_cast<std::size_t>(std::max(ctx.opt->rootBeam, 0));
    // Not at depth 3: a 2-level pass ranks the children too poorly (the
    // depth-3 style matches lost their order with it).
    const bool beamed = ab && beam > 0 && depth >= 4;
    // Per thread, the searches' storage: the group's (Context::memory),
    // emptied, or this decision's own. Either way the frontier memo holds
    // only this decision's states.
    tbb::enumerable_thread_specific<SearchScratch> own;
    tbb::enumerable_thread_specific<SearchScratch>& scratch = ctx.memory ? ctx.memory->threads : own;
    for (auto& local : scratch) local.frontier.clear();
    for (int d = 2; d <= depth; ++d) {
        std::vector<Value> values(children.size());
        std::vector<double> floor(children.size(), -kInf);
        std::vector<Stats> childStats(children.size());
        for (auto& cs : childStats) cs.budget = share;
        const std::size_t first = order[0];
        auto& mine = scratch.local();
        mine.reserveDepth(d);
        values[first] = search(ctx, children[first].state, d - 1, -kInf, kInf, children[first].acc, rootSide, childStats[first], mine);
        const double alpha = ab ? values[first].comp : -kInf;
        for (std::size_t i = 0; i < children.size(); ++i) {
            if (ab && i != first) floor[i] = i < first ? std::nextafter(alpha, -kInf) : alpha;
        }
        auto run = [&](std::size_t k) {
            const std::size_t i = order[k];
            auto& local = scratch.local();
            local.reserveDepth(d);
            values[i] = search(ctx, children[i].state, d - 1, floor[i], kInf, children[i].acc, rootSide, childStats[i], local);
        };
        if (ctx.opt->parallel) {
            tbb::parallel_for(std::size_t{1}, live, run);
        } else {
            for (std::size_t k = 1; k < live; ++k) run(k);
        }
        std::vector<char> searched(children.size(), 0);
        for (std::size_t k = 0; k < live; ++k) searched[order[k]] = 1;
        bool exhausted = false;
        std::size_t best = first;
        for (std::size_t i = 0; i < children.size(); ++i) {
            if (!searched[i]) continue;
            stats.add(childStats[i]);
            exhausted = exhausted || childStats[i].exhausted;
            if (i == first) continue;
            if (ab && !(values[i].comp > floor[i])) continue;  // failed low: at most the bound
            if (better(true, values[i], values[best]) || (i < best && !better(true, values[best], values[i]))) best = i;
        }
        if (exhausted) {
            ++stats.shallower;
            break;
        }
        chosen = best;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
            return values[x].comp + values[x].coop > values[y].comp + values[y].coop;
        });
        // The chosen child first (a failed-low bound can equal its value).
        std::rotate(order.begin(), std::find(order.begin(), order.end(), chosen), std::find(order.begin(), order.end(), chosen) + 1);
        if (beamed && d + 1 == depth) {
            // Before the last pass: keep the `beam` best of this pass and
            // every child whose value (a failed-low child: its bound) equals
            // the chosen one's, which this pass cannot tell apart from it.
            const double top = values[chosen].comp;
            std::size_t keep = 0;
            while (keep < live && (keep < beam || values[order[keep]].comp >= top)) ++keep;
            live = keep;
        }
    }
    return children[chosen].action;
}

}  // namespace fray::sim::planner
