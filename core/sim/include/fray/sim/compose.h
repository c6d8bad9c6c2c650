#pragma once
// Scene composition from Interaction Patches (SPEC 4.4-4.5): patches are
// chained in time (temporal connections, or recycling through standard
// poses) and placed in space; a greedy collision-free locomotion engine
// brings characters to their patches, planned backward in time from each
// interaction, with newcomers entering from outside along radial directions.
// The output is the shared scene timeline.
//
// Each scene kind is a module of its own (core/sim/src/compose_<kind>.cpp,
// registered in compose.cpp's registry) with its spec and stats types in
// fray/sim/compose/<kind>.h. A ComposeSpec is the common part plus the kind's
// own part, held by value whatever its type; ComposeStats likewise. Adding a
// kind touches its own files and the registry, not this header.
//
// Filling a spec from code (what a scene setup does):
//     DominoSpec domino;                       // fray/sim/compose/domino.h
//     domino.floor = ...; domino.starts = {{0.2, {0, 0}}};
//     ComposeSpec spec = ComposeSpec::of(domino);  // kind "domino"
//     spec.duration = 20, spec.seed = 7;       // the common part
//     spec.part<DominoSpec>()->background = 4; // the kind's part, changed later
// or parseComposeSpec on the JSON text. Every kind's spec type names its kind
// (static constexpr const char* kKind) and has defaults for every field.
#include <any>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/sim/patches.h"
#include "fray/sim/scene.h"

namespace fray::sim {

// A timed user command: from `time` on, patches whose main-character actions
// carry `annotation` are preferred (s_u of SPEC 4.4). "move" (one-vs-many
// only) instead sends the main character walking to `at` once it is free
// after `time`; the preference of the command before it stays. `at` is
// where the command was placed on the floor (optional but for move).
struct UserCommand {
    double time = 0;
    std::string annotation;  // punch, kick, avoid, ... or a group (attack, defence); or move
    std::optional<glm::vec2> at = std::nullopt;
};

// What every kind reads: the scene, the patches it may use and how they are scored.
struct ComposeCommonSpec {
    double duration = 30;          // s (one-vs-one stops here; one-vs-many when the enemies are used up or here)
    bool durationGiven = false;    // the spec named a duration (domino: everyone stands at least this long)
    std::uint64_t seed = 1;
    double entryRadius = 8;        // m: newcomers enter from this far out
    std::vector<std::string> patterns;  // pattern names to use; empty: all in the library
    std::vector<UserCommand> commands;
    // Scores (SPEC 4.4).
    double wDensity = 10, wUsage = 1000, wUser = 10000, densityScale = 1.0;
    std::string text;              // the spec as written, kept in the scene
};

// A compose spec: the common part, the kind's name ("kind" in the spec file,
// as the registry knows it) and the kind's own part (its <Kind>Spec).
struct ComposeSpec : ComposeCommonSpec {
    std::string kind;  // "one-vs-many", "domino", ...; empty: none chosen yet
    std::any own;      // the kind's own part (a <Kind>Spec whose kKind is `kind`)

    // A spec of Part's kind with `part` as its own part and the common part's defaults.
    template <class Part>
    static ComposeSpec of(Part part) {
        ComposeSpec s;
        s.set(std::move(part));
        return s;
    }
    // Makes the spec one of Part's kind with `part` as its own part.
    template <class Part>
    Part& set(Part part) {
        kind = Part::kKind;
        return own.emplace<Part>(std::move(part));
    }
    // The kind's own part if the spec is of Part's kind, else null.
    template <class Part>
    const Part* part() const {
        return kind == Part::kKind ? std::any_cast<Part>(&own) : nullptr;
    }
    template <class Part>
    Part* part() {
        return kind == Part::kKind ? std::any_cast<Part>(&own) : nullptr;
    }
};

// The names of the registered scene kinds, in registry order.
std::vector<std::string> sceneKindNames();

// Does a compose spec of this kind draw on the patch library? (The rat scene
// generates its own patches for the rat's speed; it reads "kind" only, and says yes
// for anything it cannot read, so the full parser reports the error.)
bool composeNeedsPatches(std::string_view specText);

// Reads a compose spec (JSON). Errors name the file and the JSON path.
// `patterns`: those a spec may name (the patch library's).
Result<ComposeSpec> parseComposeSpec(std::string_view text, std::string_view fileName, const std::vector<PatternList>& patterns);
Result<ComposeSpec> parseComposeSpec(std::string_view text, std::string_view fileName, const PatchLibrary& patches);

struct ComposeCommonStats {
    int patchesUsed = 0;
    int temporalLinks = 0, recycled = 0;   // how each next patch was found
    int locomotionSteps = 0;
    double maxJunctionError = 0;           // m: worst gap between where locomotion ended and where a patch starts
    double seconds = 0;
};

// The stats of a composition: the common part and, for the kinds that keep
// their own, the kind's part (its <Kind>Stats).
struct ComposeStats : ComposeCommonStats {
    std::any own;
    // The kind's own stats if they are of type S, else null.
    template <class S>
    const S* part() const {
        return std::any_cast<S>(&own);
    }
};

// Composes a scene of spec.kind. A spec whose own part is empty gets its
// kind's defaults; an unknown or empty kind, or an own part of another
// kind's type, is an error.
Result<Scene> compose(const ActionLibrary& lib, const PatchLibrary& patches, const ComposeSpec& spec,
                      ComposeStats* stats = nullptr, const ProgressFn& progress = {});

}  // namespace fray::sim
