#pragma once
// A prepared project ready for the planners (motions with contacts, motion
// graph, action library), and a scene file opened against its project.
#include <filesystem>
#include <memory>
#include <string>

#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"
#include "fray/pipeline/prep_session.h"

namespace fray::pipeline {

struct SimSession {
    Session session;
    ProjectGraph graph;
    sim::ActionLibrary library;  // shares copies of session.motions: it stands on its own
};

// Opens the project, computes (or reads from the cache) contacts and the
// graph, writes the cache when it changed, and builds the action library.
Result<std::unique_ptr<SimSession>> openSimSession(const std::filesystem::path& project, const ProgressFn& progress,
                                                   const NoteFn& note = {});

struct LoadedScene {
    std::unique_ptr<SimSession> session;
    sim::Scene scene;
};
// Reads a scene file, opens the project it names (relative to the scene file)
// and resolves its actions.
Result<LoadedScene> openScene(const std::filesystem::path& sceneFile, const ProgressFn& progress, const NoteFn& note = {});

// A scene may only replace a previous scene: never the user's other files.
Status checkSceneOutput(const std::filesystem::path& out);
// How a scene written to sceneFile names its project: relative to the
// scene's folder when possible, else absolute.
std::string sceneProjectReference(const std::filesystem::path& sceneFile, const std::filesystem::path& project);

}  // namespace fray::pipeline
