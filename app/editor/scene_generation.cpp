#include "scene_generation.h"

#include <chrono>
#include <cstdio>

#include "fray/prep/json_reader.h"
#include "fray/prep/pipeline.h"
#include "fray/render/image.h"
#include "fray/pipeline/setup_run.h"
#include "fray/setup/graph_setup.h"
#include "fray/setup/convert.h"
#include "fray/sim/compose.h"
#include "fray/sim/compose/domino.h"
#include "fray/sim/patterns.h"
#include "fray/sim/planner.h"
#include "fray/sim/spec.h"

namespace fray::editor {

namespace fs = std::filesystem;

namespace {

ProgressFn stage(const ProgressFn& progress, double from, double to) {
    if (!progress) return {};
    return [=](double f, std::string_view name) { return progress(from + (to - from) * f, name); };
}

// The patch library a composition draws on: the one given, else the
// project's file, else generated from the project's PatternLists (or the
// defaults the actions can play, as `fray-cli patches generate` does).
Result<std::shared_ptr<const sim::PatchLibrary>> compositionPatches(const GenerateInput& in, pipeline::SimSession& s,
                                                                    const ProgressFn& progress) {
    if (in.patches) {
        if (in.patches->libraryKey() != sim::libraryFingerprint(s.library))
            return makeError("the patches were generated from other actions than the project's now: generate patches again "
                             "(PatternLists panel)");
        return in.patches;
    }
    const fs::path file = patchLibraryFile(in.projectFile);
    std::error_code ec;
    if (fs::exists(file, ec)) {
        auto loaded = sim::loadPatchLibrary(file, s.library);
        if (!loaded) return loaded.error();
        return std::shared_ptr<const sim::PatchLibrary>(std::make_shared<sim::PatchLibrary>(std::move(*loaded)));
    }
    auto set = sim::projectPatterns(s.session.project, in.projectFile.filename().string());
    if (!set) return set.error();
    if (set->patterns.empty()) {
        for (auto& p : sim::defaultPatterns())
            if (sim::checkPattern(p, *set, s.library)) set->patterns.push_back(std::move(p));
    }
    auto generated = generatePatchLibrary(s.library, *set, {}, progress);
    if (!generated) return generated.error();
    return std::shared_ptr<const sim::PatchLibrary>(generated->library);
}

}  // namespace

Result<std::unique_ptr<pipeline::SimSession>> prepareSimSession(const prep::Project& project, const fs::path& file,
                                                                const ProgressFn& progress) {
    auto out = std::make_unique<pipeline::SimSession>();
    pipeline::Session& s = out->session;
    s.file = file;
    s.project = project;
    s.asLoaded = project;
    auto motions = prep::loadProjectMotions(project, file, pipeline::loadProjectMotion, stage(progress, 0.0, 0.5));
    if (!motions) return motions.error();
    s.motions = std::move(*motions);
    std::string why;
    s.cache = prep::readCache(file, &why);
    auto contacts = pipeline::computeContacts(s, false, stage(progress, 0.5, 0.7));
    if (!contacts) return contacts.error();
    auto graph = pipeline::projectGraph(s, "", 0.0, stage(progress, 0.7, 0.9));
    if (!graph) return graph.error();
    out->graph = std::move(*graph);
    auto lib = sim::buildActionLibrary(s.project, s.motions, out->graph.graph, stage(progress, 0.9, 1.0));
    if (!lib) return makeError(file.string() + ": " + lib.error().message);
    out->library = std::move(*lib);
    return out;
}

bool sessionServes(const pipeline::SimSession& session, const prep::Project& project) {
    prep::Project a = session.session.project, b = project;
    a.laterSections.clear();
    b.laterSections.clear();
    return a == b;
}

fs::path patchLibraryFile(const fs::path& projectFile) { return fs::path(projectFile.string() + ".patches"); }

bool isComposeSpec(const std::string& specText) {
    auto j = prep::parseJson(specText, "spec");
    return j && j->is_object() && j->contains("kind");
}

Result<sim::FloorBitmap> loadFloorBitmapPng(const fs::path& file, double metresPerPixel, glm::vec2 origin) {
    auto image = render::readPng(file);
    if (!image) return image.error();
    sim::FloorBitmap floor;
    floor.width = image->width, floor.height = image->height;
    floor.metresPerPixel = metresPerPixel;
    floor.origin = origin;
    floor.painted.assign(static_cast<std::size_t>(floor.width) * static_cast<std::size_t>(floor.height), 0);
    std::size_t count = 0;
    for (int y = 0; y < image->height; ++y) {
        for (int x = 0; x < image->width; ++x) {
            const std::uint8_t* px = image->pixel(x, y);
            if (px[3] < 128) continue;
            const int luma = (299 * px[0] + 587 * px[1] + 114 * px[2]) / 1000;
            if (luma > 64 && luma < 192) {
                char colour[8];
                std::snprintf(colour, sizeof colour, "#%02x%02x%02x", px[0], px[1], px[2]);
                return makeError(file.string() + ": not a two-colour image: pixel (" + std::to_string(x) + ", " +
                                 std::to_string(y) + ") is " + colour + "; paint the area in black on white (or on transparent)");
            }
            if (luma <= 64) {
                floor.painted[static_cast<std::size_t>(y) * static_cast<std::size_t>(floor.width) + static_cast<std::size_t>(x)] = 1;
                ++count;
            }
        }
    }
    if (count == 0) return makeError(file.string() + ": nothing is painted (paint the area in black on white)");
    return floor;
}

Result<PatchGeneration> generatePatchLibrary(const sim::ActionLibrary& lib, const sim::PatternSet& set,
                                             const std::vector<std::string>& names, const ProgressFn& progress) {
    std::vector<const sim::PatternList*> chosen;
    for (const std::string& n : names) {
        const sim::PatternList* p = set.find(n);
        if (!p) return makeError("no PatternList named '" + n + "'");
        chosen.push_back(p);
    }
    if (chosen.empty())
        for (const sim::PatternList& p : set.patterns) chosen.push_back(&p);
    if (chosen.empty()) return makeError("there are no PatternLists to generate patches from");
    for (const sim::PatternList* p : chosen)
        if (Status st = sim::checkPattern(*p, set, lib); !st) return st.error();
    PatchGeneration out;
    out.library = std::make_shared<sim::PatchLibrary>();
    sim::GenerateOptions options;
    const double n = static_cast<double>(chosen.size());
    for (std::size_t i = 0; i < chosen.size(); ++i) {
        const sim::GenerateStats before = out.library->stats();
        const double from = 0.9 * static_cast<double>(i) / n, to = 0.9 * static_cast<double>(i + 1) / n;
        if (Status st = sim::generatePatches(lib, *chosen[i], set, *out.library, options, stage(progress, from, to)); !st)
            return st.error();
        out.perPattern.emplace_back(chosen[i]->name, out.library->stats().since(before));
    }
    if (!reportProgress(progress, 0.92, "connection tables")) return cancelled();
    sim::buildConnections(lib, *out.library);
    reportProgress(progress, 1.0, "done");
    return out;
}

QString discardReasons(const sim::GenerateStats& s) {
    return QString("%1 initial conditions, %2 paths: %3 kept; discarded %4 too close, %5 wrong order, %6 unintended hits, "
                   "%7 missed contacts, %8 below the threshold, %9 near duplicates")
        .arg(s.initialConditions)
        .arg(s.paths)
        .arg(s.kept)
        .arg(s.tooClose)
        .arg(s.wrongOrder)
        .arg(s.unintendedHit)
        .arg(s.missedContact)
        .arg(s.belowThreshold)
        .arg(s.duplicates);
}

Result<GeneratedScene> generateScene(const GenerateInput& in, const ProgressFn& progress) {
    // The spec text of a setup (its trajectories written in), or the file's.
    std::string specText = in.specText;
    std::string specName = in.specName;
    if (in.setup) {
        auto text = setup::setupSpecJson(*in.setup);
        if (!text) return text.error();
        specText = std::move(*text);
        specName = "setup '" + in.setup->name + "'";
    } else if (auto j = prep::parseJson(specText, specName); !j) {
        return j.error();  // syntax first (line and column), before any project work
    }
    std::shared_ptr<pipeline::SimSession> shared;
    if (in.cachedSession && in.cachedSession->session.file == in.projectFile && sessionServes(*in.cachedSession, in.project)) {
        shared = in.cachedSession;
        shared->session.project = in.project;  // setups, PatternLists, presets as they are now
    } else {
        auto session = prepareSimSession(in.project, in.projectFile, stage(progress, 0.0, 0.3));
        if (!session) return session.error();
        shared = std::move(*session);
        if (in.plans) in.plans->clear();  // planned on another library
    }
    pipeline::SimSession& s = *shared;
    GeneratedScene out;
    const auto t0 = std::chrono::steady_clock::now();
    const bool compose = in.setup ? !setup::isSimulateKind(in.setup->kind) : isComposeSpec(specText);
    if (in.setup) {
        // The one path of `fray-cli simulate/compose --setup` (its rejected patches left out).
        std::shared_ptr<const sim::PatchLibrary> patches;
        if (pipeline::setupNeedsPatches(*in.setup)) {
            auto p = compositionPatches(in, s, stage(progress, 0.3, 0.6));
            if (!p) return p.error();
            patches = *p;
        }
        out.patches = patches;
        pipeline::SetupRunStats st;
        const bool graph = setup::isGraphKind(in.setup->kind);
        // A graph setup's graph may be built here (seconds to minutes): most of the bar.
        auto scene = pipeline::runSetup(s, *in.setup, patches.get(), stage(progress, graph ? 0.3 : 0.6, 0.95), &st, in.graphs.get(),
                                        in.plans.get());
        if (!scene) return scene.error();
        if (in.plans && setup::isTreeExpansion(in.setup->kind)) out.replan = st.replan;
        const auto& g = st.graph;
        out.summary = graph ? QString("%1 '%2': %3 characters, %4 s, %5 decisions (%6 off the graph), %7 hits; graph: %8")
                                  .arg(setup::setupKindName(in.setup->kind))
                                  .arg(QString::fromStdString(in.setup->name))
                                  .arg(scene->characters.size())
                                  .arg(scene->duration, 0, 'f', 1)
                                  .arg(g.decisions)
                                  .arg(g.offGraph)
                                  .arg(scene->hits.size())
                                  .arg(QString::fromStdString(g.graphSource))
                    : compose ? QString("%1 '%2': %3 characters, %4 s, %5 hits; %6 patches")
                                    .arg(setup::setupKindName(in.setup->kind))
                                    .arg(QString::fromStdString(in.setup->name))
                                    .arg(scene->characters.size())
                                    .arg(scene->duration, 0, 'f', 1)
                                    .arg(scene->hits.size())
                                    .arg(st.compose.patchesUsed)
                              : QString("%1 '%2': %3 characters, %4 s, %5 decisions, %6 hits")
                                    .arg(setup::setupKindName(in.setup->kind))
                                    .arg(QString::fromStdString(in.setup->name))
                                    .arg(scene->characters.size())
                                    .arg(scene->duration, 0, 'f', 1)
                                    .arg(scene->stats.decisions)
                                    .arg(scene->hits.size());
        if (!in.setup->pins.empty() && setup::isTreeExpansion(in.setup->kind)) {
            out.summary += QString(", %1 pinned").arg(in.setup->pins.size());
        }
        if (in.setup->kind == setup::SetupKind::GraphCarry) {
            out.summary += QString("; path error mean %1 m, max %2 m; hands within %3 % of the box")
                               .arg(g.pathErrorMean, 0, 'f', 3)
                               .arg(g.pathErrorMax, 0, 'f', 2)
                               .arg(100.0 * g.gripErrorMax, 0, 'f', 2);
        } else if (graph) {
            out.summary += QString("; landed %1 (red) vs %2 (blue)").arg(g.landedRed).arg(g.landedBlue);
        }
        if (!g.note.empty()) out.summary += "; note: " + QString::fromStdString(g.note);
        // Compose kinds cannot honour pins: said, never silent.
        if (const std::string note = setup::pinsNotHonoured(*in.setup); !note.empty()) out.summary += "; " + QString::fromStdString(note);
        out.loaded.scene = std::move(*scene);
    } else if (compose) {
        std::shared_ptr<const sim::PatchLibrary> patches;
        if (sim::composeNeedsPatches(specText)) {
            auto p = compositionPatches(in, s, stage(progress, 0.3, 0.6));
            if (!p) return p.error();
            patches = *p;
        }
        out.patches = patches;
        std::vector<int> rejected = in.rejected;
        std::sort(rejected.begin(), rejected.end());
        rejected.erase(std::unique(rejected.begin(), rejected.end()), rejected.end());
        sim::PatchLibrary used;
        if (patches) {
            if (rejected.empty()) {
                used = *patches;
            } else {
                auto kept = setup::withoutRejected(*patches, rejected);
                if (!kept) return kept.error();
                used = std::move(*kept);
            }
        }
        auto spec = sim::parseComposeSpec(specText, specName, used);
        if (!spec) return spec.error();
        if (auto* domino = spec->part<sim::DominoSpec>(); domino && !domino->floorFile.empty()) {
            fs::path bitmap(domino->floorFile);
            if (bitmap.is_relative()) bitmap = in.specDir / bitmap;
            auto floor = loadFloorBitmapPng(bitmap, domino->metresPerPixel, domino->floorOrigin);
            if (!floor) return floor.error();
            domino->floor = std::move(*floor);
        }
        sim::ComposeStats st;
        auto scene = sim::compose(s.library, used, *spec, &st, stage(progress, 0.6, 0.95));
        if (!scene) return makeError(specName + ": " + scene.error().message);
        out.summary = QString("%1: %2 characters, %3 s, %4 hits; %5 patches")
                          .arg(QString::fromStdString(spec->kind))
                          .arg(scene->characters.size())
                          .arg(scene->duration, 0, 'f', 1)
                          .arg(scene->hits.size())
                          .arg(st.patchesUsed);
        out.loaded.scene = std::move(*scene);
    } else {
        auto presets = sim::projectPresets(s.session.project, in.projectFile.filename().string());
        if (!presets) return presets.error();
        auto spec = sim::parseSceneSpec(specText, specName, s.library, *presets);
        if (!spec) return spec.error();
        sim::ReplanInfo replan;
        auto scene = in.plans ? sim::simulate(s.library, s.session.project.combos, *spec, *in.plans, stage(progress, 0.3, 0.95), &replan)
                              : sim::simulate(s.library, s.session.project.combos, *spec, stage(progress, 0.3, 0.95));
        if (!scene) return makeError(specName + ": " + scene.error().message);
        if (in.plans) out.replan = replan;
        out.summary = QString("tree expansion: %1 characters, %2 s, %3 decisions, %4 hits")
                          .arg(scene->characters.size())
                          .arg(scene->duration, 0, 'f', 1)
                          .arg(scene->stats.decisions)
                          .arg(scene->hits.size());
        out.loaded.scene = std::move(*scene);
    }
    out.loaded.scene.project = in.projectFile.filename().string();
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!reportProgress(progress, 0.96, "metrics")) return cancelled();
    out.metrics = sim::computeMetrics(out.loaded.scene, s.library);
    // The stage gets its own copy of the library (it outlives the next generate's use of the session).
    out.loaded.session = std::make_unique<pipeline::SimSession>();
    out.loaded.session->library = s.library;
    out.session = std::move(shared);
    reportProgress(progress, 1.0, "done");
    return out;
}

