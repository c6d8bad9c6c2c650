#include "fray/sim/patches.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <mutex>
#include <numbers>

#include <tbb/parallel_for.h>

#include "patch_engine.h"
#include "patch_library_builder.h"

namespace fray::sim {

namespace {

using namespace patchgen;

// ---------------------------------------------------------------------------
// Evaluation (SPEC 4.2): contact, relative distance/orientation, timing.

struct Scores {
    double contact = 1, distance = 1, timing = 1;
};

Playing playingOf(const ActionInstance& i) { return {i.action, i.start, i.offset, i.root}; }

const ActionInstance* instanceAt(const std::vector<ActionInstance>& track, double t) {
    const int i = instanceIndexAt(track, t + 1e-9);
    return i < 0 ? nullptr : &track[static_cast<std::size_t>(i)];
}

RootXf placeAt(const ActionLibrary& lib, const std::vector<ActionInstance>& track, double t) {
    const auto* i = instanceAt(track, t);
    return playingOf(*i).placement(lib, std::min(t, i->end));
}

// The middle of a body's two hands (the far ends of its forearm boxes), where
// an item held in both hands is.
glm::vec3 handsAt(const ActionLibrary& lib, const ActionInstance& inst, double t) {
    const Playing p = playingOf(inst);
    const double at = std::min(t, inst.end);
    glm::vec3 sum(0.0f);
    for (int seg : {kLeftForearm, kRightForearm}) sum += segmentTip(p.box(lib, at, seg), seg);
    return 0.5f * sum;
}

// How close the hands of the two characters come while entry e (a receive)
// plays: the hand-over's contact.
double closestHands(const Engine& eng, const State& s, std::size_t e) {
    const auto& pe = eng.pattern.entries[e];
    const auto& mine = s.tracks[static_cast<std::size_t>(pe.character)];
    const auto& theirs = s.tracks[static_cast<std::size_t>(1 - pe.character)];
    const ActionInstance* recv = instanceAt(mine, s.entryStart[e]);
    double closest = std::numeric_limits<double>::max();
    if (recv == nullptr) return closest;
    for (double t = recv->start; t <= recv->end + 1e-9; t += 1.0 / kSampleRate) {
        const ActionInstance* other = instanceAt(theirs, t);
        if (other == nullptr) continue;
        closest = std::min(closest, static_cast<double>(glm::length(handsAt(eng.lib, *recv, t) - handsAt(eng.lib, *other, t))));
    }
    return closest;
}

Scores evaluate(const Engine& eng, const State& s) {
    const auto& lib = eng.lib;
    Scores sc;
    // Contact: every reactive entry was caused (the engine guarantees it);
    // every defence entry avoided an attack that came close.
    double sum = 0;
    int items = 0;
    for (std::size_t e = 0; e < eng.pattern.entries.size(); ++e) {
        const auto& pe = eng.pattern.entries[e];
        if (isResponse(eng.pattern, e)) {
            sum += 1, ++items;
            continue;
        }
        if (pe.annotation == "receive") {
            // A hand-over: the hands must meet.
            ++items;
            const double closest = closestHands(eng, s, e);
            sum += std::clamp((kHandsMeet + kHandsSlack - closest) / kHandsSlack, 0.0, 1.0);
            continue;
        }
        if (pe.annotation != "defence" && pe.annotation != "avoid" && pe.annotation != "dodge") continue;
        ++items;
        const auto& mine = s.tracks[static_cast<std::size_t>(pe.character)];
        const auto& theirs = s.tracks[static_cast<std::size_t>(1 - pe.character)];
        const double t0 = s.entryStart[e];
        const ActionInstance* def = instanceAt(mine, t0);
        double closest = std::numeric_limits<double>::max();
        for (const auto& att : theirs) {
            const auto& A = lib.actions()[static_cast<std::size_t>(att.action)];
            if (!A.is(kAttack) || A.effector < 0) continue;
            for (int smp = A.activeBegin; smp < A.activeEnd; ++smp) {
                const double t = att.start + smp / kSampleRate - att.offset;
                if (t < def->start || t > def->end || t > att.end) continue;
                const glm::vec3 eff = lib.boxesAt(att.action, smp)[A.effector].placed(att.root).centre;
                for (int target : {kHead, kTorso}) {
                    const glm::vec3 c = playingOf(*def).box(lib, t, target).centre;
                    closest = std::min(closest, static_cast<double>(glm::length(eff - c)));
                }
            }
        }
        sum += std::clamp((kNearMiss + 0.35 - closest) / 0.35, 0.0, 1.0);
    }
    if (items > 0) sc.contact = sum / items;

    // Distance and orientation while both are on their feet, 10 Hz.
    double end = 0;
    for (const auto& t : s.tracks) end = std::max(end, t.back().end);
    double dsum = 0;
    int n = 0;
    for (double t = 0; t <= end; t += 0.1) {
        const RootXf p = placeAt(lib, s.tracks[0], t), q = placeAt(lib, s.tracks[1], t);
        const glm::vec2 d = q.pos - p.pos;
        const double r = glm::length(d);
        const double g = r > 1.5 ? std::exp(-(r - 1.5) * (r - 1.5) / 0.25) : r < 0.4 ? r / 0.4 : 1.0;
        double face = 0;
        int k = 0;
        for (int c = 0; c < 2; ++c) {
            const auto* inst = instanceAt(s.tracks[static_cast<std::size_t>(c)], t);
            if (inst->forced) continue;
            const RootXf me = c == 0 ? p : q;
            const glm::vec2 to = c == 0 ? d : -d;
            face += 0.5 * (1.0 + std::cos(r > 1e-6 ? wrapAngle(angleOf(to) - me.heading) : 0.0)), ++k;
        }
        dsum += k > 0 ? 0.5 * g + 0.5 * face / k : g;
        ++n;
    }
    if (n > 0) sc.distance = dsum / n;

    // Timing: consecutive entries of different characters start close together.
    double tsum = 0;
    int m = 0;
    for (std::size_t e = 1; e < eng.pattern.entries.size(); ++e) {
        if (eng.pattern.entries[e].character == eng.pattern.entries[e - 1].character) continue;
        const double gap = s.entryStart[e] - s.entryStart[e - 1];
        const double over = std::max(0.0, gap - 0.5);
        tsum += std::exp(-over * over / 0.25), ++m;
    }
    if (m > 0) sc.timing = tsum / m;
    return sc;
}

void fillSwept(const ActionLibrary& lib, Patch& p) {
    for (int c = 0; c < 2; ++c) {
        auto& out = p.swept[static_cast<std::size_t>(c)];
        const auto& track = p.tracks[static_cast<std::size_t>(c)];
        const int slices = std::max(1, static_cast<int>(std::ceil(p.duration / kSweptSlice)));
        out.assign(static_cast<std::size_t>(slices), SweptBox{});
        for (int k = 0; k < slices; ++k) {
            SweptBox box = SweptBox::empty();
            for (int j = 0; j <= 3; ++j) {
                const double t = std::min((k + j / 3.0) * kSweptSlice, p.duration);
                const auto* inst = instanceAt(track, t);
                const Playing pl = playingOf(*inst);
                const double tt = std::min(t, inst->end);
                for (int seg = 0; seg < kSegmentCount; ++seg) box.add(floorBox(pl.box(lib, tt, seg)));
            }
            out[static_cast<std::size_t>(k)] = box;
        }
    }
}

Patch makePatch(const Engine& eng, const State& s, int patternIndex, const PatchConfig& ic, const Scores& sc, double score) {
    Patch p;
    p.pattern = patternIndex;
    p.tracks = s.tracks;
    p.hits = s.hits;
    p.initial = ic;
    p.contact = sc.contact, p.distance = sc.distance, p.timing = sc.timing;
    p.score = score;
    for (const auto& t : p.tracks) p.duration = std::max(p.duration, t.back().end);
    const RootXf e0 = p.endPlacement(eng.lib, 0), e1 = p.endPlacement(eng.lib, 1);
    p.final = configOf(e0, e1);
    fillSwept(eng.lib, p);
    return p;
}

State initialState(const PatchConfig& ic) {
    State s;
    const auto places = placeConfig(ic);
    for (int c = 0; c < 2; ++c) {
        auto& x = s.a[static_cast<std::size_t>(c)];
        x.cur.root = places[static_cast<std::size_t>(c)];
    }
    return s;
}

// Starts both characters: character 1 its first entry at 0 (a choice),
// character 2 its first entry at the delay, or a hold when that entry is a reaction.
struct Expansion {
    const Engine& eng;
    int patternIndex;
    PatchConfig ic;
    GenerateStats stats;
    std::vector<Patch> kept;

