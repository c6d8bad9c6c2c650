#pragma once
// Generate and preview (issue 23): what the editor's "Generate" runs in a
// worker thread, plain C++ over the pipeline library (no widgets): the
// project as the document holds it now (unsaved edits included) prepared for
// the planners, then a scene spec planned by tree expansion (`fray-cli
// simulate`) or composed from Interaction Patches (`fray-cli compose`), and
// the figures of `fray-cli metrics` for it. Also the Gantt track's rows of a
// scene and the patch library generation of the PatternList editor.
#include <QColor>
#include <QString>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/pipeline/graph_setup.h"
#include "fray/pipeline/sim_session.h"
#include "fray/prep/project.h"
#include "fray/setup/scene_setup.h"
#include "fray/sim/metrics.h"
#include "fray/sim/patches.h"
#include "fray/sim/planner.h"
#include "fray/sim/scene.h"
#include "gantt_view.h"
#include "scene_stage.h"

namespace fray::editor {

// The project prepared for the planners from a snapshot of the document:
// motions loaded, contacts and motion graph from the cache beside the project
// when fresh (the cache is read, never written), the action library built.
Result<std::unique_ptr<pipeline::SimSession>> prepareSimSession(const prep::Project& project,
                                                                const std::filesystem::path& file,
                                                                const ProgressFn& progress);

struct GenerateInput {
    std::filesystem::path projectFile;  // where the project lives (relative motion paths, the cache)
    prep::Project project;              // the document's project now
    // A scene setup of the project (planned or composed as its kind says), or
    // else a spec file's text: a simulate spec (characters...) or a compose spec ("kind").
    std::optional<setup::SceneSetup> setup;
    std::string specText;
    std::string specName;               // for messages ("duel.json")
    std::filesystem::path specDir;      // a compose spec's floor bitmap is relative to it
    // The patch library a compose spec draws on (null: the project's library
    // file, PROJECT.patches, when there is one, else generated here from the
    // project's PatternLists or the default ones).
    std::shared_ptr<const sim::PatchLibrary> patches;
    // Patches (indices into the library) the compose must not use; a setup's
    // rejected patches are added to them.
    std::vector<int> rejected;
    // A session prepared by an earlier generate (may be null): reused, with
    // the project snapshot put in, when the project's motions, actions and
    // settings are the same (only setups, PatternLists and other later
    // sections differ); else replaced by a fresh one. Only one job uses it at
    // a time.
    std::shared_ptr<pipeline::SimSession> cachedSession;
    // Interaction graphs built in memory by earlier generates (graph setups; may be null).
    std::shared_ptr<pipeline::GraphCache> graphs;
    // The last tree-expansion run (duel, chase; may be null): a live re-plan
    // resumes it where the edit cannot reach (sim::PlanCache). Cleared when
    // the session is replaced; only one job uses it at a time.
    std::shared_ptr<sim::PlanCache> plans;
};

struct GeneratedScene {
    pipeline::LoadedScene loaded;  // its session holds a copy of the action library
    std::shared_ptr<pipeline::SimSession> session;  // the session used, for the next generate
    sim::SceneMetrics metrics;
    std::shared_ptr<const sim::PatchLibrary> patches;  // the library composed from (may be generated here)
    QString summary;                                  // one line for the status bar
    double seconds = 0;                               // planning or composing, wall clock
    std::optional<sim::ReplanInfo> replan;            // tree expansion with GenerateInput::plans: how much was kept
};

// A generated scene as the window shows it, prepared in the worker thread:
// the posed stage, the Gantt rows, the metrics.
struct PreparedPreview {
    std::unique_ptr<cli::SceneStage> stage;
    GanttData gantt;
    std::vector<setup::Pin> pins;  // the setup's pins it was planned with (marked in gantt)
    sim::SceneMetrics metrics;
    QString summary;
    std::shared_ptr<pipeline::SimSession> session;  // kept for the next generate
    std::optional<sim::ReplanInfo> replan;
};

// Marks the bars the setup's pins chose (GanttBar::pin): for each pin, the
// first bar of its character's row that starts at or after its time less
// sim::kPinEarly, when that bar starts by its time plus sim::kPinLate.
void markPinnedBars(GanttData& gantt, const std::vector<setup::Pin>& pins);

// The project's patch library file (as `fray-cli patches` writes it).
std::filesystem::path patchLibraryFile(const std::filesystem::path& projectFile);

// Whether a prepared session can serve this project: the same motions,
// actions, vocabulary, settings and combinations (setups, PatternLists and
// presets may differ).
bool sessionServes(const pipeline::SimSession& session, const prep::Project& project);

// True when the spec text is a compose spec (it has a "kind").
bool isComposeSpec(const std::string& specText);

Result<GeneratedScene> generateScene(const GenerateInput& input, const ProgressFn& progress);

// A painted floor area from a two-colour PNG (dark painted, light or
// transparent not); errors name the file and the problem.
Result<sim::FloorBitmap> loadFloorBitmapPng(const std::filesystem::path& file, double metresPerPixel, glm::vec2 origin);

// Patch generation for the PatternList editor: every PatternList of `set`
// (or only `names`), with the connection tables built.
struct PatchGeneration {
    std::shared_ptr<sim::PatchLibrary> library;
    std::vector<std::pair<std::string, sim::GenerateStats>> perPattern;
};
Result<PatchGeneration> generatePatchLibrary(const sim::ActionLibrary& lib, const sim::PatternSet& set,
                                             const std::vector<std::string>& names, const ProgressFn& progress);
// Why paths were discarded, in words ("12 too close, 3 wrong order, ...").
QString discardReasons(const sim::GenerateStats& s);

// The Gantt track's rows of a scene: one per character, an action's colour
// from its first annotation; `tint` gives each character's viewport colour.
GanttData ganttFromScene(const sim::Scene& scene, const sim::ActionLibrary& lib, const std::function<QColor(int)>& tint);

// The metrics as table rows: a header and one row per character (the
// columns of `fray-cli metrics`), and the scene line.
QStringList metricsHeader();
std::vector<QStringList> metricsRows(const sim::SceneMetrics& m);
QString metricsSummary(const sim::SceneMetrics& m);

}  // namespace fray::editor
