// Interaction Patches verbs (SPEC 4): patches generate | list, compose.
#include <cstdio>
#include <memory>

#if defined(__unix__)
#include <sys/resource.h>
#endif

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/prep/json_reader.h"
#include "fray/render/image.h"
#include "fray/sim/compose.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"
#include "fray/pipeline/setup_run.h"
#include "fray/setup/convert.h"
#include "fray/setup/paint.h"
#include "fray/sim/compose/domino.h"
#include "fray/sim/compose/football.h"
#include "fray/sim/compose/luggage.h"
#include "fray/sim/compose/rat.h"
#include "cli_session.h"
#include "compose_inputs.h"
#include "verbs.h"

namespace fray::cli {

namespace fs = std::filesystem;

// The patch library of a project lives beside it: demo.frayproj -> demo.frayproj.patches.
fs::path defaultPatchFile(const std::string& project) { return fs::path(project + ".patches"); }

Result<sim::PatchLibrary> openPatches(const std::string& project, const std::string& file, const sim::ActionLibrary& lib) {
    const fs::path f = file.empty() ? defaultPatchFile(project) : fs::path(file);
    if (!fs::exists(f)) {
        return makeError(f.string() + ": no patch library (make it with: fray-cli patches generate " + project + ")");
    }
    sim::PatchFileOptions options;
    options.notice = [](const std::string& note) { std::fprintf(stderr, "%s\n", note.c_str()); };
    return sim::loadPatchLibrary(f, lib, options);
}

// A painted floor area from a two-colour PNG: dark pixels are painted, light or
// transparent ones are not; anything in between is refused (it is not a mask).
Result<sim::FloorBitmap> loadFloorBitmap(const fs::path& file, double metresPerPixel, glm::vec2 origin) {
    auto image = render::readPng(file);
    if (!image) return image.error();
    auto paint = setup::floorFromRgba(image->width, image->height, image->rgba.data(), metresPerPixel,
                                      {static_cast<double>(origin.x), static_cast<double>(origin.y)}, file.string());
    if (!paint) return paint.error();
    sim::FloorBitmap floor = setup::toFloorBitmap(*paint);
    floor.origin = origin;  // as the spec parser read it
    if (std::find(floor.painted.begin(), floor.painted.end(), 1) == floor.painted.end()) {
        return makeError(file.string() + ": nothing is painted (paint the area in black on white)");
    }
    return floor;
}

namespace {

// ---- patches generate | list ----------------------------------------------------
struct PatchesArgs {
    std::string action = "list", project, out;
    std::vector<std::string> patterns;
    int maxChoices = 0;
    bool json = false, quiet = false;
};

void printStats(const char* what, const sim::GenerateStats& s) {
    std::printf("%s: %lld initial conditions, %lld paths: %lld kept, %lld near duplicates, %lld below the threshold, "
                "discarded %lld too close, %lld wrong order, %lld unintended hits, %lld missed contacts; %.2f s\n",
                what, static_cast<long long>(s.initialConditions), static_cast<long long>(s.paths), static_cast<long long>(s.kept),
                static_cast<long long>(s.duplicates), static_cast<long long>(s.belowThreshold), static_cast<long long>(s.tooClose),
                static_cast<long long>(s.wrongOrder), static_cast<long long>(s.unintendedHit), static_cast<long long>(s.missedContact),
                s.seconds);
}

void runGenerate(const PatchesArgs& a, SimSession& s) {
    auto set = sim::projectPatterns(s.session.project, a.project);
    if (!set) return fail(set.error().message);
    if (set->patterns.empty()) {
        if (!a.quiet) std::fprintf(stderr, "%s has no PatternLists: using the default ones\n", a.project.c_str());
        // Only those the project's actions can play (a fighting project has no
        // tackles, a football one no punches); a PatternList the user wrote
        // that no action can satisfy is still an error.
        for (auto& p : sim::defaultPatterns()) {
            if (auto st = sim::checkPattern(p, *set, s.library); !st) {
                if (!a.quiet) std::fprintf(stderr, "skipping the default %s\n", st.error().message.c_str());
                continue;
            }
            set->patterns.push_back(std::move(p));
        }
        if (set->patterns.empty()) return fail(a.project + ": the project's actions can play none of the default PatternLists");
    }
    std::vector<const sim::PatternList*> chosen;
    for (const auto& name : a.patterns) {
        const auto* p = set->find(name);
        if (!p) return fail(a.project + ": no PatternList named '" + name + "'");
        chosen.push_back(p);
    }
    if (chosen.empty()) {
        for (const auto& p : set->patterns) chosen.push_back(&p);
    }
    sim::PatchLibrary out;
    sim::GenerateOptions opt;
    opt.maxChoicesPerEntry = a.maxChoices;
    const auto progress = stderrProgress(a.quiet);
    for (const auto* p : chosen) {
        const auto before = out.stats();
        if (auto st = sim::generatePatches(s.library, *p, *set, out, opt, progress); !st) return fail(st.error().message);
        printStats(p->name.c_str(), out.stats().since(before));
    }
    const fs::path file = a.out.empty() ? defaultPatchFile(a.project) : fs::path(a.out);
    if (fs::exists(file)) {
        auto old = readWholeFile(file, "the existing output");
        if (!old || old->compare(0, 8, "FRAYPTCH") != 0) {
            return fail(file.string() + ": exists and is not a Fray patch library; refusing to overwrite it");
        }
    }
    // The file stores the connection tables: loading it needs no rebuild.
    sim::buildConnections(s.library, out);
    if (auto st = sim::savePatchLibrary(out, file); !st) return fail(st.error().message);
    std::size_t temporal = 0, spatial = 0;
    for (const auto& t : out.temporal()) temporal += t.size();
    for (const auto& t : out.spatial()) spatial += t.size();
    std::printf("%s: %zu patches from %zu PatternLists; %zu temporal and %zu spatial connections; %zu standard poses\n",
                file.string().c_str(), out.patches().size(), out.patterns().size(), temporal, spatial, out.standardPoses().size());
}

void runList(const PatchesArgs& a, SimSession& s) {
    auto patches = openPatches(a.project, a.out, s.library);
    if (!patches) return fail(patches.error().message);
    const auto& lib = s.library;
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < patches->patches().size(); ++i) {
        const auto& p = patches->patches()[i];
        const auto& pattern = patches->patterns()[static_cast<std::size_t>(p.pattern)].name;
        std::array<std::string, 2> acts;
        for (int c = 0; c < 2; ++c) {
            for (const auto& inst : p.tracks[static_cast<std::size_t>(c)]) {
                acts[static_cast<std::size_t>(c)] += (acts[static_cast<std::size_t>(c)].empty() ? "" : " ") +
                                                     lib.actions()[static_cast<std::size_t>(inst.action)].label() + (inst.forced ? "!" : "");
            }
        }
        if (a.json) {
            out.push_back({{"index", i}, {"pattern", pattern}, {"score", p.score}, {"duration", p.duration},
                           {"hits", p.hits.size()}, {"character1", acts[0]}, {"character2", acts[1]},
                           {"initial", {{"r", p.initial.r}, {"theta1_deg", p.initial.theta1 * 180 / 3.14159265358979},
                                        {"theta2_deg", p.initial.theta2 * 180 / 3.14159265358979}, {"delay", p.initial.delay}}},
                           {"temporal_links", patches->temporal()[i].size()}, {"spatial_links", patches->spatial()[i].size()}});
        } else {
            std::printf("%5zu %-28s %.2f %5.2fs r=%.1f  1: %s | 2: %s\n", i, pattern.c_str(), p.score, p.duration, p.initial.r,
                        acts[0].c_str(), acts[1].c_str());
        }
    }
    if (a.json) std::printf("%s\n", out.dump(2).c_str());
}

void runPatches(const PatchesArgs& a) {
    if (a.action != "generate" && a.action != "list") return fail("patches: expected generate or list, got '" + a.action + "'");
    auto ss = openSimSession(a.project, stderrProgress(a.quiet));
    if (!ss) return fail(ss.error().message);
    if (a.action == "generate") return runGenerate(a, **ss);
    runList(a, **ss);
}

// ---- compose --------------------------------------------------------------------
struct ComposeArgs {
    std::string project, spec, setup, out, patches;
    bool quiet = false;
};


// The most resident memory the process has used so far (MB), 0 where unknown.
double peakMemoryMB() {
#if defined(__unix__)
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) == 0) return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kB
#endif
    return 0.0;
}