    void finish(const State& s, Verdict v) {
        ++stats.paths;
        switch (v) {
            case Verdict::TooClose: ++stats.tooClose; return;
            case Verdict::WrongOrder: ++stats.wrongOrder; return;
            case Verdict::UnintendedHit: ++stats.unintendedHit; return;
            case Verdict::MissedContact: ++stats.missedContact; return;
            case Verdict::Ok: break;
        }
        for (std::size_t e = 0; e < eng.pattern.entries.size(); ++e) {
            if (!s.started[e]) {
                ++stats.missedContact;
                return;
            }
        }
        // A hand-over whose hands never come within reach passes nothing.
        for (std::size_t e = 0; e < eng.pattern.entries.size(); ++e) {
            if (eng.pattern.entries[e].annotation == "receive" && closestHands(eng, s, e) > kHandsReach) {
                ++stats.missedContact;
                return;
            }
        }
        const Scores sc = evaluate(eng, s);
        const auto& w = eng.pattern.weights;
        const double total = w.contact + w.distance + w.timing;
        const double score = (w.contact * sc.contact + w.distance * sc.distance + w.timing * sc.timing) / total;
        if (score < eng.pattern.threshold) {
            ++stats.belowThreshold;
            return;
        }
        kept.push_back(makePatch(eng, s, patternIndex, ic, sc, score));
    }

