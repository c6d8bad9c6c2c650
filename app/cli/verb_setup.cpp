// fray-cli setup P list | show NAME | import NAME --spec F | remove NAME:
// the scene setups stored in a project (issue 23, docs/AUTHORING.md). An
// imported spec file keeps its numbers as written, so `simulate/compose P
// --setup NAME` plans the same scene bytes as `--spec F`.
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/prep/json_reader.h"
#include "fray/setup/convert.h"
#include "fray/setup/scene_setup.h"
#include "cli_session.h"
#include "compose_inputs.h"
#include "verbs.h"

namespace fray::cli {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

struct SetupArgs {
    std::string project, action = "list", name, spec;
    bool json = false, replace = false, quiet = false;
};

std::string summary(const setup::SceneSetup& s) {
    std::string out;
    const auto cs = setup::characters(s);
    if (!cs.empty()) out += std::to_string(cs.size()) + " characters";
    if (!s.trajectories.empty()) out += (out.empty() ? "" : ", ") + std::to_string(s.trajectories.size()) + " trajectories";
    if (s.floor) {
        std::size_t painted = 0;
        for (auto b : s.floor->painted) painted += b;
        char buf[96];
        std::snprintf(buf, sizeof buf, "floor %d x %d px at %g m (%zu painted)", s.floor->width, s.floor->height,
                      s.floor->metresPerPixel, painted);
        out += (out.empty() ? "" : ", ") + std::string(buf);
    }
    if (!s.pins.empty()) out += (out.empty() ? "" : ", ") + std::to_string(s.pins.size()) + " pins";
    if (!s.patches.rejected.empty()) out += (out.empty() ? "" : ", ") + std::to_string(s.patches.rejected.size()) + " rejected patches";
    if (!s.patches.kept.empty()) out += (out.empty() ? "" : ", ") + std::to_string(s.patches.kept.size()) + " kept patches";
    return out;
}

// Checks an imported setup against the project the way simulate/compose will
// read it (presets, annotations, motions; the patch library's patterns when
// it exists), so a bad spec is refused at import and not at the first run.
Status checkAgainstProject(const SetupArgs& a, const setup::SceneSetup& s) {
    auto ss = openSimSession(a.project, stderrProgress(a.quiet));
    if (!ss) return ss.error();
    auto& session = **ss;
    if (setup::isTreeExpansion(s.kind)) {
        auto presets = sim::projectPresets(session.session.project, a.project);
        if (!presets) return presets.error();
        auto spec = setup::toSceneSpec(s, session.library, *presets);
        if (!spec) return makeError(a.spec + ": " + spec.error().message);
        return {};
    }
    auto text = setup::setupSpecJson(s);
    if (!text) return text.error();
    sim::PatchLibrary patches;
    if (sim::composeNeedsPatches(*text)) {
        const fs::path lib(a.project + ".patches");
        if (!fs::exists(lib)) {
            std::fprintf(stderr, "fray-cli: %s: no patch library yet; the setup's patterns are checked when it is composed\n",
                         a.project.c_str());
            return {};
        }
        auto loaded = openPatches(a.project, "", session.library);
        if (!loaded) return loaded.error();
        patches = std::move(*loaded);
    }
    auto spec = setup::toComposeSpec(s, patches);
    if (!spec) return makeError(a.spec + ": " + spec.error().message);
    return {};
}

void runSetup(const SetupArgs& a) {
    static const char* const actions[] = {"list", "show", "import", "remove"};
    if (std::find_if(std::begin(actions), std::end(actions), [&](const char* x) { return a.action == x; }) == std::end(actions)) {
        return fail("setup: expected list, show NAME, import NAME --spec FILE or remove NAME, got '" + a.action + "'");
    }
    if (a.action != "list" && a.name.empty()) return fail("setup " + a.action + ": give a setup name");
    if (a.action == "list" || a.action == "show") {
        auto project = prep::loadProject(a.project);
        if (!project) return fail(project.error().message);
        auto setups = setup::projectSetups(*project, a.project);
        if (!setups) return fail(setups.error().message);
        if (a.action == "list") {
            if (a.json) {
                json out = json::array();
                for (const auto& s : *setups) out.push_back(json{{"name", s.name}, {"kind", setup::setupKindName(s.kind)}, {"summary", summary(s)}});
                std::printf("%s\n", out.dump(2).c_str());
            } else {
                for (const auto& s : *setups) std::printf("%-24s %-12s %s\n", s.name.c_str(), setup::setupKindName(s.kind), summary(s).c_str());
            }
            return;
        }
        const setup::SceneSetup* s = setup::findSetup(*setups, a.name);
        if (!s) return fail(a.project + ": no setup named '" + a.name + "'");
        if (a.json) {
            // The setup as stored in the project (floor pixels encoded).
            const json all = json::parse(setup::setupsToJson({*s}));
            std::printf("%s\n", all["setups"][0].dump(2).c_str());
            return;
        }
        auto spec = setup::setupSpecJson(*s);
        if (!spec) return fail(spec.error().message);
        std::printf("# %s: %s setup, run with fray-cli %s %s --setup '%s'%s%s\n", s->name.c_str(), setup::setupKindName(s->kind),
                    setup::isTreeExpansion(s->kind) ? "simulate" : "compose", a.project.c_str(), s->name.c_str(),
                    summary(*s).empty() ? "" : "; ", summary(*s).c_str());
        for (const auto& p : s->pins) std::printf("# pin: %s plays %s at %.2f s\n", p.character.c_str(), p.action.c_str(), p.time);
        std::printf("%s\n", spec->c_str());
        return;
    }
    if (!prep::isValidUtf8(a.name)) return fail("setup " + a.action + ": the name must be UTF-8 text");
    if (a.action == "import") {
        if (a.spec.empty()) return fail("setup import: give the spec file with --spec FILE");
        auto text = readWholeFile(a.spec, "the scene spec");
        if (!text) return fail(text.error().message);
        auto imported = setup::importSpec(a.name, *text, a.spec, loadFloorBitmap);
        if (!imported) return fail(imported.error().message);
        if (auto st = checkAgainstProject(a, *imported); !st) return fail(st.error().message);
        const Status st = editProject(a.project, [&](prep::Project& project) -> Status {
            auto setups = setup::projectSetups(project, a.project);
            if (!setups) return setups.error();
            if (setup::SceneSetup* old = setup::findSetup(*setups, a.name)) {
                if (!a.replace) return makeError(a.project + ": a setup named '" + a.name + "' exists (--replace to overwrite it)");
                *old = *imported;
            } else {
                setups->push_back(*imported);
            }
            setup::setProjectSetups(project, *setups);
            return {};
        });
        if (!st) return fail(st.error().message);
        std::printf("%s: setup '%s' (%s) imported from %s%s%s\n", a.project.c_str(), a.name.c_str(), setup::setupKindName(imported->kind),
                    a.spec.c_str(), summary(*imported).empty() ? "" : ": ", summary(*imported).c_str());
        return;
    }
    // remove
    const Status st = editProject(a.project, [&](prep::Project& project) -> Status {
        auto setups = setup::projectSetups(project, a.project);
        if (!setups) return setups.error();
        const auto before = setups->size();
        std::erase_if(*setups, [&](const setup::SceneSetup& s) { return s.name == a.name; });
        if (setups->size() == before) return makeError(a.project + ": no setup named '" + a.name + "'");
        setup::setProjectSetups(project, *setups);
        return {};
    });
    if (!st) return fail(st.error().message);
    std::printf("%s: setup '%s' removed\n", a.project.c_str(), a.name.c_str());
}

}  // namespace

void registerSetup(CLI::App& app) {
    auto args = std::make_shared<SetupArgs>();
    auto* cmd = app.add_subcommand("setup", "Scene setups stored in a project: list, show, import a --spec file, remove");
    cmd->add_option("project", args->project, "Project file (*.frayproj)")->required();
    cmd->add_option("action", args->action, "list | show NAME | import NAME --spec FILE | remove NAME");
    cmd->add_option("name", args->name, "Setup name");
    cmd->add_option("--spec", args->spec, "import: the simulate or compose spec (JSON; a domino floor's PNG is read beside it)");
    cmd->add_flag("--replace", args->replace, "import: replace a setup of the same name");
    cmd->add_flag("--json", args->json, "JSON output (list; show: the setup as stored)");
    cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
    cmd->callback([args] { runSetup(*args); });
}

}  // namespace fray::cli
