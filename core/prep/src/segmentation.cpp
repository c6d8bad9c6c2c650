#include "fray/prep/segmentation.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace fray::prep {
namespace {

int framesOf(double seconds, double fps) { return std::max(0, static_cast<int>(std::lround(seconds * fps))); }

// Calls fn(first, last) for every maximal run of frames where pred(f) holds.
template <class Pred, class Fn>
void forEachRun(int frames, Pred pred, Fn fn) {
    int f = 0;
    while (f < frames) {
        if (!pred(f)) {
            ++f;
            continue;
        }
        const int first = f;
        while (f < frames && pred(f)) ++f;
        fn(first, f - 1);
    }
}

}  // namespace

SegmentationResult segment(const MotionSignals& signals, const FootContacts& contacts,
                           const SegmentationParams& params) {
    SegmentationResult r;
    const int frames = signals.frameCount;
    const double fps = signals.fps;
    if (frames < 3) return r;
    const auto n = static_cast<std::size_t>(frames);

    // Smoothed profile (centred box filter).
    const int half = framesOf(params.smoothSeconds * 0.5, fps);
    r.smoothed.resize(n);
    {
        double sum = 0.0;
        int lo = 0, hi = -1;
        for (int f = 0; f < frames; ++f) {
            const int a = std::max(0, f - half), b = std::min(frames - 1, f + half);
            while (hi < b) sum += double(signals.acceleration[static_cast<std::size_t>(++hi)]);
            while (lo < a) sum -= double(signals.acceleration[static_cast<std::size_t>(lo++)]);
            r.smoothed[static_cast<std::size_t>(f)] = static_cast<float>(sum / (b - a + 1));
        }
    }
    if (params.highAccelThreshold) {
        r.threshold = *params.highAccelThreshold;
    } else {
        std::vector<float> sorted = r.smoothed;
        std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n / 2), sorted.end());
        r.threshold = params.thresholdFactor * double(sorted[n / 2]);
    }

    // High-acceleration periods, with short gaps closed.
    r.highAccel.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) r.highAccel[i] = double(r.smoothed[i]) > r.threshold ? 1 : 0;
    const int gap = framesOf(params.closeGapSeconds, fps);
    forEachRun(frames, [&](int f) { return r.highAccel[static_cast<std::size_t>(f)] == 0; },
               [&](int first, int last) {
                   if (first > 0 && last < frames - 1 && last - first + 1 <= gap) {
                       for (int f = first; f <= last; ++f) r.highAccel[static_cast<std::size_t>(f)] = 1;
                   }
               });

    r.support.resize(n);
    for (int f = 0; f < frames; ++f) r.support[static_cast<std::size_t>(f)] = supportAt(contacts, f);

    // Candidate cuts with a strength; thinning keeps the stronger first.
    // Rest-derived cuts are the most certain, then quiet-phase cuts by the
    // phase length, then flight cuts.
    struct Candidate {
        int frame;
        double strength;
    };
    std::vector<Candidate> candidates;
    const int minAction = std::max(1, framesOf(params.minActionSeconds, fps));
    const double restLevel = params.restFraction * r.threshold;
    const int minRest = std::max(1, framesOf(params.minRestSeconds, fps));
    const int idle = std::max(1, framesOf(params.idleSeconds, fps));
    const int delay = framesOf(params.onsetDelaySeconds, fps);
    const int minPhase = framesOf(params.minPhaseSeconds, fps);
    const int recovery = framesOf(params.recoverySeconds, fps);
    const int riseWindow = framesOf(params.onsetWindowSeconds, fps);
    const int apex = framesOf(params.attackApexSeconds, fps);
    const double prominence = params.basinProminence * r.threshold;
    auto acc = [&](int f) { return double(r.smoothed[static_cast<std::size_t>(f)]); };
    auto resting = [&](int f) { return acc(f) <= restLevel; };
    auto quiet = [&](int f) { return r.highAccel[static_cast<std::size_t>(f)] == 0; };
    // Standing pelvis height: the 90th percentile over the take.
    double standing = 0.0;
    if (signals.posture.size() == n) {
        std::vector<float> heights(n);
        for (std::size_t i = 0; i < n; ++i) heights[i] = signals.posture[i][0];
        std::nth_element(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(n * 9 / 10), heights.end());
        standing = double(heights[n * 9 / 10]);
    }
    auto grounded = [&](int f) {
        return standing > 0.0 && double(signals.posture[static_cast<std::size_t>(f)][0]) < params.groundedFraction * standing;
    };
    // Where the profile rises out of the basin [a, b] toward a peak of height
    // `peak`: from the basin's lowest frame, forward while the profile stays
    // within onsetFraction of the climb.
    auto onset = [&](int a, int b, double peak) {
        int at = a;
        for (int f = a; f <= b; ++f) {
            if (acc(f) < acc(at)) at = f;
        }
        const double level = acc(at) + std::min(params.onsetFraction * std::max(0.0, peak - acc(at)), params.onsetCapFraction * r.threshold);
        while (at < b && acc(at + 1) <= level) ++at;
        return at;
    };
    // Peaks inside [first, last] that rise and then fall by `prominence`.
    auto peaksIn = [&](int first, int last) {
        std::vector<int> peaks;
        if (prominence <= 0.0) return peaks;
        bool climbing = false;
        double low = acc(first), high = 0.0;
        int highAt = first;
        for (int f = first; f <= last; ++f) {
            if (!climbing) {
                low = std::min(low, acc(f));
                if (acc(f) - low >= prominence) climbing = true, high = acc(f), highAt = f;
            } else {
                if (acc(f) > high) high = acc(f), highAt = f;
                if (acc(f) <= high - prominence) peaks.push_back(highAt), climbing = false, low = acc(f);
            }
        }
        return peaks;
    };
    // The take's own effector jitter at rest: a real performer never stands
    // perfectly still, a synthetic one does.
    double stillSpeed = 0.0;
    if (params.stillNoiseFactor > 0.0 && signals.effectorSpeed.size() == n) {
        std::vector<float> atRest;
        for (int f = 0; f < frames; ++f) {
            if (resting(f)) atRest.push_back(signals.effectorSpeed[static_cast<std::size_t>(f)]);
        }
        if (!atRest.empty()) {
            const auto q = atRest.begin() + static_cast<std::ptrdiff_t>(atRest.size() / 4);
            std::nth_element(atRest.begin(), q, atRest.end());
            stillSpeed = params.stillNoiseFactor * double(*q);
        }
    }
    const double movingSpeed = params.movingFactor * stillSpeed;
    forEachRun(frames, [&](int f) { return r.support[static_cast<std::size_t>(f)] == Support::Double && quiet(f); },
               [&](int first, int last) {
                   // Rests; a long one is an idle of its own, starting after
                   // the recovery beat of the action that came to rest.
                   int restFrames = 0, restEnd = -1;
                   std::vector<std::pair<int, int>> rests;
                   forEachRun(last - first + 1, [&](int i) { return resting(first + i); },
                              [&](int a, int b) {
                                  if (b - a + 1 >= minRest) rests.emplace_back(first + a, first + b);
                              });
                   // A rest interrupted by a stir of the profile in which no
                   // effector moves faster than the take's jitter is one rest
                   // (a real performer's profile flickers around the rest level).
                   if (stillSpeed > 0.0 && rests.size() > 1) {
                       std::vector<std::pair<int, int>> joined{rests.front()};
                       for (std::size_t i = 1; i < rests.size(); ++i) {
                           bool stillBetween = true;
                           for (int f = joined.back().second + 1; f < rests[i].first && stillBetween; ++f) {
                               stillBetween = double(signals.effectorSpeed[static_cast<std::size_t>(f)]) <= stillSpeed;
                           }
                           if (stillBetween) joined.back().second = rests[i].second;
                           else joined.push_back(rests[i]);
                       }
                       rests = std::move(joined);
                   }
                   for (std::size_t i = 0; i < rests.size(); ++i) {
                       const auto [restFirst, restLast] = rests[i];
                       restFrames = std::max(restFrames, restLast - restFirst + 1);
                       restEnd = restLast;
                       if (restFirst == 0) continue;
                       // The idle starts after the recovery beat, or earlier
                       // where no effector moves faster than the take's own
                       // jitter at rest (a real performer settles slowly, and
                       // the profile reaches the rest level late).
                       int start = std::min(restLast, restFirst + recovery);
                       if (stillSpeed > 0.0) {
                           auto still = [&](int f) {
                               return double(signals.effectorSpeed[static_cast<std::size_t>(f)]) <= stillSpeed;
                           };
                           const int from = i > 0 ? rests[i - 1].second + 1 : first;
                           int f = restFirst;
                           // Back over still frames; a stir shorter than
                           // minRestSeconds (jitter) does not end the rest.
                           while (f > from) {
                               if (still(f - 1)) {
                                   --f;
                                   continue;
                               }
                               int g = f - 1, stir = 0;
                               while (g >= from && !still(g) && stir < minRest) --g, ++stir;
                               if (stir >= minRest || g < from) break;
                               f = g;
                           }
                           if (still(f)) start = std::min(start, f);
                       }
                       // Long enough from where it starts to where movement
                       // starts again (or the rest itself, as before).
                       const int until = restLast < frames - 1 ? restLast + delay : restLast;
                       if (std::max(restLast - restFirst + 1, until - start) >= idle) {
                           candidates.push_back({start, 1e6 + (restLast - restFirst)});
                       }
                   }
                   // Several basins (a block between two punches): an action
                   // starts as each basin rises, but not at the still apex
                   // just after an attack. Not while on the ground, where a
                   // fall or a get-up has many basins.
                   bool low = false;
                   for (int f = first; f <= last && !low; ++f) low = grounded(f);
                   const std::vector<int> peaks = low ? std::vector<int>{} : peaksIn(first, last);
                   const bool afterAttack = first > 0 && !quiet(first - 1);
                   std::vector<Candidate> split;
                   if (!peaks.empty()) {
                       int a = first;
                       for (std::size_t i = 0; i <= peaks.size(); ++i) {
                           const int b = i < peaks.size() ? peaks[i] : last;
                           double peak = 0.0;
                           if (i < peaks.size()) {
                               peak = acc(peaks[i]);
                           } else {
                               if (last == frames - 1) break;
                               for (int f = last + 1; f <= std::min(frames - 1, last + riseWindow); ++f) {
                                   peak = std::max(peak, acc(f));
                               }
                           }
                           const int at = onset(a, b, peak);
                           // A peak with no effector moving clearly faster
                           // than the take's jitter is a sway of the trunk or
                           // a hand settling, not a movement: its basins are one.
                           if (movingSpeed > 0.0 && i < peaks.size()) {
                               double fastest = 0.0;
                               for (int f = at; f <= std::min(frames - 1, at + riseWindow); ++f) {
                                   fastest = std::max(fastest, double(signals.effectorSpeed[static_cast<std::size_t>(f)]));
                               }
                               if (fastest <= movingSpeed) continue;
                               // Nor is a cut where that movement is already
                               // under way (a slow movement's profile rises
                               // late, so its onset lands mid-stroke).
                               if (double(signals.effectorSpeed[static_cast<std::size_t>(at)]) > params.pauseFraction * fastest) continue;
                           }
                           const bool atApex = afterAttack && at - first < apex;
                           if (!atApex) {
                               split.push_back({at, restFrames > 0 ? 1e6 + restFrames : double(b - a + 1)});
                           }
                           a = b;
                       }
                   }
                   if (!split.empty()) {
                       candidates.insert(candidates.end(), split.begin(), split.end());
                       return;
                   }
                   // One basin: cut where movement starts after a rest, else
                   // at the quietest frame.
                   if (restFrames > 0) {
                       if (restEnd < frames - 1) candidates.push_back({std::min(frames - 1, restEnd + delay), 1e6 + restFrames});
                       return;
                   }
                   // Shorter phases are the support flickering inside a movement.
                   if (last - first + 1 < minPhase) return;
                   int at = (first + last) / 2;
                   if (params.placement == SegmentationParams::Placement::Minimum) {
                       for (int f = first; f <= last; ++f) {
                           if (acc(f) < acc(at)) at = f;
                       }
                       at = std::min(frames - 1, at + delay);
                   }
                   candidates.push_back({at, double(last - first + 1)});
               });
    if (params.cutFlightPhases) {
        const int window = framesOf(params.flightWindowSeconds, fps);
        forEachRun(frames, [&](int f) { return r.support[static_cast<std::size_t>(f)] == Support::None && quiet(f); },
                   [&](int first, int last) {
                       // A flight phase between two single-support phases of
                       // opposite feet (a running stride), with no double support near.
                       if (first == 0 || last == frames - 1) return;
                       const Support before = r.support[static_cast<std::size_t>(first - 1)];
                       const Support after = r.support[static_cast<std::size_t>(last + 1)];
                       if (!((before == Support::Left && after == Support::Right) ||
                             (before == Support::Right && after == Support::Left))) {
                           return;
                       }
                       for (int f = std::max(0, first - window); f <= std::min(frames - 1, last + window); ++f) {
                           if (r.support[static_cast<std::size_t>(f)] == Support::Double) return;
                       }
                       candidates.push_back({(first + last) / 2, double(last - first + 1)});
                   });
    }

    // Thinning: keep candidates at least minAction apart from each other and
    // from the ends, stronger first (ties: earlier frame).
    std::stable_sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
        return a.strength != b.strength ? a.strength > b.strength : a.frame < b.frame;
    });
    std::vector<int> kept;
    for (const auto& c : candidates) {
        if (c.frame < minAction || c.frame > frames - minAction) continue;
        const auto it = std::lower_bound(kept.begin(), kept.end(), c.frame);
        if (it != kept.end() && *it - c.frame < minAction) continue;
        if (it != kept.begin() && c.frame - *(it - 1) < minAction) continue;
        kept.insert(it, c.frame);
    }

    // Recurrence filter.
    if (params.recurrenceDistance > 0 && signals.posture.size() == n &&
        static_cast<int>(kept.size()) >= params.recurrenceMinCuts) {
        const auto need = static_cast<std::size_t>(
            std::max(1.0, std::floor(params.recurrenceShare * static_cast<double>(kept.size()))));
        auto distance = [&](int a, int b) {
            const auto& p = signals.posture[static_cast<std::size_t>(a)];
            const auto& q = signals.posture[static_cast<std::size_t>(b)];
            double d = 0.0;
            for (std::size_t k = 0; k < p.size(); ++k) d += std::abs(double(p[k]) - double(q[k]));
            return d;
        };
        // The radius adapts to how varied the cut postures are: a real actor
        // never returns to exactly the same guard, so the radius is at least
        // recurrenceSpread x the median distance between candidate postures.
        std::vector<double> pairwise;
        for (std::size_t i = 0; i < kept.size(); ++i) {
            for (std::size_t j = i + 1; j < kept.size(); j += 1 + kept.size() / 64) {
                pairwise.push_back(distance(kept[i], kept[j]));
            }
        }
        std::nth_element(pairwise.begin(), pairwise.begin() + static_cast<std::ptrdiff_t>(pairwise.size() / 2),
                         pairwise.end());
        const double radius = std::max(params.recurrenceDistance, params.recurrenceSpread * pairwise[pairwise.size() / 2]);
        std::vector<int> recurring;
        for (int c : kept) {
            std::size_t near = 0;
            for (int o : kept) {
                if (o != c && distance(c, o) < radius && ++near >= need) break;
            }
            if (near >= need) recurring.push_back(c);
        }
        kept = std::move(recurring);
    }
    r.cuts = std::move(kept);
    return r;
}