    // Continues from a state where character `who` must choose for its pending entry.
    void expand(const State& s, int who) {
        const int e = eng.pendingEntry(s.a[static_cast<std::size_t>(who)], who);
        std::vector<int> cands;
        eng.candidates(s, who, e, cands);
        if (cands.empty()) {
            ++stats.paths, ++stats.missedContact;
            return;
        }
        for (int a : cands) {
            State next = s;
            const bool first = next.a[static_cast<std::size_t>(who)].last < 0;
            eng.launch(next, who, a, e, next.time, first);
            run(std::move(next));
        }
    }

    void run(State s) {
        Verdict v = Verdict::Ok;
        const int who = eng.advance(s, v);
        if (who >= 0) return expand(s, who);
        finish(s, v);
    }

    void start() {
        State s = initialState(ic);
        const int e1 = eng.entriesOf[1].front();
        const bool reactiveFirst = isResponse(eng.pattern, static_cast<std::size_t>(e1));
        // Character 2 first: a hold from 0, or its first action at the delay
        // (a placeholder until then: the first sample of that action). When
        // its first entry follows another of character 1's than the first, it
        // waits in a guard until that entry starts, then the delay.
        const int e0first = eng.entriesOf[0].front();
        const bool deferred = !reactiveFirst && e1 - 1 != e0first;
        if (reactiveFirst || deferred) {
            if (eng.hold < 0) {
                ++stats.paths, ++stats.missedContact;
                return;
            }
            eng.launch(s, 1, deferred ? eng.holdBefore[static_cast<std::size_t>(e1)] : eng.hold, -1, 0.0, true);
            if (deferred) s.a[1].waitFor = e1 - 1, s.a[1].waitDelay = ic.delay;
        }
        // Character 1 chooses its first action at time 0.
        const int e0 = eng.entriesOf[0].front();
        std::vector<int> c0;
        eng.candidates(s, 0, e0, c0);
        if (c0.empty()) {
            ++stats.paths, ++stats.missedContact;
            return;
        }
        for (int a0 : c0) {
            State s0 = s;
            eng.launch(s0, 0, a0, e0, 0.0, true);
            if (reactiveFirst || deferred) {
                run(std::move(s0));
                continue;
            }
            std::vector<int> c1;
            s0.time = ic.delay;
            eng.candidates(s0, 1, e1, c1);
            s0.time = 0;
            for (int a1 : c1) {
                State s1 = s0;
                eng.launch(s1, 1, a1, e1, ic.delay, true);
                if (!eng.orderOk(s1, e1)) {
                    ++stats.paths, ++stats.wrongOrder;
                    continue;
                }
                run(std::move(s1));
            }
        }
    }
};

// Keeps the best keepPerPath patches of every distinct action sequence (by
// label), in generation order otherwise.
void keepBestPerPath(const ActionLibrary& lib, std::vector<Patch>& patches, int keepPerPath, bool spread, PatchLibrary::Data& out) {
    std::map<std::string, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < patches.size(); ++i) {
        std::string key;
        for (const auto& t : patches[i].tracks) {
            for (const auto& inst : t) key += lib.actions()[static_cast<std::size_t>(inst.action)].label() + (inst.forced ? "!" : "") + ",";
            key += "|";
        }
        groups[key].push_back(i);
    }
    std::vector<char> keep(patches.size(), keepPerPath <= 0 ? 1 : 0);
    if (keepPerPath > 0) {
        for (auto& [key, members] : groups) {
            std::stable_sort(members.begin(), members.end(),
                             [&](std::size_t a, std::size_t b) { return patches[a].score > patches[b].score; });
            const auto want = static_cast<std::size_t>(keepPerPath);
            if (!spread || members.size() <= want) {
                for (std::size_t k = 0; k < members.size() && k < want; ++k) keep[members[k]] = 1;
                continue;
            }
            // Farthest first among the near-best, from the best one on.
            std::vector<std::size_t> pool;
            for (std::size_t m : members) {
                if (patches[m].score >= patches[members.front()].score - 0.02) pool.push_back(m);
            }
            auto apart = [&](std::size_t a, std::size_t b) {
                const PatchConfig& x = patches[a].initial;
                const PatchConfig& y = patches[b].initial;
                const double dd = (x.delay - y.delay) / 0.3;
                return configDistance(x, y) + dd * dd;
            };
            std::vector<double> nearest(pool.size(), std::numeric_limits<double>::max());
            std::size_t pick = 0, kept = 0;
            while (kept < want && kept < pool.size()) {
                keep[pool[pick]] = 1;
                ++kept;
                nearest[pick] = -1;
                std::size_t next = pool.size();
                for (std::size_t q = 0; q < pool.size(); ++q) {
                    if (nearest[q] < 0) continue;
                    nearest[q] = std::min(nearest[q], apart(pool[q], pool[pick]));
                    if (next == pool.size() || nearest[q] > nearest[next]) next = q;
                }
                if (next == pool.size()) break;
                pick = next;
            }
            // Fewer near-best than asked for: the best of the rest.
            for (std::size_t m : members) {
                if (kept >= want) break;
                if (!keep[m]) keep[m] = 1, ++kept;
            }
        }
    }
    for (std::size_t i = 0; i < patches.size(); ++i) {
        if (keep[i]) {
            out.patches.push_back(std::move(patches[i]));
            ++out.stats.kept;
        } else {
            ++out.stats.duplicates;
        }
    }
}

std::vector<double> grid(double lo, double hi, double step) {
    std::vector<double> out;
    const int n = static_cast<int>(std::floor((hi - lo) / step + 1e-9));
    for (int i = 0; i <= n; ++i) out.push_back(lo + i * step);
    return out;
}

}  // namespace

