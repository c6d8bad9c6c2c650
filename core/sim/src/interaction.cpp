#include "interaction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace fray::sim::detail {

namespace {
constexpr float kHitReach = 2.2f;  // m, pelvis to pelvis: no blow lands from farther

// Earliest hit in [t0, t1] of att's attack on def; time < 0 if none.
HitCandidate findHit(const ActionLibrary& lib, const Playing& att, const Playing& def, double t0, double t1) {
    HitCandidate hit;
    const auto& a = lib.actions()[static_cast<std::size_t>(att.action)];
    const double ws = att.start + a.activeBegin / kSampleRate - att.offset;
    const double we = att.start + a.activeEnd / kSampleRate - att.offset;
    const double lo = std::max(ws, t0), hi = std::min(we, t1);
    if (lo > hi) return hit;
    if (glm::length(att.placement(lib, lo).pos - def.placement(lib, lo).pos) > kHitReach) return hit;
    const int sBegin = lib.sampleAt(att.action, att.clipTime(lo));
    const int sEnd = lib.sampleAt(att.action, att.clipTime(hi));
    // Kicks land with the shin or the foot.
    int effectors[2] = {a.effector, -1};
    if (a.effector == kLeftShin) effectors[1] = kLeftFoot;
    if (a.effector == kRightShin) effectors[1] = kRightFoot;
    // Both placements are fixed over the window: their rotations computed once.
    const FloorRotation attRotation(att.root.heading), defRotation(def.root.heading);
    for (int s = sBegin; s <= sEnd; ++s) {
        const double ts = std::max(att.start + s / kSampleRate - att.offset, t0);
        if (ts > t1) break;
        const Obb* ab = lib.boxesAt(att.action, s);
        const Obb* db = lib.boxesAt(def.action, lib.sampleAt(def.action, def.clipTime(ts)));
        for (int e : effectors) {
            if (e < 0) continue;
            // overlaps() in two steps: most pairs fail its bounding-sphere
            // test, which needs only the placed centres, so the boxes' axes
            // are placed for the pairs that pass it.
            const glm::vec3 effCentre = ab[e].placedCentre(att.root, attRotation);
            const float effRadius = ab[e].radius();
            std::optional<Obb> eff;
            for (int target : kTargetSegments) {
                const Obb& tb = db[target];
                const glm::vec3 gap = tb.placedCentre(def.root, defRotation) - effCentre;
                const float r = effRadius + tb.radius();
                if (glm::dot(gap, gap) > r * r) continue;
                if (!eff) eff = ab[e].placed(att.root, attRotation);
                if (!overlapsBeyondSpheres(*eff, tb.placed(def.root, defRotation))) continue;
                hit.time = ts;
                hit.target = target;
                hit.effector = e;
                hit.speed = lib.effectorSpeed()[static_cast<std::size_t>(a.sampleBegin + s)];
                const auto& d = lib.actions()[static_cast<std::size_t>(def.action)];
                hit.blocked = d.is(kBlock) && d.defended == target;
                return hit;
            }
        }
    }
    return hit;
}

}  // namespace

CoreBody::CoreBody(const ActionLibrary& lib, const BodyPose& pose, const FloorRotation& rotate, glm::vec2 clipPelvis,
                   float shrink)
    : lib_(&lib), pose_(pose), rotate_(rotate), shrink_(shrink), pelvis_(pose.root.pos + rotate_(clipPelvis)) {}

const std::array<Obb, kCoreSegments.size()>& CoreBody::boxes() const {
    if (!boxes_) {
        const Obb* local = lib_->boxesAt(pose_.action, lib_->sampleAt(pose_.action, pose_.tau));
        auto& placed = boxes_.emplace();
        for (std::size_t k = 0; k < kCoreSegments.size(); ++k) {
            placed[k] = local[kCoreSegments[k]].placed(pose_.root, rotate_).shrunk(shrink_);
            radii_[k] = placed[k].radius();
        }
    }
    return *boxes_;
}

CoreDiscs::CoreDiscs(const ActionLibrary& lib, float shrink) : lib_(&lib), shrink_(shrink) {
    first_.reserve(static_cast<std::size_t>(lib.size()));
    for (int a = 0; a < lib.size(); ++a) {
        first_.push_back(static_cast<int>(discs_.size()));
        const int n = lib.actions()[static_cast<std::size_t>(a)].sampleCount;
        for (int s = 0; s < n; ++s) {
            const Obb* local = lib.boxesAt(a, s);
            glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
            for (int seg : kCoreSegments) {
                const glm::vec2 c(local[seg].centre.x, local[seg].centre.z);
                lo = glm::min(lo, c), hi = glm::max(hi, c);
            }
            Disc d{0.5f * (lo + hi), 0.0f};
            for (int seg : kCoreSegments) {
                const glm::vec2 c(local[seg].centre.x, local[seg].centre.z);
                d.radius = std::max(d.radius, glm::length(c - d.centre) + local[seg].shrunk(shrink).radius());
            }
            discs_.push_back(d);
        }
    }
}

