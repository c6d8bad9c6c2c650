// Tree-expansion verbs: simulate (SPEC 2), metrics, presets.
#include <chrono>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/prep/json_reader.h"
#include "fray/posture/posture.h"
#include "fray/pipeline/setup_run.h"
#include "fray/setup/convert.h"
#include "fray/setup/graph_setup.h"
#include "fray/sim/action_library.h"
#include "fray/sim/metrics.h"
#include "fray/sim/planner.h"
#include "fray/sim/spec.h"
#include "cli_session.h"
#include "options.h"
#include "verbs.h"

namespace fray::cli {
namespace {

namespace fs = std::filesystem;

// ---- simulate -----------------------------------------------------------------
struct SimulateArgs {
    std::string project, spec, setup, out;
    bool quiet = false;
};

void runSimulate(const SimulateArgs& a) {
    const fs::path outFile(a.out);
    auto source = readSceneSource("simulate", a.spec, a.setup, outFile, "the scene spec");
    if (!source) return fail(source.error().message);
    const std::string& label = source->label;
    const auto progress = stderrProgress(a.quiet);
    auto ss = openSimSession(a.project, progress);
    if (!ss) return fail(ss.error().message);
    auto& s = **ss;
    auto presets = sim::projectPresets(s.session.project, a.project);
    if (!presets) return fail(presets.error().message);
    Result<sim::Scene> scene = sim::Scene{};
    if (!a.setup.empty()) {
        // simulate --setup NAME: the project's stored setup (issue 23), run as the editor runs it.
        auto found = setupToRun("simulate", s.session.project, a.project, a.setup, label);
        if (!found) return fail(found.error().message);
        pipeline::SetupRunStats runStats;
        scene = pipeline::runSetup(s, *found, nullptr, progress, &runStats);
        if (!scene) return fail(scene.error().message);
        if (setup::isGraphKind(found->kind)) {
            // An Interaction Graph setup: the scene `igraph play` writes for the same parameters (docs/IGRAPH.md).
            const auto& g = runStats.graph;
            if (!g.note.empty()) std::fprintf(stderr, "fray-cli: note: %s\n", g.note.c_str());
            scene->project = sceneProjectReference(outFile, a.project);
            if (auto st = sim::saveScene(*scene, s.library, outFile); !st) return fail(st.error().message);
            std::printf("%s: %s setup '%s', %zu characters, %.1f s, %lld decisions (%lld off the graph), %zu hits", a.out.c_str(),
                        setup::setupKindName(found->kind), found->name.c_str(), scene->characters.size(), scene->duration,
                        static_cast<long long>(g.decisions), static_cast<long long>(g.offGraph), scene->hits.size());
            if (found->kind == setup::SetupKind::GraphCarry) {
                std::printf("; path error mean %.3f m, max %.3f m; hand-to-hand distance within %.2f %% of the box\n", g.pathErrorMean,
                            g.pathErrorMax, 100.0 * g.gripErrorMax);
            } else {
                std::printf(", landed %d (red) vs %d (blue)\n", g.landedRed, g.landedBlue);
            }
            std::printf("graph: %s, %lld states, %lld edges", g.graphSource.c_str(), static_cast<long long>(g.states),
                        static_cast<long long>(g.edges));
            if (g.buildSeconds > 0) std::printf(", built in %.2f s", g.buildSeconds);
            std::printf("\n");
            return;
        }
    } else {
        auto spec = sim::parseSceneSpec(source->specText, a.spec, s.library, *presets);
        if (!spec) return fail(spec.error().message);
        scene = sim::simulate(s.library, s.session.project.combos, *spec, progress);
        if (!scene) return fail(label + ": " + scene.error().message);
    }
    scene->project = sceneProjectReference(outFile, a.project);
    if (auto st = sim::saveScene(*scene, s.library, outFile); !st) return fail(st.error().message);
    const auto& st = scene->stats;
    std::printf("%s: %zu characters, %.1f s, %lld decisions, %zu hits, %zu catches, %lld forced reactions, %lld fallbacks\n",
                a.out.c_str(), scene->characters.size(), scene->duration, static_cast<long long>(st.decisions),
                scene->hits.size(), scene->catches.size(), static_cast<long long>(st.forced),
                static_cast<long long>(st.fallbacks));
    std::printf("planning: %.2f s wall clock (%.1fx real time), %lld nodes, %lld leaves, pruned %.0f %% of %lld choices, "
                "%lld alpha-beta cutoffs, %lld decisions at a lower depth (leaf budget)\n",
                st.seconds, st.seconds > 0 ? scene->duration / st.seconds : 0.0,
                static_cast<long long>(st.nodes), static_cast<long long>(st.leaves), 100.0 * st.prunedShare(),
                static_cast<long long>(st.choices), static_cast<long long>(st.cutoffs), static_cast<long long>(st.shallower));
}

// ---- metrics ------------------------------------------------------------------
struct MetricsArgs {
    std::string scene, posture;
    bool json = false, quiet = false, handPins = false;
};

void runMetrics(const MetricsArgs& a) {
    const auto mode = posture::parseMode(a.posture.empty() ? "kinematic" : a.posture);
    if (!mode) return fail("--posture: '" + a.posture + "' is not kinematic or physics");
    const auto options = postureOptions(a.posture, a.handPins);
    if (!options) return fail(options.error().message);
    auto loaded = openScene(a.scene, stderrProgress(a.quiet));
    if (!loaded) return fail(loaded.error().message);
    const auto& lib = loaded->session->library;
    const auto m = sim::computeMetrics(loaded->scene, lib);
    // --posture: the posture metrics of that mode (docs/POSTURE.md); alone with --json.
    if (!a.json || a.posture.empty()) std::fputs((a.json ? sim::metricsToJson(m) : sim::metricsToText(m)).c_str(), stdout);
    if (a.posture.empty()) return;
    const auto captured = sim::kinematicTracks(loaded->scene, lib);
    auto shown = posture::tracks(*mode, loaded->scene, lib, *options);
    if (!shown) return fail(shown.error().message);
    const auto p = sim::computePostureMetrics(loaded->scene, lib, *shown, captured);
    std::fputs((a.json ? sim::postureMetricsToJson(p) : sim::postureMetricsToText(p)).c_str(), stdout);
}

// ---- presets ------------------------------------------------------------------
struct PresetsArgs {
    std::string project, action = "list", name, description;
    std::vector<std::string> edits;
    bool json = false;
};

void runPresets(const PresetsArgs& a) {
    auto s = openSession(a.project, false, {});
    if (!s) return fail(s.error().message);
    auto presets = sim::projectPresets(s->project, a.project);
    if (!presets) return fail(presets.error().message);
    auto find = [&](const std::string& name) -> const sim::Preset* {
        for (const auto& p : *presets) {
            if (p.name == name) return &p;
        }
        return nullptr;
    };
    if (a.action == "list" || a.action == "show") {
        nlohmann::ordered_json out = nlohmann::ordered_json::array();
        for (const auto& p : *presets) {
            if (a.action == "show" && p.name != a.name) continue;
            if (a.json) {
                auto j = nlohmann::ordered_json::parse(sim::weightsToJson(p.weights));
                j["name"] = p.name;
                j["description"] = p.description;
                out.push_back(j);
            } else {
                std::printf("%-20s %s\n", p.name.c_str(), p.description.c_str());
                if (a.action == "show") std::printf("  %s\n", sim::weightsToJson(p.weights).c_str());
            }
        }
        if (a.action == "show" && !find(a.name)) return fail(a.project + ": no preset named '" + a.name + "'");
        if (a.json) std::printf("%s\n", out.dump(2).c_str());
        return;
    }
    if (a.name.empty()) return fail("presets " + a.action + ": give a preset name");
    if (a.action != "set" && a.action != "remove") {
        return fail("presets: expected list, show, set or remove, got '" + a.action + "'");
    }
    if (!prep::isValidUtf8(a.name) || !prep::isValidUtf8(a.description)) {
        return fail("presets " + a.action + ": the name and --description must be UTF-8 text");
    }
    // Read-modify-write under the project's lock: a concurrent edit waits.
    const Status st = editProject(a.project, [&](prep::Project& project) -> Status {
        auto current = sim::projectPresets(project, a.project);
        if (!current) return current.error();
        if (a.action == "set") {
            sim::Preset p;
            for (const auto& old : *current) {
                if (old.name == a.name) p = old;
            }
            p.name = a.name;
            if (!a.description.empty()) p.description = a.description;
            for (const auto& e : a.edits) {
                if (auto ok = sim::applyWeightEdit(p.weights, e); !ok) return makeError("presets set: " + ok.error().message);
            }
            sim::setProjectPreset(project, p);
        } else if (!sim::removeProjectPreset(project, a.name)) {
            return makeError(a.project + ": '" + a.name + "' is not a project preset (built-ins cannot be removed)");
        }
        return {};
    });
    if (!st) return fail(st.error().message);
    std::printf("%s: preset %s %s\n", a.project.c_str(), a.name.c_str(), a.action == "set" ? "saved" : "removed");
}

}  // namespace

void registerSim(CLI::App& app) {
    {
        auto args = std::make_shared<SimulateArgs>();
        auto* cmd = app.add_subcommand("simulate", "Temporal tree expansion: plan an interaction scene from a JSON spec");
        cmd->add_option("project", args->project, "Project file (*.frayproj)")->required();
        auto* spec = cmd->add_option("--spec", args->spec, "Scene spec (JSON: characters, presets, depths, paths, duration, seed)");
        auto* setupOpt = cmd->add_option("--setup", args->setup, "A duel, chase or Interaction Graph (graph-duel, graph-teams, graph-carry) setup stored in the project (fray-cli setup P list)");
        spec->excludes(setupOpt);
        cmd->add_option("-o,--out", args->out, "Scene file to write (*.frayscene)")->required();
        cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
        cmd->callback([args] { runSimulate(*args); });
    }
    {
        auto args = std::make_shared<MetricsArgs>();
        auto* cmd = app.add_subcommand("metrics", "Scene quality and outcome metrics per character");
        cmd->add_option("scene", args->scene, "Scene file")->required();
        cmd->add_flag("--json", args->json, "JSON output");
        cmd->add_option("--posture", args->posture, "Also the posture metrics of this mode: kinematic | physics (with --json: only them)");
        addHandPinsFlag(cmd, args->handPins);
        cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
        cmd->callback([args] { runMetrics(*args); });
    }
    {
        auto args = std::make_shared<PresetsArgs>();
        auto* cmd = app.add_subcommand("presets", "List and edit the planner's style presets stored in a project");
        cmd->add_option("project", args->project, "Project file")->required();
        cmd->add_option("action", args->action, "list | show NAME | set NAME key=value... | remove NAME");
        cmd->add_option("name", args->name, "Preset name");
        cmd->add_option("edits", args->edits, "key=value weight edits (set)");
        cmd->add_option("--description", args->description, "Description (set)");
        cmd->add_flag("--json", args->json, "JSON output (list, show)");
        cmd->callback([args] { runPresets(*args); });
    }
}

}  // namespace fray::cli