// ---------------------------------------------------------------------------

double configDistance(const PatchConfig& a, const PatchConfig& b) {
    constexpr double cr = 0.30, ct = std::numbers::pi;
    const double dr = (a.r - b.r) / cr;
    const double d1 = wrapAngle(a.theta1 - b.theta1) / ct;
    const double d2 = wrapAngle(a.theta2 - b.theta2) / ct;
    return dr * dr + d1 * d1 + d2 * d2;
}

std::array<RootXf, 2> placeConfig(const PatchConfig& c) {
    RootXf a;  // origin, facing +Z
    const glm::vec2 dir = headingVector(c.theta1);
    RootXf b;
    b.pos = dir * static_cast<float>(c.r);
    b.heading = wrapAngle(angleOf(-dir) - c.theta2);
    return {a, b};
}

PatchConfig configOf(const RootXf& a, const RootXf& b) {
    PatchConfig c;
    const glm::vec2 d = b.pos - a.pos;
    c.r = glm::length(d);
    if (c.r < 1e-6) return c;
    c.theta1 = wrapAngle(angleOf(d) - a.heading);
    c.theta2 = wrapAngle(angleOf(-d) - b.heading);
    return c;
}

RootXf Patch::endPlacement(const ActionLibrary& lib, int character) const {
    const auto& last = tracks[static_cast<std::size_t>(character)].back();
    return last.placementAt(lib, last.offset + (last.end - last.start));
}

