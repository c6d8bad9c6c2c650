#pragma once
// Scene kinds as modules: what each kind of composition contributes (its
// spec's JSON fields and their reader, what a spec of that kind must have,
// and the composition itself), the helpers their readers share, and the
// registry compose.cpp keeps of them. Adding a kind: its own
// compose_<kind>.cpp (and fray/sim/compose/<kind>.h for its spec and stats,
// the spec naming its kind in kKind), its module function declared here and
// one entry in the registry (compose.cpp). Internal to fray_sim.
#include <any>
#include <span>
#include <string_view>

#include <nlohmann/json.hpp>

#include "compose_context.h"
#include "fray/prep/json_reader.h"

namespace fray::sim::detail {

using Json = nlohmann::ordered_json;

struct SceneKindModule {
    const char* name;  // "kind" in the spec; its spec type's kKind
    bool needsPatches;  // draws on the patch library (else makes its own)
    std::span<const char* const> fields;  // its own fields of the spec JSON
    // Its own part of a spec with every field at its default.
    std::any (*defaults)();
    // Reads its own fields into `part` (one of its own parts; every kind's
    // fields are read whatever the kind, so a spec can be switched from one
    // kind to another and a bad field of another kind is still reported).
    Status (*parse)(const prep::JsonReader& rd, const Json& j, std::any& part);
    // What a spec of this kind must have, once every field is read.
    Status (*check)(const prep::JsonReader& rd, const std::any& part);
    // Does `part` hold this kind's spec type?
    bool (*holds)(const std::any& part);
    // Composes the scene (its characters, tracks, hits and marks; the
    // registry adds what every scene has). spec.own holds this kind's part.
    Result<Scene> (*compose)(const ActionLibrary& lib, const PatchLibrary& patches, const ComposeSpec& spec, ComposeStats& stats,
                             const ProgressFn& progress);
};

// The registered kinds, in the order their fields are read.
std::span<const SceneKindModule* const> sceneKinds();
// The registered kind of that name, or null.
const SceneKindModule* kindNamed(std::string_view name);

const SceneKindModule& oneVsManyKind();
const SceneKindModule& oneVsOneKind();
const SceneKindModule& dominoKind();
const SceneKindModule& luggageKind();
const SceneKindModule& footballKind();
const SceneKindModule& ratKind();

// Nothing to read (one-vs-one has no fields of its own) or to check.
template <class Part>
Status noFields(const prep::JsonReader&, const Json&, Part&) { return {}; }
template <class Part>
Status noCheck(const prep::JsonReader&, const Part&) { return {}; }

// Runs kind K (a Composer) on a spec.
template <class K>
Result<Scene> composeKind(const ActionLibrary& lib, const PatchLibrary& patches, const ComposeSpec& spec, ComposeStats& stats,
                          const ProgressFn& progress) {
    K c(lib, patches, spec, stats);
    if (auto st = c.ready(); !st) return st.error();
    if (auto st = c.run(progress); !st) return st.error();
    return std::move(c.scene);
}

// The module of scene kind K (a Composer with run()), whose spec part Part
// (named Part::kKind) is read by Parse and checked by Check (once every field is read).
template <class K, class Part, Status (*Parse)(const prep::JsonReader&, const Json&, Part&),
          Status (*Check)(const prep::JsonReader&, const Part&)>
SceneKindModule kindModule(bool needsPatches, std::span<const char* const> fields) {
    return {Part::kKind,
            needsPatches,
            fields,
            [] { return std::any(Part{}); },
            [](const prep::JsonReader& rd, const Json& j, std::any& part) { return Parse(rd, j, std::any_cast<Part&>(part)); },
            [](const prep::JsonReader& rd, const std::any& part) { return Check(rd, std::any_cast<const Part&>(part)); },
            [](const std::any& part) { return std::any_cast<Part>(&part) != nullptr; },
            composeKind<K>};
}

// Optional members of a compose spec: absent leaves `out` as it is; present
// must be a number (an integer for the int form) within [lo, hi].
Status optionalInt(const prep::JsonReader& rd, const Json& obj, const char* key, int lo, int hi, int& out);
// An optional number field of obj (at JSON path `parent`) within (lo, hi],
// or [lo, hi] when lowIncluded.
Status optionalNumberIn(const prep::JsonReader& rd, const Json& obj, const std::string& parent, const char* key, double lo,
                        double hi, const char* unit, double& out, bool lowIncluded);
Status optionalNumber(const prep::JsonReader& rd, const Json& obj, const char* key, double lo, double hi, const char* unit,
                      double& out);

}  // namespace fray::sim::detail
