// fray-cli setup P list | show NAME | import NAME --spec F | remove NAME:
// the scene setups stored in a project (issue 23, docs/AUTHORING.md). An
// imported spec file keeps its numbers as written, so `simulate/compose P
// --setup NAME` plans the same scene bytes as `--spec F`.
#include <cmath>
#include <cstdio>
#include <tuple>
#include <memory>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/prep/json_reader.h"
#include "fray/setup/convert.h"
#include "fray/setup/graph_setup.h"
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
    std::string character, pinAction;  // pin / unpin
    double time = -1;
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
    if (setup::isGraphKind(s.kind)) {
        // Parameters checked by the import; the graph is built (or read) when it runs.
        if (auto p = setup::graphParams(s); !p) return makeError(a.spec + ": " + p.error().message);
        return {};
    }
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

// The character a --character names: a setup character's name, else its
// 0-based index.
Result<std::string> pinCharacter(const setup::SceneSetup& s, const std::string& given) {
    const auto cs = setup::characters(s);
    std::string names;
    for (std::size_t i = 0; i < cs.size(); ++i) names += (i ? ", " : "") + cs[i].name;
    if (given.empty()) return makeError("--character: give the character's name or index (" + names + ")");
    if (setup::characterIndex(s, given) >= 0) return given;
    if (given.find_first_not_of("0123456789") == std::string::npos && given.size() < 9) {
        const int i = std::stoi(given);
        if (i < static_cast<int>(cs.size())) return cs[static_cast<std::size_t>(i)].name;
        return makeError("--character: index " + given + " is out of range (setup '" + s.name + "' has " + std::to_string(cs.size()) +
                         " characters: " + names + ")");
    }
    return makeError("--character: setup '" + s.name + "' has no character named '" + given + "' (" + names + ")");
}

// setup P pin NAME --character C --time T --action A / unpin NAME --character C --time T.
void runPin(const SetupArgs& a) {
    const bool pin = a.action == "pin";
    if (!(a.time >= 0) || !std::isfinite(a.time) || a.time > 3600) return fail("setup " + a.action + ": --time: give the time in seconds, 0 to 3600");
    if (pin && a.pinAction.empty()) return fail("setup pin: --action: give an action name or \"@annotation\"");
    auto project = prep::loadProject(a.project);
    if (!project) return fail(project.error().message);
    auto setups = setup::projectSetups(*project, a.project);
    if (!setups) return fail(setups.error().message);
    setup::SceneSetup* s = setup::findSetup(*setups, a.name);
    if (!s) return fail(a.project + ": no setup named '" + a.name + "'");
    if (!setup::isTreeExpansion(s->kind)) {
        return fail("setup '" + s->name + "' is a " + setup::setupKindName(s->kind) +
                    " setup: pins are honoured by tree expansion only (duel and chase setups); compose kinds cannot honour them");
    }
    auto who = pinCharacter(*s, a.character);
    if (!who) return fail("setup " + a.action + ": " + who.error().message);
    const auto at = std::find_if(s->pins.begin(), s->pins.end(), [&](const setup::Pin& p) {
        return p.character == *who && std::fabs(p.time - a.time) < 1e-6;
    });
    std::string done;
    if (pin) {
        if (at != s->pins.end()) {
            done = "replaced the pin of '" + *who + "' at " + std::to_string(a.time) + " s ('" + at->action + "' -> '" + a.pinAction + "')";
            at->action = a.pinAction;
        } else {
            const setup::Pin p{*who, a.time, a.pinAction};
            s->pins.insert(std::find_if(s->pins.begin(), s->pins.end(), [&](const setup::Pin& q) {
                               return std::tie(q.character, q.time) > std::tie(p.character, p.time);
                           }),
                           p);
            done = "pinned '" + a.pinAction + "' for '" + *who + "'";
        }
        // The setup as simulate will read it: unknown actions, times beyond the scene, ...
        auto ss = openSimSession(a.project, stderrProgress(a.quiet));
        if (!ss) return fail(ss.error().message);
        auto presets = sim::projectPresets((*ss)->session.project, a.project);
        if (!presets) return fail(presets.error().message);
        auto spec = setup::toSceneSpec(*s, (*ss)->library, *presets);
        if (!spec) return fail(spec.error().message);
    } else {
        if (at == s->pins.end()) {
            std::string list;
            for (const auto& p : s->pins) {
                if (p.character == *who) list += (list.empty() ? "" : ", ") + std::to_string(p.time);
            }
            return fail("setup unpin: --time: '" + *who + "' has no pin at " + std::to_string(a.time) + " s" +
                        (list.empty() ? " (it has none)" : " (its pins: " + list + ")"));
        }
        done = "unpinned '" + at->action + "' of '" + *who + "'";
        s->pins.erase(at);
    }
    const setup::SceneSetup edited = *s;
    const Status st = editProject(a.project, [&](prep::Project& p) -> Status {
        auto now = setup::projectSetups(p, a.project);
        if (!now) return now.error();
        setup::SceneSetup* target = setup::findSetup(*now, a.name);
        if (!target) return makeError(a.project + ": no setup named '" + a.name + "'");
        *target = edited;
        setup::setProjectSetups(p, *now);
        return {};
    });
    if (!st) return fail(st.error().message);
    std::printf("%s: setup '%s': %s at %g s (%zu pins)\n", a.project.c_str(), a.name.c_str(), done.c_str(), a.time, edited.pins.size());
}

void runSetup(const SetupArgs& a) {
    static const char* const actions[] = {"list", "show", "import", "remove", "pin", "unpin"};
    if (std::find_if(std::begin(actions), std::end(actions), [&](const char* x) { return a.action == x; }) == std::end(actions)) {
        return fail("setup: expected list, show NAME, import NAME --spec FILE, remove NAME, pin NAME or unpin NAME, got '" + a.action + "'");
    }
    if (a.action == "pin" || a.action == "unpin") {
        if (a.name.empty()) return fail("setup " + a.action + ": give a setup name");
        return runPin(a);
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
                    setup::isSimulateKind(s->kind) ? "simulate" : "compose", a.project.c_str(), s->name.c_str(),
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
    auto* cmd = app.add_subcommand("setup", "Scene setups stored in a project: list, show, import a --spec file, remove, pin/unpin an action");
    cmd->add_option("project", args->project, "Project file (*.frayproj)")->required();
    cmd->add_option("action", args->action, "list | show NAME | import NAME --spec FILE | remove NAME | pin NAME | unpin NAME");
    cmd->add_option("name", args->name, "Setup name");
    cmd->add_option("--spec", args->spec, "import: the simulate or compose spec (JSON; a domino floor's PNG is read beside it)");
    cmd->add_option("--character", args->character, "pin/unpin: the character (name or 0-based index)");
    cmd->add_option("--time", args->time, "pin/unpin: when the pinned action starts (s)");
    cmd->add_option("--action", args->pinAction, "pin: the action to play there (a name or \"@annotation\"; docs/TREE_EXPANSION.md \"Pins\")");
    cmd->add_flag("--replace", args->replace, "import: replace a setup of the same name");
    cmd->add_flag("--json", args->json, "JSON output (list; show: the setup as stored)");
    cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
    cmd->callback([args] { runSetup(*args); });
}

}  // namespace fray::cli
