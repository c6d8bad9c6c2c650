#pragma once
// Learning from the user (docs/DATA_PREP.md): once some actions of a project
// are confirmed or corrected, the segmentation parameters are refit to agree
// with them, and the rest of the project (and new takes) is segmented with
// the refit parameters. An action counts as confirmed when the user named it
// or confirmed an annotation; its cuts are examples.
#include <vector>

#include "fray/prep/actions.h"
#include "fray/prep/segmentation.h"
#include "fray/prep/signals.h"

namespace fray::prep {

// A stretch of one motion whose cuts the user confirmed: frames
// [first, last], with the cuts inside it (first frames of actions).
struct SegmentationExample {
    const MotionSignals* signals = nullptr;
    const FootContacts* contacts = nullptr;
    int first = 0;
    int last = 0;
    std::vector<int> cuts;
};

// The confirmed stretches of a motion: maximal runs of consecutive confirmed
// actions (a name or a confirmed annotation). The cut that starts a run and
// the one that ends it are part of the example.
std::vector<SegmentationExample> confirmedExamples(const MotionActions& doc, const MotionSignals& signals,
                                                   const FootContacts& contacts);

struct RefitReport {
    SegmentationParams params;   // the refit parameters (base when nothing scored better)
    BoundaryScore before, after; // on the examples, with base and with params
    int examples = 0;
    int trueCuts = 0;
    int tried = 0;               // parameter sets scored
};

// Grid search around base over the parameters that carry a take's character
// (high-acceleration threshold factor, basin prominence, onset cap, the idle
// start's still noise factor, the minimum quiet-phase length), scored by
// boundary F1 (+-0.1 s) against the examples' cuts, counting only cuts inside
// each example. Keeps base unless a candidate scores strictly better; among
// candidates that score alike, the one that changes the fewest parameters,
// then the one that makes the fewest cuts on the examples' motions.
// Deterministic.
RefitReport refitSegmentation(const std::vector<SegmentationExample>& examples, const SegmentationParams& base = {});

// Automatic cuts merged with the user's: inside confirmed stretches the
// document's cuts stay, elsewhere the automatic ones are used.
std::vector<int> mergeWithConfirmed(const MotionActions& doc, const std::vector<int>& automatic);

}  // namespace fray::prep