// What a kind's own stats say, where it keeps its own.
void reportKind(const ComposeArgs& a, const sim::ComposeSpec& spec, const sim::ComposeStats& st, const sim::Scene& scene) {
    if (const auto* fb = st.part<sim::FootballStats>()) {
        char goal[64] = "did not reach the goal line";
        if (fb->goalReached >= 0) std::snprintf(goal, sizeof goal, "crossed the goal line at %.1f s", fb->goalReached);
        std::printf("%s: %d patches joined through the carrier's motion graph, %d second tackler%s beside them by spatial "
                    "connection; the carrier got past %d tacklers and %s\n",
                    a.out.c_str(), fb->graphJoined, fb->secondTacklers, fb->secondTacklers == 1 ? "" : "s", fb->tacklersPassed, goal);
    }
    const auto* rat = spec.part<sim::RatSpec>();
    const auto* ratStats = st.part<sim::RatStats>();
    if (rat && ratStats) {
        if (static_cast<int>(scene.characters.size()) - 1 < rat->crowd) {
            std::printf("%s: %zu of the %d people asked for fit within %.1f m of the trajectory at %.2f m spacing\n", a.out.c_str(),
                        scene.characters.size() - 1, rat->crowd, rat->band, rat->spacing);
        }
        std::printf("%s: %d {run, AVOID} patches generated for the rat's %.1f m/s\n", a.out.c_str(), ratStats->ratPatches, rat->ratSpeed);
        std::printf("%s: %d people within %.1f m of the rat's trajectory: %d stepped out of its way (closest it came to "
                    "their feet %.2f m), %d were pushed aside by a neighbour first, %d had no way out and reeled back, %d could not "
                    "even do that; %d bumps in all\n",
                    a.out.c_str(), ratStats->ratNear, rat->reach, ratStats->ratAvoided, ratStats->ratClearance, ratStats->ratPushed,
                    ratStats->ratStartled, ratStats->ratRunOver, ratStats->bumps);
    }
    if (const auto* luggage = spec.part<sim::LuggageSpec>(); luggage && st.patchesUsed < luggage->handoffs) {
        std::printf("%s: %d of the %d hand-overs asked for fit in the %.0f s duration (raise \"duration\" for more)\n", a.out.c_str(),
                    st.patchesUsed, luggage->handoffs, spec.duration);
    }
    if (const auto* domino = st.part<sim::DominoStats>()) {
        std::printf("%s: %d of the %d chain falls joined by spatial connection; the falls cover %.0f %% of the painted area (within "
                    "%.1f m of someone who fell)\n",
                    a.out.c_str(), domino->spatialFalls, domino->chainFalls, 100.0 * domino->paintedCoverage,
                    double(sim::DominoStats::kCoverRadius));
    }
}

