#pragma once
// Interaction Patches (SPEC 4.2-4.4, thesis chapter 6): short two-character
// interactions generated from PatternLists by expanding a game tree over
// every action that carries each entry's annotation, from initial conditions
// sampled on a grid; the connection tables that say which patches can follow
// or overlap which; and the standard poses that let characters be recycled.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <glm/common.hpp>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/sim/action_library.h"
#include "fray/sim/patterns.h"
#include "fray/sim/scene.h"

namespace fray::sim {

// Two-character configuration (SPEC 4.1): distance, each character's angle to
// the line joining them (rad, 0 = facing the other, + = the other is to its left),
// and, for initial conditions, the second character's delay.
struct PatchConfig {
    double r = 0, theta1 = 0, theta2 = 0, delay = 0;
    friend bool operator==(const PatchConfig&, const PatchConfig&) = default;
};

// F(Pc, Ps) of SPEC 4.4 with C_r = 0.30 m and C_theta = 180 degrees.
double configDistance(const PatchConfig& a, const PatchConfig& b);
// Places two characters in a configuration: character 1 at the origin facing +Z.
std::array<RootXf, 2> placeConfig(const PatchConfig& c);
// The configuration of two placements.
PatchConfig configOf(const RootXf& a, const RootXf& b);

// Floor rectangle (x, z) swept by a character during a time slice.
struct SweptBox {
    glm::vec2 lo{0.0f}, hi{0.0f};
    // The empty box (grows with add).
    static SweptBox empty() {
        return {glm::vec2(std::numeric_limits<float>::max()), glm::vec2(-std::numeric_limits<float>::max())};
    }
    void add(const SweptBox& o) { lo = glm::min(lo, o.lo), hi = glm::max(hi, o.hi); }
    bool overlaps(const SweptBox& o, float margin = 0.0f) const {
        return lo.x <= o.hi.x + margin && o.lo.x <= hi.x + margin && lo.y <= o.hi.y + margin && o.lo.y <= hi.y + margin;
    }
};
inline constexpr double kSweptSlice = 0.25;  // s per swept box
// The box around an oriented box's floor footprint.
inline SweptBox floorBox(const Obb& b) {
    const glm::vec2 c(b.centre.x, b.centre.z), h = floorHalfExtents(b);
    return {c - h, c + h};
}
// The box around a swept box moved by a placement (around the rotated rectangle).
inline SweptBox placedBox(const SweptBox& b, const RootXf& xf) {
    const glm::vec2 c = xf.apply((b.lo + b.hi) * 0.5f);
    const glm::vec2 h = (b.hi - b.lo) * 0.5f;
    const float cs = std::fabs(std::cos(static_cast<float>(xf.heading))), sn = std::fabs(std::sin(static_cast<float>(xf.heading)));
    const glm::vec2 e(cs * h.x + sn * h.y, sn * h.x + cs * h.y);
    return {c - e, c + e};
}

struct Patch {
    int pattern = 0;                              // index in the library's patterns
    std::array<std::vector<ActionInstance>, 2> tracks;  // patch frame: character 1 starts at the origin facing +Z
    std::vector<HitEvent> hits;                   // attacker/defender are 0 or 1
    double duration = 0;                          // the later character's end
    double score = 0;                             // weighted criteria, in [0, 1]
    double contact = 0, distance = 0, timing = 0; // the criteria
    PatchConfig initial, final;                   // final: when the later character ends
    std::array<std::vector<SweptBox>, 2> swept;   // per character, per kSweptSlice from 0
    bool handMade = false;
    // End placement of a character (where its last action leaves it) and its end time.
    RootXf endPlacement(const ActionLibrary& lib, int character) const;
    double endTime(int character) const { return tracks[static_cast<std::size_t>(character)].back().end; }
};

struct GenerateOptions {
    double distanceStep = 0.20;                  // m (SPEC 4.1)
    double angleStepDegrees = 20;
    double delayStep = 0.1;                      // s
    int maxChoicesPerEntry = 0;                  // > 0: at most this many action variants per entry (tests)
    double fallImpulse = 30;                     // N s: a stronger blow knocks down
    double collisionSpeed = 1.2;                 // m/s: a body segment this fast pushes what it hits
    // Paths that play the same actions (by name) from neighbouring initial
    // conditions are near duplicates: keep the best this many of each (0:
    // all; -1: the pattern's own setting).
    int keepPerPath = -1;
    bool parallel = true;
    // Cancel through the progress callback (fray/core/progress.h: return
    // false, or wrap a flag with cancelWhen): generatePatches then returns
    // fray::cancelled().
};

struct GenerateStats {
    std::int64_t initialConditions = 0, paths = 0;
    std::int64_t tooClose = 0, wrongOrder = 0, unintendedHit = 0, missedContact = 0, belowThreshold = 0, duplicates = 0;
    std::int64_t kept = 0;
    double seconds = 0;