int PatchLibrary::nearestPose(const PatchConfig& c) const {
    int best = -1;
    double bestD = std::numeric_limits<double>::max();
    for (std::size_t i = 0; i < d_.standardPoses.size(); ++i) {
        const double d = configDistance(c, d_.standardPoses[i]);
        if (d < bestD) bestD = d, best = static_cast<int>(i);
    }
    return best;
}

Status generatePatches(const ActionLibrary& lib, const PatternList& pattern, const PatternSet& set, PatchLibrary& library,
                       const GenerateOptions& options, const ProgressFn& progress) {
    PatchLibrary::Data& out = detail::built(library);
    if (pattern.entries.size() > static_cast<std::size_t>(kMaxEntries)) {
        return makeError("pattern '" + pattern.name + "' has more than " + std::to_string(kMaxEntries) + " entries");
    }
    if (auto st = checkPattern(pattern, set, lib); !st) return st;
    const auto wallStart = std::chrono::steady_clock::now();
    const Engine eng(lib, pattern, options);
    if (eng.hold < 0) {
        for (std::size_t e = 0; e < pattern.entries.size(); ++e) {
            if (isResponse(pattern, e)) return makeError("the project has no idle action to wait for a blow in");
        }
    }
    for (std::size_t e = 0; e < pattern.entries.size(); ++e) {
        if (!isResponse(pattern, e) && eng.choices[e].empty()) {
            return makeError("pattern '" + pattern.name + "', entry " + std::to_string(e + 1) + ": no action to choose");
        }
    }
    // The initial-condition grid inside the intersection of the first actions' ranges.
    const auto& f1 = pattern.entries[static_cast<std::size_t>(eng.entriesOf[0].front())];
    const auto& f2 = pattern.entries[static_cast<std::size_t>(eng.entriesOf[1].front())];
    const InitialRange a = set.rangeFor(f1.annotation), b = set.rangeFor(f2.annotation);
    const auto rs = grid(std::max(a.minDistance, b.minDistance), std::min(a.maxDistance, b.maxDistance), options.distanceStep);
    const auto t1s = grid(a.minAngle, a.maxAngle, options.angleStepDegrees);
    const auto t2s = grid(b.minAngle, b.maxAngle, options.angleStepDegrees);
    const auto ds = isResponse(pattern, static_cast<std::size_t>(eng.entriesOf[1].front()))
                        ? std::vector<double>{0.0}
                        : grid(std::max(a.minDelay, b.minDelay), std::min(a.maxDelay, b.maxDelay), options.delayStep);
    std::vector<PatchConfig> ics;
    for (double r : rs)
        for (double t1 : t1s)
            for (double t2 : t2s)
                for (double d : ds) ics.push_back({r, t1 * kDegree, t2 * kDegree, d});
    if (ics.empty()) return makeError("pattern '" + pattern.name + "': the initial-condition grid is empty");

    const int patternIndex = static_cast<int>(out.patterns.size());
    std::vector<Expansion> results;
    results.reserve(ics.size());
    for (const auto& ic : ics) results.push_back(Expansion{eng, patternIndex, ic, {}, {}});
    std::atomic<std::size_t> done{0};
    std::atomic<bool> stop{false};
    std::mutex progressMutex;  // the callback is called from one thread at a time
    if (!reportProgress(progress, 0.0, "patches")) return cancelled();
    auto work = [&](std::size_t i) {
        if (stop.load(std::memory_order_relaxed)) return;
        results[i].start();
        const std::size_t n = ++done;
        if (n % 16 != 0) return;
        const std::lock_guard<std::mutex> lock(progressMutex);
        if (!reportProgress(progress, static_cast<double>(n) / static_cast<double>(ics.size()), "patches")) {
            stop = true;
        }
    };
    if (options.parallel) {
        tbb::parallel_for(std::size_t{0}, ics.size(), work);
    } else {
        for (std::size_t i = 0; i < ics.size(); ++i) work(i);
    }
    if (stop.load()) return cancelled();
    out.patterns.push_back(pattern);
    std::vector<Patch> candidates;
    for (auto& r : results) {
        out.stats.add(r.stats);
        for (auto& p : r.kept) candidates.push_back(std::move(p));
    }
    keepBestPerPath(lib, candidates, options.keepPerPath >= 0 ? options.keepPerPath : pattern.keepPerPath, pattern.spread, out);
    out.stats.initialConditions += static_cast<std::int64_t>(ics.size());
    out.stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    out.libraryKey = libraryFingerprint(lib);
    reportProgress(progress, 1.0, "patches");
    return {};
}

