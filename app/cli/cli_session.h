#pragma once
// fray-cli's view of the pipeline library (core/pipeline): the same
// sessions, with progress lines and notes printed on stderr.
#include <filesystem>
#include <string>
#include <string_view>

#include "fray/pipeline/prep_session.h"
#include "fray/pipeline/sim_session.h"
#include "fray/setup/scene_setup.h"

namespace fray::cli {

using pipeline::computeContacts;
using pipeline::ContactsSummary;
using pipeline::importLabels;
using pipeline::LoadedScene;
using pipeline::loadProjectMotion;
using pipeline::ProjectGraph;
using pipeline::projectGraph;
using pipeline::Session;
using pipeline::SimSession;
using pipeline::checkOutputIsNotInput;
using pipeline::checkSceneOutput;
using pipeline::editProject;
using pipeline::sceneProjectReference;

// Progress lines on stderr ("fray-cli: load walk_01 40%"), at most one per
// 10 % step of each stage.
ProgressFn stderrProgress(bool quiet = false);
// "fray-cli: NOTE" on stderr.
void stderrNote(std::string_view note);

inline Result<Session> openSession(const std::filesystem::path& file, bool loadMotions, const ProgressFn& progress) {
    return pipeline::openSession(file, loadMotions, progress, stderrNote);
}
inline Status saveSession(const Session& s) { return pipeline::saveSession(s, stderrNote); }
inline Result<std::unique_ptr<SimSession>> openSimSession(const std::filesystem::path& project, const ProgressFn& progress) {
    return pipeline::openSimSession(project, progress, stderrNote);
}
inline Result<LoadedScene> openScene(const std::filesystem::path& sceneFile, const ProgressFn& progress) {
    return pipeline::openScene(sceneFile, progress, stderrNote);
}

// compose/simulate --spec FILE | --setup NAME (`verb` starts the usage
// error): exactly one of them, an output a scene may replace, then the spec's
// text (`what` names the file in read errors; "" with --setup) and the label
// errors about it start with (the spec's file, or "setup 'NAME'").
struct SceneSource {
    std::string label, specText;
};
Result<SceneSource> readSceneSource(std::string_view verb, const std::string& spec, const std::string& setupName,
                                    const std::filesystem::path& out, std::string_view what);

// The project's setup NAME, for `verb` (compose or simulate); refused, named,
// when there is none or when it is the other verb's kind.
Result<setup::SceneSetup> setupToRun(std::string_view verb, const prep::Project& project, const std::string& projectFile,
                                     const std::string& name, const std::string& label);

}  // namespace fray::cli
