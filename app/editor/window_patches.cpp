// MainWindow: the PatternList editor and the patch browser (issue 23). The
// PatternLists are the project's (its "pattern_lists" section); patches are
// generated from them in the background and kept in memory with the action
// library they were made from; selecting one plays it looping in the viewport;
// a compose spec composes from them, without the rejected ones.
#include <QDockWidget>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QStatusBar>
#include <QUndoStack>
#include <cstdio>
#include <fstream>

#include "fray/authoring/project_document.h"
#include "gantt_view.h"
#include "main_window.h"
#include "patch_browser.h"
#include "patterns_panel.h"
#include "scene_generation.h"

namespace fray::editor {

namespace {

QString qs(const std::string& s) { return QString::fromStdString(s); }

}  // namespace

void MainWindow::buildPatchDocks() {
    patterns_ = new PatternsPanel;
    patterns_->setObjectName("patternsPanel");
    patternsDock_ = new QDockWidget("PatternLists", this);
    patternsDock_->setObjectName("PatternsDock");
    patternsDock_->setWidget(patterns_);
    addDockWidget(Qt::RightDockWidgetArea, patternsDock_);
    tabifyDockWidget(inspectorDock_, patternsDock_);

    patchBrowser_ = new PatchBrowser;
    patchBrowser_->setObjectName("patchBrowser");
    patchesDock_ = new QDockWidget("Patches", this);
    patchesDock_->setObjectName("PatchesDock");
    patchesDock_->setWidget(patchBrowser_);
    addDockWidget(Qt::BottomDockWidgetArea, patchesDock_);
    tabifyDockWidget(combosDock_, patchesDock_);
    inspectorDock_->raise();
    timelineDock_->raise();

    // Every request is one undo command on the document (its change event refills the panel).
    const auto doc = [this] { return doc_.get(); };
    const auto str = [](const QString& s) { return s.toStdString(); };
    connect(patterns_, &PatternsPanel::patternAddRequested, this,
            [this, doc, str](const QString& name, const sim::PatternEntry& first) {
        if (!doc()) return;
        sim::PatternList p;
        p.name = str(name);
        p.entries.push_back(first);
        p.entries.push_back(sim::PatternEntry{1, "any"});
        reportStatus(doc()->addPattern(p));
    });
    connect(patterns_, &PatternsPanel::patternRemoveRequested, this,
            [this, doc, str](const QString& name) { if (doc()) reportStatus(doc()->removePattern(str(name))); });
    connect(patterns_, &PatternsPanel::rowAddRequested, this,
            [this, doc, str](const QString& name, int index, const sim::PatternEntry& row) {
                if (doc()) reportStatus(doc()->addPatternRow(str(name), index, row));
            });
    connect(patterns_, &PatternsPanel::rowRemoveRequested, this,
            [this, doc, str](const QString& name, int index) { if (doc()) reportStatus(doc()->removePatternRow(str(name), index)); });
    connect(patterns_, &PatternsPanel::rowMoveRequested, this, [this, doc, str](const QString& name, int from, int to) {
        if (doc()) reportStatus(doc()->movePatternRow(str(name), from, to));
    });
    connect(patterns_, &PatternsPanel::weightsRequested, this, [this, doc, str](const QString& name, const sim::PatternWeights& w) {
        if (doc()) reportStatus(doc()->setPatternWeights(str(name), w));
    });
    connect(patterns_, &PatternsPanel::thresholdRequested, this, [this, doc, str](const QString& name, double t) {
        if (doc()) reportStatus(doc()->setPatternThreshold(str(name), t));
    });
    connect(patterns_, &PatternsPanel::rangeRequested, this, [this, doc, str](const QString& word, const sim::InitialRange& r) {
        if (doc()) reportStatus(doc()->setInitialRange(str(word), r));
    });
    connect(patterns_, &PatternsPanel::generateRequested, this, &MainWindow::generatePatches);
    connect(patchBrowser_, &PatchBrowser::patchSelected, this, &MainWindow::previewPatch);
    connect(patchBrowser_, &PatchBrowser::handMadeRequested, this, &MainWindow::showHandMadeDialog);
    connect(patchBrowser_, &PatchBrowser::rejectRequested, this,
            [this](const std::vector<int>& patches, bool reject) { setPatchesRejected(patches, reject); });
}

void MainWindow::reportStatus(const Status& s) {
    if (s) return;
    editFailed(qs(s.error().message));
    lastError_ = qs(s.error().message);
    fillPatterns();  // the panel shows the document's set again
}

std::vector<int> MainWindow::rejectedPatches() const {
    if (!doc_) return {};
    const QString name = currentSetup();
    if (name.isEmpty()) return {};
    auto s = doc_->sceneSetup(name.toStdString());
    return s ? s->patches.rejected : std::vector<int>{};
}

void MainWindow::setPatchesRejected(const std::vector<int>& patches, bool reject) {
    const QString name = currentSetup();
    if (!doc_ || patches.empty()) return;
    if (name.isEmpty()) {
        showError("Patches", "Keep and reject are stored in a scene setup: select one in the Scene panel (or import a spec as one)");
        return;
    }
    // Several patches: one undo step.
    QUndoStack* stack = doc_->undoStack();
    if (patches.size() > 1)
        stack->beginMacro(QString("%1 %2 patches in '%3'").arg(reject ? "Reject" : "Keep").arg(patches.size()).arg(name));
    for (int p : patches) {
        const Status st = doc_->setPatchVerdict(name.toStdString(), p,
                                                reject ? authoring::ProjectDocument::Verdict::Reject
                                                       : authoring::ProjectDocument::Verdict::Keep);
        if (!st) {
            reportStatus(st);
            break;
        }
    }
    if (patches.size() > 1) stack->endMacro();
    patchBrowser_->setRejected(rejectedPatches());
}

void MainWindow::fillPatterns() {
    if (!patterns_) return;
    if (!doc_) {
        patterns_->setPatterns({}, {});
        return;
    }
    auto set = doc_->patternSet();
    if (!set) {
        patterns_->setPatterns({}, {});
        patterns_->setReport("The project's PatternLists cannot be read: " + qs(set.error().message));
        return;
    }
    QStringList words;
    for (const std::string& w : doc_->project().vocabulary) words << qs(w);
    for (const char* group : {"attack", "defence", "fall", "any"})
        if (!words.contains(group)) words << group;
    patterns_->setPatterns(*set, words);
    patterns_->setGenerating(jobThread_ != nullptr);
}

void MainWindow::generatePatches(const QStringList& names) {
    if (!doc_) return;
    auto set = doc_->patternSet();
    if (!set) {
        showError("Generate patches", qs(set.error().message));
        return;
    }
    std::vector<std::string> chosen;
    for (const QString& n : names) chosen.push_back(n.toStdString());
    // A project without PatternLists: the default ones its actions can play
    // (as `fray-cli patches generate`), checked in the worker.
    const bool defaults = set->patterns.empty();
    if (defaults) set->patterns = sim::defaultPatterns();
    const prep::Project snapshot = doc_->project();
    const std::filesystem::path file = projectFile_.toStdString();
    struct Out {
        std::optional<Result<PatchGeneration>> generated;
        std::shared_ptr<pipeline::SimSession> session;
        std::string saveError;
    };
    auto out = std::make_shared<Out>();
    auto clock = std::make_shared<QElapsedTimer>();
    clock->start();
    patterns_->setReport("Generating patches...");
    const bool started = startJob(
        "generating patches",
        [out, snapshot, file, set = *set, chosen, defaults](const ProgressFn& progress) mutable {
            const auto prepare = [&](double f, std::string_view s) { return progress ? progress(0.3 * f, s) : true; };
            auto session = prepareSimSession(snapshot, file, prepare);
            if (!session) {
                out->generated.emplace(session.error());
                return;
            }
            const auto work = [&](double f, std::string_view s) { return progress ? progress(0.3 + 0.7 * f, s) : true; };
            if (defaults) {
                std::vector<sim::PatternList> playable;
                for (auto& p : set.patterns)
                    if (sim::checkPattern(p, set, (*session)->library)) playable.push_back(std::move(p));
                set.patterns = std::move(playable);
            }
            out->generated.emplace(generatePatchLibrary((*session)->library, set, chosen, work));
            out->session = std::move(*session);
            // The project's patch library file: setups' keep/reject verdicts
            // name its patches (as `fray-cli patches list` numbers them).
            if (*out->generated) {
                const std::filesystem::path lib = patchLibraryFile(file);
                std::error_code ec;
                if (std::filesystem::exists(lib, ec)) {
                    std::ifstream in(lib, std::ios::binary);
                    char magic[8] = {};
                    in.read(magic, 8);
                    if (std::string(magic, 8) != "FRAYPTCH")
                        out->saveError = lib.string() + ": exists and is not a Fray patch library; not overwritten";
                }
                if (out->saveError.empty())
                    if (Status st = sim::savePatchLibrary(*(*out->generated)->library, lib); !st) out->saveError = st.error().message;
            }
        },
        [this, out, clock] {
            patterns_->setGenerating(false);
            if (!out->generated || !*out->generated) {
                const bool wasCancelled = out->generated && out->generated->error().isCancelled();
                const QString why = out->generated ? qs(out->generated->error().message) : QString("no result");
                patterns_->setReport(wasCancelled ? "Generating patches cancelled." : "Generating patches failed: " + why);
                if (!wasCancelled) showError("Generate patches", why);
                return;
            }
            PatchGeneration& g = out->generated->value();
            patchSession_ = out->session;
            patchLibrary_ = g.library;
            patchGenerated_ = g.library;
            handMadeApplied_.clear();
            rebuildPatchLibrary();  // the project's hand-made patches after the generated ones
            QStringList lines;
            for (const auto& [name, stats] : g.perPattern) lines << "<b>" + qs(name).toHtmlEscaped() + "</b>: " + discardReasons(stats);
            patterns_->setReport(lines.join("<br>") + QString("<br>%1 patches in %2 s").arg(g.library->patches().size()).arg(
                                                          static_cast<double>(clock->elapsed()) / 1000.0, 0, 'f', 2));
            if (!out->saveError.empty()) showError("Generate patches", qs(out->saveError));
            patchBrowser_->setPatches(patchLibrary_, &patchSession_->library);
            patchBrowser_->setRejected(rejectedPatches());
            patchesDock_->show();
            patchesDock_->raise();
            statusBar()->showMessage(QString("Generated %1 patches").arg(g.library->patches().size()), 10000);
            std::printf("fray: generated %zu patches\n", g.library->patches().size());
            std::fflush(stdout);
        });
    if (started) patterns_->setGenerating(true);
}

void MainWindow::previewPatch(int patch) {
    if (patch < 0 || !patchLibrary_ || !patchSession_ || patch >= static_cast<int>(patchLibrary_->patches().size())) return;
    if (jobThread_) {
        statusBar()->showMessage(jobName_ + " is running: the patch plays once it is done", 5000);
        return;
    }
    const sim::Patch& p = patchLibrary_->patches()[static_cast<std::size_t>(patch)];
    // The patch as a two-character scene (its own frame: character 1 starts at
    // the origin facing +Z); playback loops over its duration.
    pipeline::LoadedScene loaded;
    loaded.session = std::make_unique<pipeline::SimSession>();
    loaded.session->library = patchSession_->library;
    sim::Scene& scene = loaded.scene;
    scene.duration = p.duration;
    for (int c = 0; c < 2; ++c) {
        sim::SceneCharacter ch;
        ch.name = "character " + std::to_string(c + 1);
        ch.side = c;
        ch.group = 0;
        ch.track = p.tracks[static_cast<std::size_t>(c)];
        scene.characters.push_back(std::move(ch));
    }
    scene.hits = p.hits;
    const QString title = QString("patch %1 (%2, score %3)")
                              .arg(patch)
                              .arg(qs(patchLibrary_->patterns()[static_cast<std::size_t>(p.pattern)].name))
                              .arg(p.score, 0, 'f', 2);
    PreparedPreview preview;
    preview.metrics = sim::computeMetrics(scene, loaded.session->library);
    preview.stage = std::make_unique<cli::SceneStage>(std::move(loaded));
    const cli::SceneStage& stage = *preview.stage;
    preview.gantt = ganttFromScene(stage.scene(), stage.library(), [&stage](int c) {
        const glm::vec3 t = stage.tint(c);
        return QColor::fromRgbF(t.x, t.y, t.z);
    });
    preview.summary = title + ", looping";
    showGenerated(std::move(preview));
    previewedPatch_ = patch;
    previewSetup_.clear();  // a patch, not a setup's scene: edits are not compared against it
}

}  // namespace fray::editor