Status addHandMadePatch(const ActionLibrary& lib, const PatternList& pattern, const PatchConfig& initial,
                        const std::array<std::vector<int>, 2>& actions, PatchLibrary& library, const GenerateOptions& options) {
    PatchLibrary::Data& out = detail::built(library);
    const Engine eng(lib, pattern, options);
    for (int c = 0; c < 2; ++c) {
        std::size_t k = 0;
        for (int e : eng.entriesOf[static_cast<std::size_t>(c)]) {
            if (isResponse(pattern, static_cast<std::size_t>(e))) continue;
            const auto& list = actions[static_cast<std::size_t>(c)];
            if (k >= list.size()) {
                return makeError("hand-made patch: character " + std::to_string(c + 1) + " needs an action for entry " +
                                 std::to_string(e + 1) + " (" + eng.entry(e).annotation + ")");
            }
            const int a = list[k++];
            if (a < 0 || a >= lib.size()) return makeError("hand-made patch: action index " + std::to_string(a) + " is out of range");
            if (!matchesAnnotation(lib.actions()[static_cast<std::size_t>(a)], eng.entry(e).annotation)) {
                return makeError("hand-made patch: " + lib.actions()[static_cast<std::size_t>(a)].label() + " is not '" +
                                 eng.entry(e).annotation + "' (entry " + std::to_string(e + 1) + ")");
            }
        }
    }
    // Play the given choices through the engine: a one-path tree.
    std::array<std::size_t, 2> next{};
    const int patternIndex = static_cast<int>(out.patterns.size());
    State s = initialState(initial);
    const int e1 = eng.entriesOf[1].front();
    auto take = [&](int c) { return actions[static_cast<std::size_t>(c)][next[static_cast<std::size_t>(c)]++]; };
    eng.launch(s, 0, take(0), eng.entriesOf[0].front(), 0.0, true);
    if (isResponse(pattern, static_cast<std::size_t>(e1))) {
        eng.launch(s, 1, eng.hold, -1, 0.0, true);
    } else if (e1 - 1 != eng.entriesOf[0].front()) {
        if (eng.hold < 0) return makeError("hand-made patch: the project has no idle action to wait in");
        eng.launch(s, 1, eng.holdBefore[static_cast<std::size_t>(e1)], -1, 0.0, true);
        s.a[1].waitFor = e1 - 1, s.a[1].waitDelay = initial.delay;
    } else {
        eng.launch(s, 1, take(1), e1, initial.delay, true);
    }
    Verdict v = Verdict::Ok;
    for (int who = eng.advance(s, v); who >= 0; who = eng.advance(s, v)) {
        const int e = eng.pendingEntry(s.a[static_cast<std::size_t>(who)], who);
        eng.launch(s, who, take(who), e, s.time, false);
    }
    const char* why = v == Verdict::TooClose ? "the characters' bodies overlap"
                      : v == Verdict::WrongOrder ? "the actions do not start in the pattern's order"
                      : v == Verdict::UnintendedHit ? "a blow lands where the pattern has none"
                      : v == Verdict::MissedContact ? "a reaction in the pattern is never caused by a blow"
                                                    : nullptr;
    if (why) return makeError(std::string("hand-made patch: ") + why);
    const Scores sc = evaluate(eng, s);
    const auto& w = pattern.weights;
    const double score = (w.contact * sc.contact + w.distance * sc.distance + w.timing * sc.timing) /
                         (w.contact + w.distance + w.timing);
    Patch p = makePatch(eng, s, patternIndex, initial, sc, score);
    p.handMade = true;
    out.patterns.push_back(pattern);
    out.patches.push_back(std::move(p));
    out.libraryKey = libraryFingerprint(lib);
    return {};
}

std::uint64_t libraryFingerprint(const ActionLibrary& lib) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](std::uint64_t v) {
        h ^= v;
        h *= 1099511628211ull;
    };
    for (const auto& a : lib.actions()) {
        for (char ch : a.motionId) mix(static_cast<unsigned char>(ch));
        mix(static_cast<std::uint64_t>(a.firstFrame));
        mix(static_cast<std::uint64_t>(a.lastFrame));
        mix(a.flags);
    }
    return h;
}

}  // namespace fray::sim
