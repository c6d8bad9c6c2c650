#pragma once
// What fray-play and fray open: motion files or a project's takes (with their
// actions as labels), and where the demo project is when no file is given.
// Scene files (*.frayscene) are not takes: fray-play opens them on their own
// (app/cli/scene_stage.h); here they are refused with a clear message.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fray/core/motion.h"
#include "fray/core/result.h"
#include "fray/prep/project.h"
#include "fray/render/motion_stage.h"

namespace fray::app {

struct LoadedTake {
    std::string name;
    std::shared_ptr<Motion> motion;
    std::vector<render::ActionSpan> actions;  // empty for plain motion files
};

// The takes of a project as it is in memory (an editor's document), motion
// paths resolved from projectFile's folder; may be empty.
Result<std::vector<LoadedTake>> loadProjectTakes(const prep::Project& project, const std::filesystem::path& projectFile);

// Motion files (BVH, FBX, glTF, ...) or exactly one .frayproj.
Result<std::vector<LoadedTake>> loadTakes(const std::vector<std::string>& inputs);

// The demo project written by the build: $FRAY_DEMO_LIBRARY/demo.frayproj, or
// demo-library/demo.frayproj beside the executable's bin/ folder.
std::optional<std::filesystem::path> findDemoProject(const char* argv0);

// The demo scene README command (1) writes (demo-run/duel.frayscene beside the
// demo project's folder), when it exists.
std::optional<std::filesystem::path> findDemoScene(const std::filesystem::path& demoProject);

// One actor per take, placed side by side along X, starting at the origin,
// one team colour each.
void stageTakes(const std::vector<LoadedTake>& takes, render::MotionStage& stage);

}  // namespace fray::app