void runCompose(const ComposeArgs& a) {
    const fs::path outFile(a.out);
    auto source = readSceneSource("compose", a.spec, a.setup, outFile, "the compose spec");
    if (!source) return fail(source.error().message);
    const std::string& label = source->label;
    const std::string& specText = source->specText;
    // Syntax first (line and column), before any project or library work.
    if (!a.spec.empty()) {
        if (auto j = prep::parseJson(specText, a.spec); !j) return fail(j.error().message);
    }
    auto ss = openSimSession(a.project, stderrProgress(a.quiet));
    if (!ss) return fail(ss.error().message);
    auto& s = **ss;
    Result<sim::PatchLibrary> patches = sim::PatchLibrary{};
    Result<sim::ComposeSpec> spec = sim::ComposeSpec{};
    Result<sim::Scene> scene = sim::Scene{};
    sim::ComposeStats st;
    if (!a.setup.empty()) {
        // compose --setup NAME: the project's setup, run as the editor runs it
        // (its floor bitmap; the patch library less the patches it rejected).
        auto found = setupToRun("compose", s.session.project, a.project, a.setup, label);
        if (!found) return fail(found.error().message);
        if (auto note = setup::pinsNotHonoured(*found); !note.empty()) std::fprintf(stderr, "fray-cli: note: %s\n", note.c_str());
        if (pipeline::setupNeedsPatches(*found)) patches = openPatches(a.project, a.patches, s.library);
        if (!patches) return fail(patches.error().message);
        spec = setup::toComposeSpec(*found, *patches);  // what the summary below reports
        if (!spec) return fail(spec.error().message);
        pipeline::SetupRunStats stats;
        scene = pipeline::runSetup(s, *found, &*patches, stderrProgress(a.quiet), &stats);
        if (!scene) return fail(scene.error().message);
        st = stats.compose;
    } else {
        // The rat scene generates its own patches for the rat's speed; the others draw on the patch library.
        if (sim::composeNeedsPatches(specText)) patches = openPatches(a.project, a.patches, s.library);
        if (!patches) return fail(patches.error().message);
        spec = sim::parseComposeSpec(specText, a.spec, *patches);
        if (!spec) return fail(spec.error().message);
        if (auto* domino = spec->part<sim::DominoSpec>(); domino && !domino->floorFile.empty()) {
            fs::path bitmap(domino->floorFile);
            if (bitmap.is_relative()) bitmap = fs::path(a.spec).parent_path() / bitmap;  // relative to the spec
            auto floor = loadFloorBitmap(bitmap, domino->metresPerPixel, domino->floorOrigin);
            if (!floor) return fail(floor.error().message);
            domino->floor = std::move(*floor);
        }
        scene = sim::compose(s.library, *patches, *spec, &st, stderrProgress(a.quiet));
        if (!scene) return fail(label + ": " + scene.error().message);
    }
    scene->project = sceneProjectReference(outFile, a.project);
    if (auto saved = sim::saveScene(*scene, s.library, outFile); !saved) return fail(saved.error().message);
    const sim::DominoStats* dominoStats = st.part<sim::DominoStats>();
    std::printf("%s: %s, %zu characters, %.1f s, %zu hits; %d patches (%d by temporal connection, %d recycled through "
                "standard poses, %d chain falls), %d locomotion steps, worst junction %.2f m; %.3f s\n",
                a.out.c_str(), spec->kind.c_str(), scene->characters.size(), scene->duration, scene->hits.size(), st.patchesUsed,
                st.temporalLinks, st.recycled, dominoStats ? dominoStats->chainFalls : 0, st.locomotionSteps, st.maxJunctionError,
                st.seconds);
    reportKind(a, *spec, st, *scene);
    // Time and memory on stderr (stdout stays the same from run to run).
    std::fprintf(stderr, "%s: composed in %.3f s; peak memory %.0f MB (the whole process, loading included)\n", a.out.c_str(),
                 st.seconds, peakMemoryMB());
}

}  // namespace

