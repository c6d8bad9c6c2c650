#pragma once
// Scene export: a planned scene (sim::Scene, played back by sim::ScenePoser)
// written as files other tools read. See docs/EXPORT.md.
// - glTF 2.0, one file (.gltf with the buffer embedded, or .glb): per scene
//   character a joint hierarchy, a skin, a capsule body (fray::buildBodyMesh)
//   tinted by side, and one animation for all characters;
// - BVH: one file per character, in scene space (metres, Y up);
// - FBX (binary, through Assimp's exporter): the content of the glTF file, in
//   centimetres;
// and with each, <name>.<format>.scene.json: who does which action when and where.
// Deterministic: the same scene and options give byte-identical files.
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/motion.h"
#include "fray/core/progress.h"
#include "fray/core/retarget.h"
#include "fray/core/skinned_mesh.h"
#include "fray/core/result.h"
#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"

namespace fray::exporter {

enum class Format { Gltf, Glb, Bvh, Fbx };

std::string_view toString(Format format);  // "gltf", "glb", "bvh", "fbx"
std::optional<Format> parseFormat(std::string_view name);
inline constexpr std::string_view kFormatNames = "gltf, glb, bvh or fbx";

// The summary's "format": how an export recognises an earlier one's files.
inline constexpr std::string_view kSummaryFormat = "fray-export";
// 2: one summary per name and format (<name>.<format>.scene.json), "units"
// is the summary's (m) and "file_units" the file's, "last_frame_time" and
// per action "motion_fps" and per character "root_path" added.
inline constexpr int kSummaryVersion = 2;

// Root motion (docs/EXPORT.md): None keeps the skeleton's own root (the
// pelvis, moving in scene space); Floor adds a root bone on the floor under
// the pelvis that carries the trajectory (position on the floor, heading
// about Y) with the pelvis relative to it; InPlace adds the same bone but
// leaves it at the origin, so the character moves in place.
enum class RootMotion { None, Floor, InPlace };
std::optional<RootMotion> parseRootMotion(std::string_view name);  // "none", "floor", "in-place"
inline constexpr std::string_view kRootBoneName = "root";         // "fray_root" when the skeleton has a "root"

struct ExportOptions {
    Format format = Format::Gltf;
    std::filesystem::path outDir;  // created when missing
    double fps = 30.0;             // samples per second of scene time, 1..1000
    // File stem: <name>.gltf, <name>_<character>.bvh, <name>.<format>.scene.json;
    // letters, digits, '_', '-' and '.' only, not starting with '.'.
    std::string name = "scene";
    std::string source;            // the scene file, recorded in the summary ("" = not recorded)
    // The user's rig (fray::loadRigSkeleton): every character is retargeted
    // onto its skeleton (joint names, hierarchy, proportions, local frames)
    // before writing; the report goes to ExportReport::notes.
    std::optional<RetargetTarget> rig;
    // The rig's own skinned mesh, bound to rig->skeleton (RigSkeleton::skin):
    // the retargeted characters wear it instead of Fray's capsules. Empty: capsules.
    std::shared_ptr<const SkinnedMesh> rigSkin;
    RootMotion rootMotion = RootMotion::None;
    // Where each character's pose at a scene time comes from (local pose,
    // root in scene space): empty = sim::ScenePoser (kinematic playback);
    // e.g. posture::ScenePoses::pose for the physics postures (docs/POSTURE.md).
    std::function<void(int character, double t, Pose& out)> poses;
};

// Checks fps and name; the error says which and why.
Status validateOptions(const ExportOptions& options);

struct ExportReport {
    std::vector<std::filesystem::path> files;  // written, in order; the summary last
    int frames = 0;                            // samples per character
    std::vector<std::string> notes;            // for the user: e.g. an older summary left in the folder
};

// Samples every character at options.fps over [0, scene.duration] and writes
// the files, each atomically. Before writing anything it refuses to replace a
// file that no earlier Fray export of this name in this folder wrote (the
// summary lists those), and checks that the folder can be written to.
// Errors name the file or folder and the problem; "cancelled" when progress
// returns false (files already written stay).
Result<ExportReport> exportScene(const sim::Scene& scene, const sim::ActionLibrary& lib, const ExportOptions& options,
                                 const ProgressFn& progress = {});

// Frames an export samples: every 1/fps s from 0, the last one at the
// duration (see SampledScene::time), at least 2.
int exportFrameCount(double duration, double fps);

// Characters allowed in file names: [A-Za-z0-9_.-].
bool isFileSafe(char c);
// `name` with every other character replaced by '_'.
std::string fileSafeName(std::string_view name);

}  // namespace fray::exporter
