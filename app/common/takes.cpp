#include "takes.h"

#include <cstdlib>

#include "fray/core/normalize.h"
#include "fray/io/import.h"
#include "fray/prep/project.h"

namespace fray::app {

namespace fs = std::filesystem;

namespace {

Result<Motion> loadProjectMotion(const fs::path& file, const prep::ProjectMotion& entry) {
    LoadOptions o;
    o.normalize = normalizeOptionsFor(entry.units, entry.up);
    return loadMotion(file, o);
}

}  // namespace

Result<std::vector<LoadedTake>> loadProjectTakes(const prep::Project& project, const fs::path& projectFile) {
    std::vector<LoadedTake> takes;
    for (const prep::ProjectMotion& pm : project.motions) {
        auto m = loadProjectMotion(prep::resolveMotionPath(projectFile, pm), pm);
        if (!m) return m.error();
        LoadedTake t{pm.id, std::make_shared<Motion>(std::move(*m)), {}};
        for (int i = 0; i < pm.actions.actionCount(); ++i)
            t.actions.push_back(
                {pm.actions.firstFrame(i), pm.actions.lastFrame(i), pm.actions.actions[static_cast<std::size_t>(i)].name});
        takes.push_back(std::move(t));
    }
    return takes;
}

Result<std::vector<LoadedTake>> loadTakes(const std::vector<std::string>& inputs) {
    std::vector<LoadedTake> takes;
    for (const std::string& in : inputs) {
        const fs::path path(in);
        if (path.extension() == ".frayscene")
            return makeError(in + ": a scene is played on its own (one .frayscene, nothing else); the editor does not "
                                  "play scenes yet: use fray-play or fray-cli render");
        if (path.extension() == ".frayproj") {
            if (inputs.size() != 1) return makeError(in + ": a project must be the only input");
            auto project = prep::loadProject(path);
            if (!project) return project.error();
            auto loaded = loadProjectTakes(*project, path);
            if (!loaded) return loaded.error();
            if (loaded->empty()) return makeError(in + ": the project has no motions");
            return loaded;
        }
        auto m = loadMotion(path);
        if (!m) return m.error();
        if (m->frameCount() == 0) return makeError(in + ": the motion has no frames");
        takes.push_back({path.stem().string(), std::make_shared<Motion>(std::move(*m)), {}});
    }
    return takes;
}

std::optional<fs::path> findDemoProject(const char* argv0) {
    std::vector<fs::path> candidates;
    if (const char* env = std::getenv("FRAY_DEMO_LIBRARY")) candidates.push_back(fs::path(env) / "demo.frayproj");
    std::error_code ec;
    const fs::path exe = fs::canonical("/proc/self/exe", ec);
    if (!ec) candidates.push_back(exe.parent_path().parent_path() / "demo-library" / "demo.frayproj");
    if (argv0) candidates.push_back(fs::absolute(argv0, ec).parent_path().parent_path() / "demo-library" / "demo.frayproj");
    for (const fs::path& p : candidates)
        if (fs::is_regular_file(p, ec)) return p;
    return std::nullopt;
}

std::optional<fs::path> findDemoScene(const fs::path& demoProject) {
    const fs::path scene = demoProject.parent_path().parent_path() / "demo-run" / "duel.frayscene";
    std::error_code ec;
    if (fs::is_regular_file(scene, ec)) return scene;
    return std::nullopt;
}

void stageTakes(const std::vector<LoadedTake>& takes, render::MotionStage& stage) {
    stage.clear();
    const int n = static_cast<int>(takes.size());
    for (int i = 0; i < n; ++i) {
        const LoadedTake& t = takes[static_cast<std::size_t>(i)];
        render::StageActor a;
        a.motion = t.motion.get();
        a.name = t.name;
        a.actions = t.actions;
        a.tint = render::teamColor(i);
        const auto start = render::floorTrail(*t.motion, 0, 0, 1);
        const glm::vec3 s = start.empty() ? glm::vec3(0.0f) : start[0];
        a.offset = glm::vec3((static_cast<float>(i) - 0.5f * static_cast<float>(n - 1)) * 1.6f - s.x, 0.0f, -s.z);
        stage.add(std::move(a));
    }
}

}  // namespace fray::app