void registerPatches(CLI::App& app) {
    {
        auto args = std::make_shared<PatchesArgs>();
        auto* cmd = app.add_subcommand("patches", "Interaction Patches: generate the library from the project's PatternLists, or list it");
        cmd->add_option("action", args->action, "generate | list")->required();
        cmd->add_option("project", args->project, "Project file (*.frayproj)")->required();
        cmd->add_option("--pattern", args->patterns, "PatternList to generate (repeatable; default: all)");
        cmd->add_option("-o,--out", args->out, "Patch library file (default: PROJECT.patches)");
        cmd->add_option("--max-choices", args->maxChoices, "At most this many action variants per entry (0: all)");
        cmd->add_flag("--json", args->json, "JSON output (list)");
        cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
        cmd->callback([args] { runPatches(*args); });
    }
    {
        auto args = std::make_shared<ComposeArgs>();
        auto* cmd = app.add_subcommand("compose", "Compose a scene from Interaction Patches (one-vs-many, one-vs-one, domino, luggage, football, rat)");
        cmd->add_option("project", args->project, "Project file (*.frayproj)")->required();
        auto* spec = cmd->add_option("--spec", args->spec, "Compose spec (JSON: kind and its inputs, e.g. enemies, commands, bitmap, porters, directions, rat; duration, seed; docs/PATCHES.md)");
        auto* setupOpt = cmd->add_option("--setup", args->setup, "A scene setup stored in the project (fray-cli setup P list); its rejected patches are left out");
        spec->excludes(setupOpt);
        cmd->add_option("-o,--out", args->out, "Scene file to write (*.frayscene)")->required();
        cmd->add_option("--patches", args->patches, "Patch library (default: PROJECT.patches)");
        cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
        cmd->callback([args] { runCompose(*args); });
    }
}

}  // namespace fray::cli