GanttData ganttFromScene(const sim::Scene& scene, const sim::ActionLibrary& lib, const std::function<QColor(int)>& tint) {
    GanttData d;
    d.duration = scene.duration;
    const auto& actions = lib.actions();
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        const sim::SceneCharacter& ch = scene.characters[c];
        GanttRow row;
        row.name = QString::fromStdString(ch.name);
        row.tint = tint ? tint(static_cast<int>(c)) : QColor(200, 200, 200);
        for (const sim::ActionInstance& inst : ch.track) {
            GanttBar bar;
            bar.start = inst.start;
            bar.end = inst.end;
            bar.forced = inst.forced;
            bar.fallback = inst.fallback;
            bar.action = inst.action;
            if (inst.action >= 0 && inst.action < static_cast<int>(actions.size())) {
                const sim::LibraryAction& a = actions[static_cast<std::size_t>(inst.action)];
                bar.label = QString::fromStdString(a.name.empty() ? (a.annotations.empty() ? a.label() : a.annotations.front()) : a.name);
                if (!a.annotations.empty()) bar.annotation = QString::fromStdString(a.annotations.front());
            }
            row.bars.push_back(bar);
        }
        d.rows.push_back(std::move(row));
    }
    for (const sim::HitEvent& h : scene.hits) d.hits.push_back({h.time, h.attacker, h.defender, h.blocked});
    return d;
}

