#pragma once
// The demo actor: a procedural "synthetic actor" that performs boxing,
// footwork, hit reactions, falls, locomotion and carrying, recorded as
// continuous 60 fps takes. Because the takes are generated, their ground truth
// (action cuts, annotations, foot contacts) is known exactly.
//
// Everything here is a job-like function: explicit inputs (a take spec and a
// seed), explicit outputs (a Motion and its GroundTruth), no globals. The same
// inputs give bit-identical outputs.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/motion.h"
#include "fray/demo/ground_truth.h"

namespace fray::demo {

// The demo skeleton: 24 joints, metres, Y-up, facing +Z in the rest pose
// (a T-pose). Joint names follow the Mixamo/LAFAN convention so
// guessStandardJoints finds every standard role.
Skeleton makeDemoSkeleton();

// Performance style of the fighting set. Neutral is used by locomotion,
// falls and carrying.
enum class Style : std::uint8_t { Neutral, Energetic, Tired };
std::string_view toString(Style style);

enum class TakeKind : std::uint8_t { ShadowBoxing, RunningAround, Falls, Carrying, Walking, Football, CarryingEnd };
std::string_view toString(TakeKind kind);

struct TakeSpec {
    std::string name;        // file stem, e.g. "shadowbox_energetic"
    TakeKind kind = TakeKind::Walking;
    Style style = Style::Neutral;
    double seconds = 60.0;   // target length; the take ends with the first action past it
};

struct Take {
    TakeSpec spec;
    Motion motion;
    GroundTruth truth;
};

struct LibraryOptions {
    std::uint64_t seed = 1;
    // Total length of the library in minutes; 0 keeps the default plan
    // (shadow-boxing takes of 2 minutes, the others about 1 minute).
    double minutes = 0.0;
    // Which takes: "default" (fighting, running, falls, carrying, walking) or
    // "football" (running with cuts and tackles, for the football scene) or
    // "carry" (one end of a long box, two takes to pair, for the Interaction
    // Graph's carrying).
    std::string set = "default";
};

inline constexpr double kDemoFps = 60.0;

// Default library length in minutes (sum of the default take lengths).
double defaultLibraryMinutes();
// The takes of a library, lengths scaled to options.minutes. An unknown set
// gives no takes (librarySets() lists the known ones).
std::vector<TakeSpec> planLibrary(const LibraryOptions& options);
const std::vector<std::string>& librarySets();
// Seed of one take: derived from the library seed and the take's name, so a
// take does not change when another one is added.
std::uint64_t takeSeed(std::uint64_t librarySeed, std::string_view takeName);

// Generates one take. Every action kind the take kind uses appears at least
// once, whatever the length.
Take generateTake(const TakeSpec& spec, std::uint64_t seed);

// Every action name the demo actor can perform (63 kinds, three of them only
// in the football set, twelve only in the carry set), and the action kinds of one take kind.
const std::vector<std::string>& actionKinds();
std::vector<std::string> actionKindsOf(TakeKind kind);

}  // namespace fray::demo