CoreSpheres::CoreSpheres(const ActionLibrary& lib, float shrink) {
    for (int a = 0; a < lib.size(); ++a) {
        first_.push_back(static_cast<int>(samples_.size()));
        const int n = lib.actions()[static_cast<std::size_t>(a)].sampleCount;
        for (int k = 0; k < n; ++k) {
            const Obb* local = lib.boxesAt(a, k);
            Local& sp = samples_.emplace_back();
            for (std::size_t i = 0; i < kCount; ++i) {
                const Obb& box = local[kCoreSegments[i]];
                sp.centre[i] = box.centre;
                sp.radius[i] = box.shrunk(shrink).radius();  // placing keeps the half extents
            }
        }
        Local& swept = swept_.emplace_back();
        const Local* of = samples_.data() + first_.back();
        for (std::size_t i = 0; i < kCount; ++i) {
            glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
            for (int k = 0; k < n; ++k) lo = glm::min(lo, of[k].centre[i]), hi = glm::max(hi, of[k].centre[i]);
            swept.centre[i] = n > 0 ? 0.5f * (lo + hi) : glm::vec3(0.0f);
            swept.radius[i] = 0;
            for (int k = 0; k < n; ++k) swept.radius[i] = std::max(swept.radius[i], glm::length(of[k].centre[i] - swept.centre[i]) + of[k].radius[i]);
            swept.radius[i] += 1e-3f;  // the rounding of the sum
        }
    }
}

bool coreBodiesOverlap(const CoreBody& a, const CoreBody& b, float pelvisReach) {
    const glm::vec2 d = a.pelvis() - b.pelvis();
    if (glm::dot(d, d) > pelvisReach * pelvisReach) return false;
    const auto& ab = a.boxes();
    const auto& bb = b.boxes();
    for (std::size_t i = 0; i < ab.size(); ++i) {
        for (std::size_t j = 0; j < bb.size(); ++j) {
            const glm::vec3 c = bb[j].centre - ab[i].centre;
            const float r = a.radii()[i] + b.radii()[j];
            if (glm::dot(c, c) <= r * r && overlapsBeyondSpheres(ab[i], bb[j])) return true;
        }
    }
    return false;
}

bool coreBodiesOverlap(const ActionLibrary& lib, const BodyPose& a, const BodyPose& b, float shrink, float pelvisReach) {
    return coreBodiesOverlap(CoreBody(lib, a, shrink), CoreBody(lib, b, shrink), pelvisReach);
}

double effectiveMass(int effector) {
    return (effector == kLeftForearm || effector == kRightForearm) ? 2.5 : 5.0;
}

glm::vec2 pushDirection(const RootXf& victim, const RootXf& attacker) {
    glm::vec2 push = victim.pos - attacker.pos;
    if (glm::dot(push, push) < 1e-8f) push = -headingVector(victim.heading);
    return rotateFloor(glm::normalize(push), -victim.heading);
}

void sortHits(std::vector<HitEvent>& hits) {
    std::sort(hits.begin(), hits.end(), [](const HitEvent& a, const HitEvent& b) {
        return a.time != b.time ? a.time < b.time : a.attacker < b.attacker;
    });
}

void cutIntoReaction(std::vector<ActionInstance>& track, double t, const ForcedReaction& reaction) {
    if (!track.empty()) track.back().end = t;
    track.push_back(reaction.instance(t));
}

std::pair<int, const std::vector<int>*> ReactionMemo::pool(const std::vector<int>& clips) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it = std::find(pools_.begin(), pools_.end(), clips);
    if (it != pools_.end()) return {static_cast<int>(it - pools_.begin()), &*it};
    pools_.push_back(clips);
    return {static_cast<int>(pools_.size()) - 1, &pools_.back()};
}

std::size_t ReactionMemo::Hash::operator()(const Key& k) const {
    std::uint64_t h = static_cast<std::uint32_t>(k.pool);
    for (const int x : {k.action, k.sample, k.sector * 2 + (k.strong ? 1 : 0)}) {
        h = (h ^ static_cast<std::uint32_t>(x)) * 0x100000001b3ull;
    }
    return static_cast<std::size_t>(h ^ (h >> 29));
}