BoundaryScore scoreBoundaries(const std::vector<int>& predicted, const std::vector<int>& actual, int tolerance) {
    BoundaryScore s;
    s.predicted = static_cast<int>(predicted.size());
    s.actual = static_cast<int>(actual.size());
    struct Pair {
        int distance, p, a;
    };
    std::vector<Pair> pairs;
    for (std::size_t i = 0; i < predicted.size(); ++i) {
        // Only true cuts within tolerance can pair; both lists are short per window.
        for (std::size_t j = 0; j < actual.size(); ++j) {
            const int d = std::abs(predicted[i] - actual[j]);
            if (d <= tolerance) pairs.push_back({d, static_cast<int>(i), static_cast<int>(j)});
        }
    }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) {
        return std::tie(x.distance, x.p, x.a) < std::tie(y.distance, y.p, y.a);
    });
    std::vector<char> usedP(predicted.size(), 0), usedA(actual.size(), 0);
    for (const auto& pr : pairs) {
        if (usedP[static_cast<std::size_t>(pr.p)] || usedA[static_cast<std::size_t>(pr.a)]) continue;
        usedP[static_cast<std::size_t>(pr.p)] = usedA[static_cast<std::size_t>(pr.a)] = 1;
        ++s.truePositives;
    }
    return s;
}

}  // namespace fray::prep
