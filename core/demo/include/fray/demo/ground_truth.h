#pragma once
// Ground truth of a demo take: the actions (cut, annotations, joints used,
// attack direction / target / defended part) and the per-frame foot contacts.
// Stored beside each BVH as "<take>.truth.json"; see docs/DEMO_ACTOR.md.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"

namespace fray::demo {

struct TruthAction {
    std::string name;                      // "jab", "walk", "fall_backward", ...
    int firstFrame = 0;                    // inclusive
    int lastFrame = 0;                     // inclusive
    std::string style;                     // "energetic", "tired" or "neutral"
    std::vector<std::string> annotations;  // punch, kick, avoid, dodge, block, step, ...
    std::vector<std::string> joints;       // joints used, skeleton names ("LeftHand")
    std::optional<std::string> attackDirection;  // attacks and hit reactions: "straight", "from_left", ...
    // Unit direction of the attacking joint at its peak speed on the way to the
    // apex of the attack (retraction excluded), in the actor's heading frame
    // (x left, y up, z forward) at that frame. Attacks only.
    std::optional<std::array<double, 3>> attackVector;
    std::optional<double> peakSpeed;             // m/s of the attacking joint then (attacks only)
    std::optional<std::string> targetPart;       // attacks: part aimed at; reactions: part hit
    std::optional<std::string> defendedPart;     // defences: "head", "torso"

    int frameCount() const { return lastFrame - firstFrame + 1; }
    bool has(std::string_view annotation) const;
};

struct GroundTruth {
    std::string take;          // take name
    std::string motionFile;    // BVH file name beside the JSON
    std::string kind;          // take kind ("shadow_boxing", ...)
    std::string style;         // take style
    std::uint64_t seed = 0;
    double fps = 60.0;
    int frameCount = 0;
    std::vector<TruthAction> actions;       // contiguous, in time order, covering every frame
    std::vector<std::uint8_t> leftContact;  // per frame: 1 when the left foot is planted
    std::vector<std::uint8_t> rightContact;
};

// The annotation vocabulary the demo uses (SPEC 1.4 defaults).
const std::vector<std::string>& annotationVocabulary();

// JSON text with a stable key order; per-frame arrays on one line each.
std::string toJson(const GroundTruth& truth);
Result<GroundTruth> groundTruthFromJson(std::string_view text, std::string_view name = "truth.json");
// Checks internal consistency: contiguous actions covering all frames,
// contact arrays of frameCount entries, annotations from the vocabulary.
std::optional<std::string> validate(const GroundTruth& truth);

}  // namespace fray::demo
