#pragma once
// A scene sampled for export: per character its skeleton and a Motion at the
// export rate whose root joint is in scene space (what every writer needs).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fray/core/motion.h"
#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/core/skinned_mesh.h"
#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"

namespace fray::exporter {

struct CharacterTake {
    std::string name;      // as in the scene
    std::string fileName;  // for file and node names: [A-Za-z0-9_.-] only, unique within the scene
    int side = 0, group = 0;
    Motion motion;         // at the export fps; root joint in scene space, metres, Y up
    // The body to write: the rig's own skin bound to motion's skeleton, or
    // empty for Fray's capsules.
    std::shared_ptr<const SkinnedMesh> skin;
};

struct SampledScene {
    std::vector<CharacterTake> characters;
    double fps = 30.0;
    int frames = 0;
    double duration = 0.0;  // the scene's; 0 = frames on the 1/fps grid only

    // Scene time of frame f: f / fps, except that the last frame is at the
    // scene's duration when that falls between the last two grid times (so
    // both ends of the scene are sampled whatever the rate).
    double time(int f) const;
};

// Names usable in file and node names, one per character, in scene order:
// other characters become '_', an empty name becomes "character<i>", and a
// name already taken gets "_<i>" appended.
std::vector<std::string> fileSafeNames(const sim::Scene& scene);

// Poses every character at SampledScene::time of each frame (every 1/fps s,
// the last frame at the scene's duration) with sim::ScenePoser. Quaternions are
// kept in one hemisphere from frame to frame, so importers that interpolate
// component-wise do not spin the long way round. Fails on a scene without
// characters or with a character that has no action.
// `poses`, when set, gives the poses instead of the scene poser (see
// ExportOptions::poses).
using PoseFn = std::function<void(int character, double t, Pose& out)>;
Result<SampledScene> sampleScene(const sim::Scene& scene, const sim::ActionLibrary& lib, double fps,
                                 const ProgressFn& progress, const PoseFn& poses = {});

}  // namespace fray::exporter
