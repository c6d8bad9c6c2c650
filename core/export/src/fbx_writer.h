#pragma once
// FBX through Assimp's exporter (binary FBX 7.5), in centimetres (FBX's
// default unit: UnitScaleFactor 1), Y up. Assimp 5.2's output is repaired
// (its nested lists lack their null records, so Assimp and Blender cannot read
// it back; its layers name elements it did not write) and its creation time
// fixed, so the file is readable and reproducible.
#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"
#include "sampled_scene.h"

namespace fray::exporter {

Result<std::string> writeFbx(const SampledScene& scene, std::string_view name);

// Binary FBX node records (FBX 7.x; 64-bit record headers from 7.5 on).
// Offset of the first property (its type code) of the first node at `path`
// (top-level node first), or nothing when the path does not exist.
std::optional<std::size_t> fbxPropertyOffset(std::string_view bytes, std::initializer_list<std::string_view> path);

// Assimp writes the wall-clock time into FBXHeaderExtension/CreationTimeStamp;
// this sets it to the fixed time Assimp writes in CreationTime
// (1970-01-01 10:00:00:000) so the file is reproducible. A file without the
// node is left as it is; one whose fields are not 32-bit integers is an error.
Status fixFbxCreationTime(std::string& bytes);

// ---- animation timing and rotation curves ------------------------------------
// Assimp 5.2 declares every file 24 fps (TimeMode 11) over a 1 s time span,
// whatever the keys, and ends the animation stack at the animation's length
// cut to whole seconds, so readers that honour the stack (Assimp) drop the
// keys after it. Its rotation keys are Euler angles (order XYZ) computed key
// by key, each in its principal range, so they jump by up to 360 degrees
// where an angle wraps, and a reader that interpolates the curves swings the
// long way round between those keys.

// One AnimationCurve of the file: where its KeyTime (int64) and
// KeyValueFloat (float) elements start, and how many keys it has.
struct FbxCurve {
    std::size_t times = 0, values = 0, count = 0;
};
// The X, Y and Z curves of one "R" (Lcl Rotation) AnimationCurveNode, in degrees.
struct FbxRotationCurves {
    std::array<FbxCurve, 3> axes;
};
// Every rotation curve node whose three curves are present, uncompressed and
// of equal length, in file order.
std::vector<FbxRotationCurves> fbxRotationCurves(std::string_view bytes);
std::array<float, 3> fbxRotationKey(std::string_view bytes, const FbxRotationCurves& curves, std::size_t key);

// Rewrites every rotation curve so consecutive keys are the nearest
// equivalent triples: no angle moves by more than 180 degrees between keys
// unless the rotation itself does; each key's rotation is unchanged.
void unwrapFbxRotationCurves(std::string& bytes);

// Sets GlobalSettings TimeMode (the named rate or custom), CustomFrameRate
// (fps), TimeSpanStart/Stop and every AnimationStack's Local/Reference
// Start/Stop to the file's key range. Errors when a field is missing.
Status setFbxTiming(std::string& bytes, double fps);

}  // namespace fray::exporter