    // Every counter of a and the same counter of b, in declaration order
    // (the patch library file stores them in this order); zip adds the
    // wall-clock seconds, which the file does not store (same project, same bytes).
    template <class A, class B, class F>
    static void zipCounts(A& a, B& b, F&& f) {
        f(a.initialConditions, b.initialConditions), f(a.paths, b.paths), f(a.tooClose, b.tooClose);
        f(a.wrongOrder, b.wrongOrder), f(a.unintendedHit, b.unintendedHit), f(a.missedContact, b.missedContact);
        f(a.belowThreshold, b.belowThreshold), f(a.duplicates, b.duplicates), f(a.kept, b.kept);
    }
    template <class A, class B, class F>
    static void zip(A& a, B& b, F&& f) {
        zipCounts(a, b, f);
        f(a.seconds, b.seconds);
    }
    void add(const GenerateStats& o) {
        zip(*this, o, [](auto& x, const auto& y) { x += y; });
    }
    // What was counted since `before` (one PatternList's share).
    GenerateStats since(const GenerateStats& before) const {
        GenerateStats d = *this;
        zip(d, before, [](auto& x, const auto& y) { x -= y; });
        return d;
    }
};

// Connection tables (SPEC 4.3). Temporal: b can follow a; `roles` maps a's
// characters to b's (0: same roles, 1: swapped); `shared` is -1 when both
// continue, else a's character that continues (the other leaves and b's
// other character joins). Spatial: a and b overlap in time, a's character
// `sharedA` being b's `sharedB`, b starting `offset` s after a. The shared
// character plays the same series in both from b's time `from` on: b's head
// may start its clip earlier than a does (a fall that a's victim joins at a
// reaction's best-matching frame and b plays from its start), and only what
// b does from `from` on can be used.
struct TemporalLink {
    int to = 0;
    std::int8_t roles = 0;
    std::int8_t shared = -1;
};
struct SpatialLink {
    int to = 0;
    std::int8_t sharedA = 0, sharedB = 0;
    float offset = 0;
    float from = 0;
};

namespace detail {
struct PatchLibraryBuilder;  // core/sim's generation, hand-made patches, tables and file reading
}

// A patch library: its patterns and patches, and once complete (buildConnections
// after generating; loading always gives a complete library) the connection
// tables and standard poses compose needs. Its data is private: only the
// functions below build one (generatePatches, addHandMadePatch,
// buildConnections, readPatchLibrary/loadPatchLibrary); everyone else reads it
// through the accessors. A default-constructed library is empty.
class PatchLibrary {
public:
    const std::vector<PatternList>& patterns() const { return d_.patterns; }
    const std::vector<Patch>& patches() const { return d_.patches; }
    const std::vector<std::vector<TemporalLink>>& temporal() const { return d_.temporal; }  // per patch
    const std::vector<std::vector<SpatialLink>>& spatial() const { return d_.spatial; }     // per patch
    const std::vector<PatchConfig>& standardPoses() const { return d_.standardPoses; }      // cluster means of initial/final configurations
    const std::vector<int>& initialPose() const { return d_.initialPose; }                   // per patch: its standard pose
    const std::vector<int>& finalPose() const { return d_.finalPose; }
    const GenerateStats& stats() const { return d_.stats; }
    std::uint64_t libraryKey() const { return d_.libraryKey; }  // fingerprint of the action library it was made from
    bool empty() const { return d_.patches.empty(); }
    int nearestPose(const PatchConfig& c) const;
    bool complete() const;  // tables and poses for every patch

