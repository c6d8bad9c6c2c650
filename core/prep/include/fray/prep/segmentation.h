#pragma once
// Automatic segmentation of a motion into actions (SPEC 1.2, thesis fig 3.1).
//
//  1. acceleration profile: per frame, sum over joints of squared acceleration;
//  2. support pattern per frame from the foot contacts;
//  3. high-acceleration periods: frames above a threshold (default: a factor
//     of the motion's own median), short gaps between them closed;
//  4. a candidate cut in every "quiet" double-support phase: a run of
//     double-support frames outside high-acceleration periods. A long
//     double-support phase holding several attacks is thus cut between them,
//     never inside one.
// Where the thesis is silent we do what an animator expects:
//  - placement: the thesis cuts at the centre of the phase. When the phase
//    holds a rest (acceleration near zero) the cut goes where movement starts
//    again, so each action begins with its own movement; a long rest becomes
//    an idle action of its own. Without a rest the cut goes to the quietest
//    frame (Placement::Minimum) or the centre (Placement::Centre, the thesis).
//  - gaits without double support (running) cut at the centre of each flight
//    phase, the running counterpart of the walking cut;
//  - cuts closer than the minimum action length are thinned, and cuts at
//    postures that never recur in the take (the held bottom of a duck) are
//    dropped: actions must start and end at postures other actions share, or
//    the motion graph gets dead ends.
#include <cstdint>
#include <optional>
#include <vector>

#include "fray/prep/signals.h"

namespace fray::prep {

struct SegmentationParams {
    enum class Placement { Minimum, Centre };
    // High-acceleration threshold in m^2/s^4. When unset it is
    // thresholdFactor x the median of the smoothed profile (a quantity of the
    // motion itself, so it adapts to energetic and tired takes).
    std::optional<double> highAccelThreshold;
    double thresholdFactor = 12.0;
    double smoothSeconds = 0.05;      // box filter on the profile before thresholding
    double closeGapSeconds = 0.10;    // high periods closer than this merge
    Placement placement = Placement::Minimum;
    double restFraction = 0.01;       // rest: acceleration below this fraction of the threshold
    double minRestSeconds = 0.05;     // shorter rests do not count
    double idleSeconds = 0.75;        // a rest this long becomes an action of its own
    double onsetDelaySeconds = 0.033; // the cut lands this long after the quiet frame (centred differences lead)
    double minActionSeconds = 0.25;   // no action shorter than this
    // A quiet double-support phase without a rest that is shorter than this
    // gives no cut (learnt from the user's cuts, see learning.h). The default
    // is half the smoothing window: a dip of the smoothed profile below the
    // threshold that is narrower than the filter's half-width is the
    // threshold crossing flickering, not a phase the profile resolves.
    double minPhaseSeconds = 0.025;
    // A rest of idleSeconds or more becomes an idle action that starts this
    // long after the body comes to rest: the action that came to rest keeps
    // its recovery beat (the demo actor's clips end with 0.03-0.1 s of it).
    double recoverySeconds = 0.1;
    // ... or, earlier, where the fastest effector (MotionSignals::effectorSpeed)
    // last fell to the take's own jitter at rest before the rest: a real
    // performer settles slowly, and the profile reaches the rest level late.
    // "Still" is stillNoiseFactor x the lower quartile of the effector speed
    // over the resting frames of the take (0 disables).
    // Rests of the profile separated only by frames where no effector is
    // faster than that still level are one rest (and the walk back to where
    // the effectors fell still steps over stirs shorter than minRestSeconds).
    double stillNoiseFactor = 4.0;
    // A basin of a quiet phase is split off only when an effector moves faster
    // than movingFactor x the still level within onsetWindowSeconds of the
    // cut: a bump of the profile without it is a sway of the trunk or a hand
    // settling. A take whose performer stands still (still level near 0, as
    // the synthetic demo actor) keeps its basins.
    double movingFactor = 4.0;
    // ... and only where that movement has not yet reached pauseFraction of
    // its top speed in the window (the profile of a slow movement rises late,
    // and its onset would land mid-stroke).
    double pauseFraction = 0.5;
    // A quiet double-support phase holding several actions (a block or a slip
    // between two punches) is split at its basins: a peak of the profile that
    // rises and falls by basinProminence x the threshold separates two basins,
    // and each basin is cut where the profile rises out of it (onsetFraction of
    // the way from the basin's floor to the next peak, but no more than
    // onsetCapFraction x the threshold above the floor: a real attack's peak
    // is tens of times the threshold, and a share of it lands the cut deep in
    // the attack's wind-up; looked for up to
    // onsetWindowSeconds past the phase). A split cut lies at least
    // attackApexSeconds after an attack (the still apex of a punch is no
    // boundary) and is not taken while the pelvis is below groundedFraction of
    // its standing height (falls, get-ups).
    // basinProminence 0 disables the split.
    double basinProminence = 0.1;
    double onsetFraction = 0.2;
    double onsetCapFraction = 0.1;
    double onsetWindowSeconds = 0.3;
    double attackApexSeconds = 0.2;
    double groundedFraction = 0.6;
    bool cutFlightPhases = true;      // running: cut at the centre of flight phases
    double flightWindowSeconds = 0.4; // ... when no double support lies this close
    // Recurrence filter: a cut survives when at least recurrenceShare of the
    // other cuts have a posture within the radius (L1 over
    // MotionSignals::posture, m): recurrenceDistance, or more for takes
    // whose cut postures vary widely. recurrenceDistance 0 disables it.
    double recurrenceDistance = 0.05;
    double recurrenceShare = 0.05;
    double recurrenceSpread = 0.3;  // radius >= this x the median distance between cut postures
    int recurrenceMinCuts = 20;     // fewer candidate cuts say too little about recurrence: filter off
};

struct SegmentationResult {
    std::vector<int> cuts;               // first frames of actions 1..n (sorted)
    double threshold = 0.0;              // high-acceleration threshold used (m^2/s^4)
    std::vector<float> smoothed;         // profile after smoothing (what was thresholded)
    std::vector<std::uint8_t> highAccel; // per frame
    std::vector<Support> support;        // per frame
};

SegmentationResult segment(const MotionSignals& signals, const FootContacts& contacts,
                           const SegmentationParams& params = {});

// Boundary precision / recall / F1: a predicted cut matches a true one within
// +-tolerance frames, one to one (closest pairs first).
struct BoundaryScore {
    int truePositives = 0, predicted = 0, actual = 0;
    double precision() const { return predicted ? double(truePositives) / predicted : 1.0; }
    double recall() const { return actual ? double(truePositives) / actual : 1.0; }
    double f1() const {
        const double p = precision(), r = recall();
        return p + r > 0 ? 2 * p * r / (p + r) : 0.0;
    }
    BoundaryScore& operator+=(const BoundaryScore& o) {
        truePositives += o.truePositives, predicted += o.predicted, actual += o.actual;
        return *this;
    }
};
BoundaryScore scoreBoundaries(const std::vector<int>& predicted, const std::vector<int>& actual, int tolerance);

}  // namespace fray::prep