void markPinnedBars(GanttData& gantt, const std::vector<setup::Pin>& pins) {
    for (std::size_t i = 0; i < pins.size(); ++i) {
        const setup::Pin& pin = pins[i];
        for (GanttRow& row : gantt.rows) {
            if (row.name != QString::fromStdString(pin.character)) continue;
            for (GanttBar& bar : row.bars) {
                if (bar.start < pin.time - sim::kPinEarly) continue;
                if (bar.start <= pin.time + sim::kPinLate && !bar.forced) bar.pin = static_cast<int>(i);
                break;
            }
        }
    }
}

QStringList metricsHeader() {
    return {"character", "actions", "hits", "received", "blocked", "catch (s)", "opponent (m)", "path error (m)",
            "penetration", "skate (cm)", "skate max (cm)", "fallbacks"};
}

std::vector<QStringList> metricsRows(const sim::SceneMetrics& m) {
    const auto opt = [](const std::optional<double>& v) { return v ? QString::number(*v, 'f', 2) : QString("-"); };
    std::vector<QStringList> rows;
    for (const sim::CharacterMetrics& c : m.characters) {
        rows.push_back({QString::fromStdString(c.name), QString::number(c.actions), QString::number(c.hitsGiven),
                        QString::number(c.hitsReceived), QString::number(c.blockedReceived), opt(c.timeToCatch),
                        opt(c.meanOpponentDistance), opt(c.pathErrorMean), QString::number(c.penetrationFrames),
                        QString::number(c.footSkateMean, 'f', 3), QString::number(c.footSkateMax, 'f', 2),
                        QString::number(c.fallbacks)});
    }
    return rows;
}

QString metricsSummary(const sim::SceneMetrics& m) {
    return QString("%1 s, %2 attacks, %3 hits (%4 %), %5 blocked, %6 penetration samples (%7 between groups)")
        .arg(m.duration, 0, 'f', 1)
        .arg(m.attacks)
        .arg(m.hits)
        .arg(100.0 * m.hitRate, 0, 'f', 0)
        .arg(m.blocked)
        .arg(m.penetrationFrames)
        .arg(m.crossGroupPenetrations);
}

}  // namespace fray::editor
