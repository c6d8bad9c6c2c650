#pragma once
// Setup <-> spec conversions, all in one place (issue 23): a setup to the
// simulate spec (sim::SceneSpec) and to the compose spec (sim::ComposeSpec),
// and a --spec file (with its PNG bitmap) to a setup. Conversions write the
// setup as spec JSON and run the very parsers --spec uses, so a setup and the
// spec file it came from plan byte-identical scenes; should ComposeSpec change
// shape, only this file and convert.cpp follow.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"
#include "fray/setup/scene_setup.h"
#include "fray/sim/action_library.h"
#include "fray/sim/compose.h"
#include "fray/sim/patches.h"
#include "fray/sim/spec.h"

namespace fray::setup {

// The spec JSON text of a setup: its parameters with the trajectories written
// in as checkpoint paths (and "loop_path"), "kind" first for compose kinds.
// A character following a drawn trajectory whose weights have no "w_path"
// gets kDrawnPathWeight (docs/EDITOR.md "Floor tools").
inline constexpr double kDrawnPathWeight = 300;
Result<std::string> setupSpecJson(const SceneSetup& setup);

// The simulate spec of a duel or chase setup. Errors name the setup and the
// JSON path in its parameters ("setup 'duel': /characters/0/depth: ...").
Result<sim::SceneSpec> toSceneSpec(const SceneSetup& setup, const sim::ActionLibrary& lib,
                                   const std::vector<sim::Preset>& presets);
// Pins are honoured by tree expansion only: for a compose-kind setup with
// pins, the message to show (CLI stderr, the editor's status); else "".
std::string pinsNotHonoured(const SceneSetup& setup);
// The compose spec of a compose-kind setup, with the floor bitmap in place.
Result<sim::ComposeSpec> toComposeSpec(const SceneSetup& setup, const sim::PatchLibrary& patches);
// A compose-kind setup's spec read the way `fray-cli compose --setup` reads
// it (every field, ranges included; the PatternLists a spec names must be
// among `patterns`, the project's), without composing. The error names the
// setup and the field ("setup 'rat': /rat/speed: must be ...").
Status checkComposeSetup(const SceneSetup& setup, const std::vector<sim::PatternList>& patterns);

// Reads a painted floor from a file ("bitmap" of a spec's "floor", resolved
// against the spec's folder); the CLI passes its PNG reader.
using FloorLoader = std::function<Result<sim::FloorBitmap>(const std::filesystem::path& file, double metresPerPixel,
                                                           glm::vec2 origin)>;
// A setup from a --spec file's text: simulate specs (no "kind", with
// "characters") become duel (two characters, no "stop_on_catch") or chase
// setups; compose specs keep their kind. The floor bitmap is loaded through
// `loadFloor`. Errors name the spec file and the JSON path.
Result<SceneSetup> importSpec(std::string name, std::string_view text, const std::filesystem::path& specFile,
                              const FloorLoader& loadFloor);

// The library without the rejected patches: their links removed and the
// remaining patches' indices (in links) renumbered. Standard poses are kept.
// Out-of-range ids are errors naming the id.
Result<sim::PatchLibrary> withoutRejected(const sim::PatchLibrary& patches, const std::vector<int>& rejected);

}  // namespace fray::setup