    // What a library holds (core/sim's builders fill it).
    struct Data {
        std::vector<PatternList> patterns;
        std::vector<Patch> patches;
        std::vector<std::vector<TemporalLink>> temporal;
        std::vector<std::vector<SpatialLink>> spatial;
        std::vector<PatchConfig> standardPoses;
        std::vector<int> initialPose, finalPose;
        GenerateStats stats;
        std::uint64_t libraryKey = 0;
    };

private:
    friend struct detail::PatchLibraryBuilder;
    Data d_;
};

// Generates the patches of one pattern (appended to lib.patterns/patches).
// Deterministic; parallel over initial conditions; progress and cancel.
Status generatePatches(const ActionLibrary& lib, const PatternList& pattern, const PatternSet& set, PatchLibrary& out,
                       const GenerateOptions& options = {}, const ProgressFn& progress = {});

// A hand-made patch: both characters' action lists from an initial
// configuration, played by the same engine (hits, reactions), kept whatever
// its score. Errors name the problem (an action the pattern forbids, a missed hit).
Status addHandMadePatch(const ActionLibrary& lib, const PatternList& pattern, const PatchConfig& initial,
                        const std::array<std::vector<int>, 2>& actions, PatchLibrary& out, const GenerateOptions& options = {});

// Fills the temporal and spatial tables and the standard poses (makes the
// library complete). Which links exist is the link rule: bump kPatchLinkRule
// whenever it changes.
void buildConnections(const ActionLibrary& lib, PatchLibrary& out);

// The library less the patches `removed` (ids into lib.patches(); a scene
// setup's rejected ones): links into them dropped, the rest renumbered, as
// complete as `lib`. An id outside the library is an error.
Result<PatchLibrary> withoutPatches(const PatchLibrary& lib, std::vector<int> removed);

// Fingerprint of a library's actions (identity of the patch library file).
std::uint64_t libraryFingerprint(const ActionLibrary& lib);

// The patch library file (docs/PATCHES.md, "Library file"): the patches, their
// connection tables and standard poses, and a CRC-32 of everything before it.
// Version 4 is the first with tables and a checksum; earlier versions are
// refused (damage in them cannot be detected) with a message to generate again.
inline constexpr std::uint32_t kPatchFileVersion = 4;
// Version of the rule that decides which temporal and spatial links exist
// (patch_tables.cpp) and how standard poses are clustered. Tables stored under
// another rule are stale: rebuilt or refused, never used.
inline constexpr std::uint32_t kPatchLinkRule = 1;

enum class StaleTables { Rebuild, Refuse };
struct PatchFileOptions {
    StaleTables staleTables = StaleTables::Rebuild;  // tables made under another link rule
    ProgressFn progress;                             // while rebuilding them (cancel: fray::cancelled())
    std::function<void(const std::string&)> notice;  // told when tables were rebuilt, naming the file
};

// The bytes of a complete library's file; an Internal error for an incomplete one.
Result<std::string> patchLibraryBytes(const PatchLibrary& lib);
Status savePatchLibrary(const PatchLibrary& lib, const std::filesystem::path& file);
// A complete library, or an error naming the file: not a patch library, an
// older version (Unsupported), damaged (checksum), made from other actions
// than `actions` (Stale), tables under another link rule (Stale when
// options.staleTables is Refuse; otherwise rebuilt and options.notice told).
Result<PatchLibrary> loadPatchLibrary(const std::filesystem::path& file, const ActionLibrary& actions,
                                      const PatchFileOptions& options = {});
Result<PatchLibrary> readPatchLibrary(std::string_view bytes, std::string_view fileName, const ActionLibrary& actions,
                                      const PatchFileOptions& options = {});
// The CRC-32 (zlib's) a file's last 4 bytes hold, of all the bytes before them.
std::uint32_t patchFileChecksum(std::string_view bytes);

}  // namespace fray::sim
