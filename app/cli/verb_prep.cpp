// Data-preparation verbs: project new, contacts, segment, actions, graph, combos.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/core/retarget.h"
#include "fray/io/import.h"
#include "fray/prep/annotations.h"
#include "fray/prep/contacts.h"
#include "fray/prep/json_reader.h"
#include "fray/prep/learning.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/segmentation.h"
#include "fray/prep/warnings.h"
#include "options.h"
#include "cli_session.h"
#include "verbs.h"

namespace fray::cli {
namespace {

namespace fs = std::filesystem;

// ---- project new ----------------------------------------------------------
// Takes on another skeleton than the first one's are retargeted onto it when
// the project is loaded (pipeline::loadSessionMotions); say now what maps to
// what, and refuse a take that cannot be retargeted.
Status reportRetarget(const Motion& motion, const std::string& id, std::optional<RetargetTarget>& skeleton) {
    if (!skeleton) {
        skeleton = pipeline::projectSkeletonTarget(motion, id);
        return {};
    }
    if (sameSkeleton(motion.skeleton(), skeleton->skeleton)) return {};
    RetargetReport report;
    auto r = retarget(motion, *skeleton, {}, &report);
    if (!r) return r.error();
    std::printf("%s\n", report.text().c_str());
    return {};
}

struct NewArgs {
    std::string project;
    std::vector<std::string> files;
    std::string units, up;
    bool force = false;
};

void runNew(const NewArgs& a) {
    const fs::path file(a.project);
    if (fs::exists(file) && !a.force) {
        return fail(a.project + ": already exists (use --force to replace it)");
    }
    if (!a.units.empty() && a.units != "m" && a.units != "cm" && a.units != "mm" && a.units != "inch" &&
        a.units != "cmu") {
        return fail("--units: expected m, cm, mm, inch or cmu, got '" + a.units + "'");
    }
    if (!a.up.empty() && a.up != "y" && a.up != "z") return fail("--up: expected y or z, got '" + a.up + "'");
    if (!prep::isValidUtf8(file.string())) return fail(a.project + ": the project's file name must be UTF-8 text");
    prep::Project p = prep::makeProject(file.stem().string());
    std::optional<RetargetTarget> skeleton;  // the project skeleton: the first motion's
    for (const auto& f : a.files) {
        std::error_code ec;
        if (fs::equivalent(f, file, ec)) return fail(a.project + ": is one of the imported captures; refusing to overwrite it");
        if (!prep::isValidUtf8(f)) {
            return fail(f + ": the file name is not UTF-8 text (the project stores paths as JSON text); rename the file");
        }
        prep::ProjectMotion m;
        m.units = a.units;
        m.up = a.up;
        auto motion = loadProjectMotion(f, m);
        if (!motion) return fail(motion.error().message);
        std::string id = fs::path(f).stem().string();
        for (int n = 2; p.findMotion(id); ++n) id = fs::path(f).stem().string() + "_" + std::to_string(n);
        m.id = id;
        m.path = prep::relativeMotionPath(file, f);
        m.actions = prep::MotionActions::whole(motion->frameCount());
        p.motions.push_back(std::move(m));
        std::fprintf(stderr, "fray-cli: imported %s (%d frames at %g fps)\n", f.c_str(), motion->frameCount(),
                     motion->fps());
        if (auto st = reportRetarget(*motion, p.motions.back().id, skeleton); !st) return fail(st.error().message);
    }
    if (auto st = prep::saveProject(p, file); !st) return fail(st.error().message);
    std::printf("%s: %zu motions\n", a.project.c_str(), p.motions.size());
}

// ---- contacts ---------------------------------------------------------------
struct ContactsArgs {
    std::string project, train;
    bool heuristic = false, quiet = false;
};

void runContacts(const ContactsArgs& a) {
    const auto progress = stderrProgress(a.quiet);
    auto s = openSession(a.project, true, progress);
    if (!s) return fail(s.error().message);
    if (!a.train.empty()) {
        if (auto st = importLabels(*s, a.train); !st) return fail(st.error().message);
    }
    auto summary = computeContacts(*s, a.heuristic, progress);
    if (!summary) return fail(summary.error().message);
    if (summary->svm && !summary->fromCache) {
        std::printf("svm: C %g gamma %g, leave-one-out accuracy %.2f %% on %d samples (%d support vectors), %.2f s\n",
                    summary->C, summary->gamma, 100.0 * summary->looAccuracy, summary->samples,
                    summary->supportVectors, summary->seconds);
    }
    std::printf("%-24s %8s %8s %8s %10s %s\n", "motion", "frames", "left%", "right%", "agree%", "source");
    for (const auto& m : s->motions) {
        const auto heuristic = prep::heuristicContacts(m.signals);
        auto share = [](const std::vector<std::uint8_t>& v) {
            return v.empty() ? 0.0 : 100.0 * double(std::count(v.begin(), v.end(), 1)) / double(v.size());
        };
        std::printf("%-24s %8d %8.1f %8.1f %10.1f %s%s\n", m.id.c_str(), m.signals.frameCount,
                    share(m.contacts.left), share(m.contacts.right),
                    100.0 * prep::contactAgreement(m.contacts, heuristic),
                    m.contactSource == prep::ContactSource::Svm ? "svm" : "heuristic",
                    summary->fromCache ? " (cached)" : "");
    }
    if (auto st = saveSession(*s); !st) return fail(st.error().message);
}

// Prints the project's warnings (prep::projectWarnings) on stderr.
void printWarnings(const prep::Project& project) {
    for (const auto& w : prep::projectWarnings(project)) {
        std::fprintf(stderr, "fray-cli: warning: %s\n", w.message.c_str());
    }
}

// ---- segment ----------------------------------------------------------------
struct SegmentArgs {
    std::string project, labels;
    double thresholdFactor = 0;
    bool heuristic = false, quiet = false;
};

void runSegment(const SegmentArgs& a) {
    const auto progress = stderrProgress(a.quiet);
    auto s = openSession(a.project, true, progress);
    if (!s) return fail(s.error().message);
    if (!a.labels.empty()) {
        if (auto st = importLabels(*s, a.labels); !st) return fail(st.error().message);
    }
    if (a.thresholdFactor > 0) s->project.settings.segmentThresholdFactor = a.thresholdFactor;
    auto summary = computeContacts(*s, a.heuristic, progress);
    if (!summary) return fail(summary.error().message);
    auto params = prep::segmentationParams(s->project.settings);
    // Learning from the user: actions they named or annotated keep their cuts
    // and refit the parameters used for everything else.
    std::vector<prep::SegmentationExample> examples;
    for (std::size_t i = 0; i < s->motions.size(); ++i) {
        auto e = prep::confirmedExamples(s->project.motions[i].actions, s->motions[i].signals, s->motions[i].contacts);
        examples.insert(examples.end(), e.begin(), e.end());
    }
    if (!examples.empty()) {
        const auto refit = prep::refitSegmentation(examples, params);
        params = refit.params;
        std::printf("learned from %d confirmed stretch%s (%d cuts): boundary F1 on them %.3f -> %.3f "
                    "(threshold factor %g, basin prominence %g, onset cap %g, still noise factor %g, "
                    "min phase %g s)\n",
                    refit.examples, refit.examples == 1 ? "" : "es", refit.trueCuts, refit.before.f1(),
                    refit.after.f1(), params.thresholdFactor, params.basinProminence, params.onsetCapFraction,
                    params.stillNoiseFactor, params.minPhaseSeconds);
    }
    std::printf("%-24s %8s %8s %10s\n", "motion", "frames", "actions", "mean (s)");
    int total = 0;
    for (std::size_t i = 0; i < s->motions.size(); ++i) {
        auto& m = s->motions[i];
        auto& entry = s->project.motions[i];
        reportProgress(progress, double(i) / double(s->motions.size()), "segment");
        const auto r = prep::segment(m.signals, m.contacts, params);
        entry.actions = prep::recut(entry.actions, prep::mergeWithConfirmed(entry.actions, r.cuts));
        prep::proposeAll(entry.actions, m.motion, m.joints, m.signals);
        total += entry.actions.actionCount();
        std::printf("%-24s %8d %8d %10.2f\n", entry.id.c_str(), m.signals.frameCount, entry.actions.actionCount(),
                    m.signals.frameCount / m.signals.fps / entry.actions.actionCount());
    }
    std::printf("total: %d actions\n", total);
    printWarnings(s->project);
    if (auto st = saveSession(*s); !st) return fail(st.error().message);
}

// ---- actions ----------------------------------------------------------------
struct ActionsArgs {
    std::string project, motion;
    bool json = false;
};

void runActions(const ActionsArgs& a) {
    auto s = openSession(a.project, false, {});
    if (!s) return fail(s.error().message);
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    bool found = a.motion.empty();
    for (const auto& m : s->project.motions) {
        if (!a.motion.empty() && m.id != a.motion) continue;
        found = true;
        for (int i = 0; i < m.actions.actionCount(); ++i) {
            const auto& info = m.actions.actions[static_cast<std::size_t>(i)];
            if (a.json) {
                out.push_back({{"motion", m.id},
                               {"index", i},
                               {"first_frame", m.actions.firstFrame(i)},
                               {"last_frame", m.actions.lastFrame(i)},
                               {"name", info.name},
                               {"annotations", info.annotations},
                               {"proposed", info.proposed},
                               {"joints", info.joints}});
            } else {
                std::string ann;
                for (const auto& w : info.annotations) ann += (ann.empty() ? "" : ",") + w;
                for (const auto& w : info.proposed) ann += (ann.empty() ? "" : ",") + w + "?";
                std::printf("%-20s %4d %7d %7d  %-16s %s\n", m.id.c_str(), i, m.actions.firstFrame(i),
                            m.actions.lastFrame(i), info.name.empty() ? "-" : info.name.c_str(), ann.c_str());
            }
        }
    }
    if (!found) return fail(a.project + ": no motion \"" + a.motion + "\"");
    if (a.json) std::printf("%s\n", out.dump(2).c_str());
}

// ---- graph ------------------------------------------------------------------
struct GraphArgs {
    std::string project, preset;
    double threshold = 0;
    bool json = false, quiet = false;
};

void runGraph(const GraphArgs& a) {
    const auto progress = stderrProgress(a.quiet);
    auto s = openSession(a.project, true, progress);
    if (!s) return fail(s.error().message);
    auto built = projectGraph(*s, a.preset, a.threshold, progress);
    if (!built) return fail(built.error().message);
    const auto& graph = built->graph;
    const bool cached = built->cached;
    const std::string& presetName = built->preset;
    const auto& options = built->options;
    const auto& st = graph.stats;
    if (a.json) {
        nlohmann::ordered_json j;
        j["preset"] = presetName;
        j["threshold"] = options.threshold;
        j["threshold_from_data"] = built->thresholdFromData;
        j["data_threshold"] = built->dataThreshold;
        j["nodes"] = st.nodes;
        j["edges"] = st.edges;
        j["mean_out_degree"] = st.meanOutDegree;
        j["max_out_degree"] = st.maxOutDegree;
        j["largest_scc_actions"] = st.largestSccActions;
        j["scc_share"] = st.sccShare;
        j["dead_ends"] = st.deadEnds;
        j["capture_continuations_added"] = graph.naturalEdges;
        j["from_cache"] = cached;
        j["start_node"] = graph.startNode;
        j["end_node"] = graph.endNode;
        std::printf("%s\n", j.dump(2).c_str());
    } else {
        std::printf("motion graph (%s, threshold %g): %d nodes, %d edges (actions), out-degree mean %.2f max %d,\n"
                    "largest strongly connected component: %d actions (%.1f %%), dead ends %d,\n"
                    "capture continuations added to Next(): %d%s\n",
                    presetName.c_str(), options.threshold, st.nodes, st.edges, st.meanOutDegree, st.maxOutDegree,
                    st.largestSccActions, 100.0 * st.sccShare, st.deadEnds, graph.naturalEdges, cached ? " (cached)" : "");
        if (built->thresholdFromData) {
            std::printf("threshold %.3f from the data (1.5 x the distance within which %.0f %% of action ends find a start; "
                        "the default %g joins too few of these poses); --threshold or the project's graph threshold "
                        "overrides it\n",
                        options.threshold, 100.0 * prep::kDataThresholdShare, prep::GraphOptions{}.threshold);
        }
    }
    printWarnings(s->project);
    if (cached) return;
    if (auto w = prep::writeCache(s->file, s->cache); !w) {
        std::fprintf(stderr, "fray-cli: warning: could not write the cache: %s\n", w.error().message.c_str());
    }
}

// ---- combos -----------------------------------------------------------------
struct CombosArgs {
    std::string project, action, file, mine, theirs, value;
    bool valueGiven = false;
};

Result<double> parseSuitability(const CombosArgs& a) {
    if (!a.valueGiven) return makeError("combos set: give MINE THEIRS VALUE (the suitability is missing)");
    double v = 0;
    const auto* end = a.value.data() + a.value.size();
    const auto [p, ec] = std::from_chars(a.value.data(), end, v);
    if (ec != std::errc() || p != end || !std::isfinite(v) || std::abs(v) > prep::kMaxSuitability) {
        return makeError("combos set: VALUE \"" + a.value + "\" must be a finite number between -1e6 and 1e6");
    }
    return v;
}

void runCombos(const CombosArgs& a) {
    if (a.action == "list" || a.action == "export") {
        auto s = openSession(a.project, false, {});
        if (!s) return fail(s.error().message);
        const auto& table = s->project.combos;
        if (a.action == "list") {
            std::printf("%-24s %-24s %s\n", "mine", "theirs", "suitability");
            for (const auto& r : table.records()) {
                std::printf("%-24s %-24s %g\n", r.mine.c_str(), r.theirs.c_str(), r.suitability);
            }
            return;
        }
        if (a.file.empty()) return fail("combos export: give the CSV file to write");
        if (auto st = checkOutputIsNotInput(s->file, s->project, a.file); !st) return fail(st.error().message);
        if (auto st = writeFileAtomically(a.file, table.toCsv()); !st) return fail(st.error().message);
        std::printf("%zu records -> %s\n", table.records().size(), a.file.c_str());
        return;
    }
    std::string done;
    const Status st = editProject(a.project, [&](prep::Project& project) -> Status {
        auto& table = project.combos;
        if (a.action == "import") {
            if (a.file.empty()) return makeError("combos import: give the CSV file to read");
            const auto text = readWholeFile(a.file, "the combination table");
            if (!text) return text.error();
            auto t = prep::ComboTable::fromCsv(*text, a.file, &project.vocabulary);
            if (!t) return t.error();
            for (const auto& r : t->records()) table.set(r);
            done = std::to_string(t->records().size()) + " records imported";
        } else if (a.action == "set") {
            if (a.mine.empty() || a.theirs.empty()) return makeError("combos set: give MINE THEIRS VALUE");
            auto v = parseSuitability(a);
            if (!v) return v.error();
            const prep::ComboRecord record{a.mine, a.theirs, *v};
            if (auto ok = prep::ComboTable::checkRecord(record, project.vocabulary); !ok) {
                return makeError("combos set: " + ok.error().message);
            }
            table.set(record);
        } else if (a.action == "remove") {
            if (!table.remove(a.mine, a.theirs)) return makeError("no record " + a.mine + " / " + a.theirs);
        } else {
            return makeError("combos: unknown action '" + a.action + "' (list, import, export, set, remove)");
        }
        return {};
    });
    if (!st) return fail(st.error().message);
    if (!done.empty()) std::printf("%s\n", done.c_str());
}

// ---- timeline ---------------------------------------------------------------
struct TimelineArgs {
    std::string project, motion, out;
};

// Per-frame data of thesis fig. 3.1: acceleration, high-acceleration periods,
// support feet and cuts. scripts/plot_timeline.py draws it.
void runTimeline(const TimelineArgs& a) {
    auto s = openSession(a.project, true, stderrProgress(true));
    if (!s) return fail(s.error().message);
    if (auto st = checkOutputIsNotInput(s->file, s->project, a.out); !st) return fail(st.error().message);
    auto summary = computeContacts(*s, false, {});
    if (!summary) return fail(summary.error().message);
    for (std::size_t i = 0; i < s->motions.size(); ++i) {
        if (s->motions[i].id != a.motion) continue;
        const auto& m = s->motions[i];
        const auto r = prep::segment(m.signals, m.contacts, prep::segmentationParams(s->project.settings));
        const auto& doc = s->project.motions[i].actions;
        std::string csv = "# motion " + m.id + ", fps " + std::to_string(m.signals.fps) + ", threshold " +
                          std::to_string(r.threshold) + "\nframe,acceleration,high,left,right,auto_cut,project_cut\n";
        for (int f = 0; f < m.signals.frameCount; ++f) {
            const auto k = static_cast<std::size_t>(f);
            const bool autoCut = std::binary_search(r.cuts.begin(), r.cuts.end(), f);
            const bool projectCut = std::binary_search(doc.cuts.begin(), doc.cuts.end(), f);
            csv += std::to_string(f) + "," + std::to_string(r.smoothed[k]) + "," + std::to_string(r.highAccel[k]) +
                   "," + std::to_string(m.contacts.left[k]) + "," + std::to_string(m.contacts.right[k]) + "," +
                   (autoCut ? "1" : "0") + "," + (projectCut ? "1" : "0") + "\n";
        }
        if (auto st = writeFileAtomically(a.out, csv); !st) return fail(st.error().message);
        std::printf("%s: %d frames, %zu automatic cuts, %zu project cuts\n", a.out.c_str(), m.signals.frameCount,
                    r.cuts.size(), doc.cuts.size());
        return;
    }
    fail(a.project + ": no motion \"" + a.motion + "\"");
}

}  // namespace

void registerPrep(CLI::App& app) {
    {
        auto args = std::make_shared<TimelineArgs>();
        auto* cmd = app.add_subcommand("timeline", "Write the per-frame segmentation timeline of a motion as CSV");
        cmd->add_option("project", args->project, "Project file")->required();
        cmd->add_option("motion", args->motion, "Motion id")->required();
        cmd->add_option("-o,--out", args->out, "CSV file to write")->required();
        cmd->callback([args] { runTimeline(*args); });
    }
    {
        auto* project = app.add_subcommand("project", "Create and manage Fray projects");
        project->require_subcommand(1);
        auto args = std::make_shared<NewArgs>();
        auto* cmd = project->add_subcommand("new", "Create a project from capture files");
        cmd->add_option("project", args->project, "Project file to create (*.frayproj)")->required();
        cmd->add_option("--import", args->files, "Capture files (BVH, FBX, glTF, ...)")->required()->expected(1, -1);
        cmd->add_option("--units", args->units, "Source units for every file: m, cm, mm, inch, cmu (default: detect)");
        cmd->add_option("--up", args->up, "Source up axis: y or z (default: detect)");
        cmd->add_flag("--force", args->force, "Replace an existing project file");
        cmd->callback([args] { runNew(*args); });
    }
    {
        auto args = std::make_shared<ContactsArgs>();
        auto* cmd = app.add_subcommand("contacts", "Foot contacts: train the SVM on labels, classify every frame");
        cmd->add_option("project", args->project, "Project file")->required();
        cmd->add_option("--train", args->train, "Labels CSV (motion,first_frame,last_frame,left,right) to train on");
        cmd->add_flag("--heuristic", args->heuristic, "Use the height/speed heuristic even when labels exist");
        cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
        cmd->callback([args] { runContacts(*args); });
    }
    {
        auto args = std::make_shared<SegmentArgs>();
        auto* cmd = app.add_subcommand("segment", "Segment every motion into actions and propose annotations");
        cmd->add_option("project", args->project, "Project file")->required();
        cmd->add_option("--labels", args->labels, "Contact labels CSV to import first (trains the SVM)");
        cmd->add_option("--threshold-factor", args->thresholdFactor,
                        "High-acceleration threshold as a multiple of the median (default 12)")
            ->check(finitePositive(1000));
        cmd->add_flag("--heuristic", args->heuristic, "Heuristic contacts even when labels exist");
        cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
        cmd->callback([args] { runSegment(*args); });
    }
    {
        auto args = std::make_shared<ActionsArgs>();
        auto* cmd = app.add_subcommand("actions", "List the actions of a project");
        cmd->add_option("project", args->project, "Project file")->required();
        cmd->add_option("--motion", args->motion, "Only this motion (id)");
        cmd->add_flag("--json", args->json, "JSON output");
        cmd->callback([args] { runActions(*args); });
    }
    {
        auto args = std::make_shared<GraphArgs>();
        auto* cmd = app.add_subcommand("graph", "Build the action-level motion graph and print its statistics");
        cmd->add_option("project", args->project, "Project file")->required();
        cmd->add_option("--preset", args->preset, "Pose-distance weights: fighting or locomotion (default: project)");
        cmd->add_option("--threshold", args->threshold, "Largest within-node pose distance")->check(finitePositive(1e6));
        cmd->add_flag("--json", args->json, "JSON output");
        cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
        cmd->callback([args] { runGraph(*args); });
    }
    {
        auto args = std::make_shared<CombosArgs>();
        auto* cmd = app.add_subcommand("combos", "Action combination table: list, import, export, set, remove");
        cmd->add_option("project", args->project, "Project file")->required();
        cmd->add_option("action", args->action, "list | import CSV | export CSV | set MINE THEIRS VALUE | remove MINE THEIRS")
            ->required();
        cmd->add_option("args", args->file, "CSV file (import/export) or MINE (set/remove)");
        cmd->add_option("theirs", args->theirs, "THEIRS (set/remove)");
        auto* value = cmd->add_option("value", args->value, "Suitability (set): a finite number within +-1e6");
        cmd->callback([args, value] {
            CombosArgs a = *args;
            a.valueGiven = value->count() > 0;
            if (a.action == "set" || a.action == "remove") a.mine = a.file;
            runCombos(a);
        });
    }
}

}  // namespace fray::cli
