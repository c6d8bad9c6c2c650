#include "fray/pipeline/sim_session.h"

#include <cstdio>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/prep/json_reader.h"

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

namespace {

// What sim::sceneProjectPath accepts, read without building the document (a
// 10,000-character scene is tens of MB of JSON; the parse to a document took
// longer than writing the new one): the same limits and the same parser, its
// events only, keeping the top-level object's "format" and "project" (the
// last of each, as the document would). True when the text is JSON within
// prep's size and depth limits, an object, with "format": "fray-scene" and a
// string "project".
class SceneHeader final : public nlohmann::json_sax<nlohmann::ordered_json> {
public:
    static bool isScene(std::string_view text) {
        if (text.size() > prep::kMaxJsonBytes) return false;
        SceneHeader h;
        if (!nlohmann::ordered_json::sax_parse(text.begin(), text.end(), &h)) return false;
        return h.object_ && h.format_ && *h.format_ == "fray-scene" && h.project_;
    }

    bool null() override { return value(std::nullopt); }
    bool boolean(bool) override { return value(std::nullopt); }
    bool number_integer(number_integer_t) override { return value(std::nullopt); }
    bool number_unsigned(number_unsigned_t) override { return value(std::nullopt); }
    bool number_float(number_float_t, const string_t&) override { return value(std::nullopt); }
    bool string(string_t& v) override { return value(v); }
    bool binary(binary_t&) override { return value(std::nullopt); }
    bool start_object(std::size_t) override { return open(true); }
    bool key(string_t& k) override {
        if (depth_ == 1) key_ = k;
        return true;
    }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override { return open(false); }
    bool end_array() override { return close(); }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

private:
    bool value(std::optional<std::string> v) {
        if (depth_ != 1) return true;
        if (key_ == "format") format_ = std::move(v);
        else if (key_ == "project") project_ = std::move(v);
        return true;
    }
    bool open(bool object) {
        if (depth_ == 0) object_ = object;
        else value(std::nullopt);  // an object or array is no string
        return ++depth_ <= prep::kMaxJsonDepth;
    }
    bool close() {
        --depth_;
        return true;
    }
    int depth_ = 0;
    bool object_ = false;
    std::string key_;
    std::optional<std::string> format_, project_;
};

}  // namespace

Status checkSceneOutput(const fs::path& out) {
    if (!fs::exists(out)) return {};
    auto old = readWholeFile(out, "the existing output");
    if (!old || !SceneHeader::isScene(*old)) {
        return makeError(out.string() + ": exists and is not a Fray scene file; refusing to overwrite it");
    }
    return {};
}

}  // namespace fray::pipeline
