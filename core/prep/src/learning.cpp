#include "fray/prep/learning.h"

#include <algorithm>
#include <cmath>

namespace fray::prep {
namespace {

bool confirmed(const ActionInfo& a) { return !a.name.empty() || !a.annotations.empty(); }

// Runs of consecutive confirmed actions as [first action, last action].
std::vector<std::pair<int, int>> confirmedRuns(const MotionActions& doc) {
    std::vector<std::pair<int, int>> runs;
    for (int a = 0; a < doc.actionCount(); ++a) {
        if (!confirmed(doc.actions[static_cast<std::size_t>(a)])) continue;
        if (!runs.empty() && runs.back().second == a - 1) {
            runs.back().second = a;
        } else {
            runs.emplace_back(a, a);
        }
    }
    return runs;
}

}  // namespace

std::vector<SegmentationExample> confirmedExamples(const MotionActions& doc, const MotionSignals& signals,
                                                   const FootContacts& contacts) {
    std::vector<SegmentationExample> out;
    for (const auto& [a, b] : confirmedRuns(doc)) {
        SegmentationExample e;
        e.signals = &signals;
        e.contacts = &contacts;
        e.first = doc.firstFrame(a);
        e.last = doc.lastFrame(b);
        for (int c : doc.cuts) {
            if (c >= e.first && c <= e.last + 1) e.cuts.push_back(c);
        }
        out.push_back(std::move(e));
    }
    return out;
}

RefitReport refitSegmentation(const std::vector<SegmentationExample>& examples, const SegmentationParams& base) {
    RefitReport report;
    report.params = base;
    report.examples = static_cast<int>(examples.size());
    // Segment each motion once per candidate (examples of one motion share it).
    // Also counts every cut the set makes on the examples' motions (`made`).
    auto score = [&](const SegmentationParams& p, int* made = nullptr) {
        BoundaryScore total;
        const MotionSignals* lastSignals = nullptr;
        std::vector<int> cuts;
        for (const auto& e : examples) {
            if (!e.signals || !e.contacts) continue;
            if (e.signals != lastSignals) {
                cuts = segment(*e.signals, *e.contacts, p).cuts;
                lastSignals = e.signals;
                if (made) *made += static_cast<int>(cuts.size());
            }
            std::vector<int> predicted, actual;
            for (int c : cuts) {
                if (c >= e.first && c <= e.last + 1) predicted.push_back(c);
            }
            for (int c : e.cuts) actual.push_back(c);
            total += scoreBoundaries(predicted, actual, static_cast<int>(std::lround(0.1 * e.signals->fps)));
        }
        return total;
    };
    for (const auto& e : examples) report.trueCuts += static_cast<int>(e.cuts.size());
    int bestMade = 0;
    report.before = score(base, &bestMade);
    report.after = report.before;
    if (report.trueCuts == 0) return report;
    const double factors[] = {0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 4.0};
    const double prominences[] = {0.0, 0.05, 0.1, 0.2, 0.4};
    const double caps[] = {0.03, 0.1, 0.3, 1e9};
    const double stills[] = {1.0, 0.0, 0.5, 2.0};  // x base.stillNoiseFactor; 0: idles start after the recovery beat
    // minPhaseSeconds: the base's own (half the smoothing window by default) first, so a refit can keep it
    const double phases[] = {base.minPhaseSeconds, 0.0, 0.05, 0.1};
    int bestChanges = 0;                           // the base set changes none
    for (double f : factors) {
        for (double pr : prominences) {
            for (double cap : caps) {
                for (double still : stills) {
                    for (double phase : phases) {
                        SegmentationParams p = base;
                        p.thresholdFactor = base.thresholdFactor * f;
                        if (base.highAccelThreshold) p.highAccelThreshold = *base.highAccelThreshold * f;
                        p.basinProminence = pr;
                        p.onsetCapFraction = cap;
                        p.stillNoiseFactor = base.stillNoiseFactor * still;
                        p.minPhaseSeconds = phase;
                        ++report.tried;
                        int made = 0;
                        const BoundaryScore s = score(p, &made);
                        // Among sets that score alike, the one that changes
                        // the fewest parameters, then the one that makes the
                        // fewest cuts on the examples' motions (a few
                        // examples rarely say more).
                        const int changes = (f != 1.0) + (pr != base.basinProminence) +
                                            (cap != base.onsetCapFraction) + (still != 1.0) +
                                            (phase != base.minPhaseSeconds);
                        const bool tie = s.f1() > report.after.f1() - 1e-9;
                        if (s.f1() > report.after.f1() + 1e-9 ||
                            (tie && (changes < bestChanges || (changes == bestChanges && made < bestMade)))) {
                            report.after = s;
                            report.params = p;
                            bestChanges = changes;
                            bestMade = made;
                        }
                    }
                }
            }
        }
    }
    return report;
}

std::vector<int> mergeWithConfirmed(const MotionActions& doc, const std::vector<int>& automatic) {
    const auto runs = confirmedRuns(doc);
    std::vector<std::pair<int, int>> spans;  // frames, inclusive
    for (const auto& [a, b] : runs) spans.emplace_back(doc.firstFrame(a), doc.lastFrame(b));
    auto inside = [&](int frame) {
        for (const auto& [first, last] : spans) {
            if (frame >= first && frame <= last + 1) return true;
        }
        return false;
    };
    std::vector<int> out;
    for (int c : doc.cuts) {
        if (inside(c)) out.push_back(c);
    }
    for (int c : automatic) {
        if (!inside(c)) out.push_back(c);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace fray::prep
