#pragma once
// PatternLists (SPEC 4.1, thesis 6.3.2): the ordered (character, annotation)
// entries an Interaction Patch must follow, and the valid initial-condition
// ranges per annotation that bound where the two characters may start.
// Stored in the project file's "pattern_lists" section:
//   {"patterns": [{"name": "...", "entries": [{"character": 1, "annotation": "attack"}, ...],
//                  "weights": {"contact": 1, "distance": 1, "timing": 1}, "threshold": 0.5}],
//    "initial_conditions": {"punch": {"distance": [0.6, 1.2], "angle_deg": [-40, 40], "delay": [0, 0.4]}}}
// Annotation words are the project vocabulary plus the groups "attack"
// (punch or kick), "defence" (avoid or dodge), "fall" (falling) and "any".
#include <optional>
#include <string>
#include <vector>

#include "fray/core/result.h"
#include "fray/prep/project.h"
#include "fray/sim/action_library.h"

namespace fray::sim {

inline constexpr const char* kPatternSection = "pattern_lists";

struct PatternEntry {
    int character = 0;        // 0 or 1 (written 1 or 2 in the file)
    std::string annotation;   // vocabulary word or group
    friend bool operator==(const PatternEntry&, const PatternEntry&) = default;
};

// Weights of the evaluation criteria (SPEC 4.2) and the score a path needs.
struct PatternWeights {
    double contact = 1.0, distance = 1.0, timing = 1.0;
    friend bool operator==(const PatternWeights&, const PatternWeights&) = default;
};

struct PatternList {
    std::string name;
    std::vector<PatternEntry> entries;
    PatternWeights weights;
    double threshold = 0.5;
    // Best patches kept per distinct action sequence (neighbouring initial
    // conditions give near duplicates); 0 keeps all (a domino needs the whole grid).
    int keepPerPath = 3;
    // Keep them spread over the initial-condition grid: among the patches of
    // a sequence scoring within 0.02 of its best, each next one kept is the
    // farthest (distance F of SPEC 4.4, and the delay) from those already
    // kept. Without it, ties go to grid order (the first distances and angles).
    bool spread = false;
    friend bool operator==(const PatternList&, const PatternList&) = default;
};

// Valid initial-condition ranges of an annotation (SPEC 4.1): distance r
// (pelvis to pelvis, m), the character's own angle to the line joining the
// two (deg, 0 = facing the other), and the delay of the second character's
// first action (s).
struct InitialRange {
    double minDistance = 0.6, maxDistance = 1.4;
    double minAngle = -40, maxAngle = 40;
    double minDelay = 0, maxDelay = 0.4;
    friend bool operator==(const InitialRange&, const InitialRange&) = default;
};

struct PatternSet {
    std::vector<PatternList> patterns;
    std::vector<std::pair<std::string, InitialRange>> ranges;  // the user's, overriding the defaults
    const PatternList* find(std::string_view name) const;
    // The range of an annotation: the user's, else the default for it.
    InitialRange rangeFor(const std::string& annotation) const;
};

// Default ranges (punch, kick, attack, defence words, reactions, carrying, any).
InitialRange defaultRange(const std::string& annotation);
// The example PatternLists of SPEC 4.5 that the demo library can play.
std::vector<PatternList> defaultPatterns();

// True when an action matches an entry's annotation (groups included).
// Actions annotated hand or receive match only those words.
bool matchesAnnotation(const LibraryAction& action, const std::string& annotation);
// Reactive annotations (pushed, falling, fall): the entry is a response to a
// hit or a collision, not a choice.
bool isReactiveAnnotation(const std::string& annotation);
// Is entry e of the pattern a response (caused by a blow or a body) rather
// than a choice? Character 1's first entry is always a choice: a reactive one
// means the character is already falling when the patch starts (domino).
bool isResponse(const PatternList& pattern, std::size_t e);

// Reads the project's section (absent: no patterns, default ranges). Errors
// name the file and the JSON path: unknown annotations, bad characters,
// empty patterns, inverted ranges.
Result<PatternSet> projectPatterns(const prep::Project& project, std::string_view fileName);
// Writes the set into the project's section.
void setProjectPatterns(prep::Project& project, const PatternSet& set);

// Checks a pattern against a library: every entry must have at least one
// action; the first actions' ranges must intersect. Errors name the pattern
// and the entry ("pattern 'x', entry 3 (character 2, receive): no action has this annotation").
Status checkPattern(const PatternList& pattern, const PatternSet& set, const ActionLibrary& lib);

}  // namespace fray::sim
