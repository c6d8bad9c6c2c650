#include "fray/pipeline/sim_session.h"

#include <cstdio>

#include "fray/core/atomic_file.h"

namespace fray::pipeline {

namespace fs = std::filesystem;

// A prepared project ready for the planners: motions with contacts, graph,
// action library. Heap-held: the library points into the session's motions.
Result<std::unique_ptr<SimSession>> openSimSession(const std::filesystem::path& project, const ProgressFn& progress,
                                                   const NoteFn& note) {
    auto s = openSession(project, true, progress, note);
    if (!s) return s.error();
    auto out = std::make_unique<SimSession>();
    out->session = std::move(*s);
    auto contacts = computeContacts(out->session, false, progress);
    if (!contacts) return contacts.error();
    auto graph = projectGraph(out->session, "", 0, progress);
    if (!graph) return graph.error();
    out->graph = std::move(*graph);
    if (!out->graph.cached || !contacts->fromCache) {
        if (auto w = prep::writeCache(out->session.file, out->session.cache); !w) {
            if (note) note("warning: could not write the cache: " + w.error().message);
        }
    }
    auto lib = sim::buildActionLibrary(out->session.project, out->session.motions, out->graph.graph, progress);
    if (!lib) return makeError(project.string() + ": " + lib.error().message);
    out->library = std::move(*lib);
    return out;
}


Result<LoadedScene> openScene(const fs::path& sceneFile, const ProgressFn& progress, const NoteFn& note) {
    auto text = readWholeFile(sceneFile, "the scene file");
    if (!text) return text.error();
    const std::string name = sceneFile.string();
    auto projectRel = sim::sceneProjectPath(*text, name);
    if (!projectRel) return projectRel.error();
    fs::path project(*projectRel);
    if (project.is_relative()) project = sceneFile.parent_path() / project;
    if (!fs::exists(project)) return makeError(name + ": /project: cannot find the project '" + project.string() + "'");
    auto ss = openSimSession(project, progress, note);
    if (!ss) return ss.error();
    auto scene = sim::sceneFromJson(*text, name, (*ss)->library);
    if (!scene) return scene.error();
    return LoadedScene{std::move(*ss), std::move(*scene)};
}

std::string sceneProjectReference(const fs::path& sceneFile, const fs::path& project) {
    std::error_code ec;
    const fs::path rel = fs::relative(fs::absolute(project, ec), fs::absolute(sceneFile, ec).parent_path(), ec);
    return (!ec && !rel.empty()) ? rel.generic_string() : fs::absolute(project).generic_string();
}

Status checkSceneOutput(const fs::path& out) {
    if (!fs::exists(out)) return {};
    auto old = readWholeFile(out, "the existing output");
    if (!old || !sim::sceneProjectPath(*old, out.string())) {
        return makeError(out.string() + ": exists and is not a Fray scene file; refusing to overwrite it");
    }
    return {};
}

}  // namespace fray::pipeline