InteractionEngine::InteractionEngine(const ActionLibrary& lib)
    : lib_(&lib), reactionDir_(static_cast<std::size_t>(lib.size()), glm::vec2(0.0f)),
      memo_(lib.reactionMemo_ ? lib.reactionMemo_ : std::make_shared<ReactionMemo>()) {
    for (int a = 0; a < lib.size(); ++a) {
        const auto& x = lib.action(a);
        if (!x.is(kReactive)) continue;
        const glm::vec2 d = lib.rootAt(a, std::min(0.5, x.duration)).pos;
        if (glm::length(d) > 0.05f) reactionDir_[static_cast<std::size_t>(a)] = glm::normalize(d);
    }
}

int InteractionEngine::addPool(const std::vector<int>& pool) {
    const auto [id, clips] = memo_->pool(pool);
    if (pools_.size() <= static_cast<std::size_t>(id)) pools_.resize(static_cast<std::size_t>(id) + 1, nullptr);
    pools_[static_cast<std::size_t>(id)] = clips;
    return id;
}

HitCandidate InteractionEngine::strike(const Playing& att, bool spent, const Playing& def, bool defReacting, double t0,
                                       double t1) const {
    const auto& a = lib_->actions()[static_cast<std::size_t>(att.action)];
    if (spent || defReacting || !a.is(kAttack) || a.effector < 0) return {};
    return findHit(*lib_, att, def, t0, t1);
}

ForcedReaction InteractionEngine::react(const Playing& victim, const RootXf& pusher, double t, bool strong, int poolId) const {
    const RootXf placed = victim.placement(*lib_, t);
    const auto [action, sample] = chooseReaction(victim, t, pushDirection(placed, pusher), strong, poolId);
    ForcedReaction r;
    if (action < 0) return r;
    r.action = action;
    r.offset = sample / kSampleRate;
    r.root = placed * lib_->rootAt(action, r.offset).inverse();
    r.end = t + std::max(lib_->actions()[static_cast<std::size_t>(action)].duration - r.offset, 1.0 / kSampleRate);
    return r;
}

std::pair<int, int> InteractionEngine::chooseReaction(const Playing& victim, double t, glm::vec2 pushLocal, bool strong,
                                                      int poolId) const {
    const ActionLibrary& lib = *lib_;
    // Quantised direction (8 sectors): the choice depends on the sector only,
    // so every input of it is in the key and a remembered choice is exact.
    const int sector = static_cast<int>(std::lround(angleOf(pushLocal) / (std::numbers::pi / 4))) & 7;
    const int sample = lib.sampleAt(victim.action, victim.clipTime(t));
    const ReactionMemo::Key key{poolId, victim.action, sample, sector, strong};
    auto& cache = memo_->table();
    if (auto it = cache.find(key); it != cache.end()) return it->second;

    const auto& pool = *pools_[static_cast<std::size_t>(poolId)];
    const double sectorAngle = sector * std::numbers::pi / 4;
    const glm::vec2 dir(static_cast<float>(std::sin(sectorAngle)), static_cast<float>(std::cos(sectorAngle)));
    const auto& a = lib.actions()[static_cast<std::size_t>(victim.action)];
    const auto& lm = lib.motion(a.motion);
    const prep::PoseFeature now = prep::poseFeature(lm.motion, lm.joints, lib.frameAt(victim.action, sample / kSampleRate));
    prep::PoseMatcher::Probe probe(now);
    std::pair<int, int> best{-1, 0};
    double bestCost = std::numeric_limits<double>::max();
    for (int pass = 0; pass < 2 && best.first < 0; ++pass) {
        for (std::size_t k = 0; k < lib.reactions().size(); ++k) {
            const auto& e = lib.reactions()[k];
            if (!std::binary_search(pool.begin(), pool.end(), e.action)) continue;
            const bool falls = lib.actions()[static_cast<std::size_t>(e.action)].is(kFalling);
            if (pass == 0 && falls != strong) continue;
            const glm::vec2 travel = reactionDir_[static_cast<std::size_t>(e.action)];
            const double dirCost = glm::dot(travel, travel) > 0 ? 0.5 * (1.0 - static_cast<double>(glm::dot(travel, dir))) : 0.25;
            if (const auto cost = lib.reactionPoses().distanceBelow(probe, k, dirCost, bestCost)) {
                bestCost = *cost, best = {e.action, e.sample};
            }
        }
    }
    cache.emplace(key, best);
    return best;
}

}  // namespace fray::sim::detail
