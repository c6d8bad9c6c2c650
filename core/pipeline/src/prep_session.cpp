#include "fray/pipeline/prep_session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include "fray/core/atomic_file.h"
#include "fray/core/body_mesh.h"
#include "fray/core/normalize.h"
#include "fray/io/import.h"
#include "fray/prep/contacts.h"
#include "fray/prep/labels.h"

namespace fray::pipeline {

Result<Motion> loadProjectMotion(const std::filesystem::path& file, const prep::ProjectMotion& entry) {
    LoadOptions o;
    o.normalize = normalizeOptionsFor(entry.units, entry.up);
    return loadMotion(file, o);
}

RetargetTarget projectSkeletonTarget(const Motion& first, const std::string& firstId) {
    return retargetTargetFromMotion(first, 0, "the project skeleton (motion \"" + firstId + "\")");
}

Result<std::vector<prep::LoadedMotion>> loadSessionMotions(const prep::Project& project,
                                                           const std::filesystem::path& projectFile,
                                                           const ProgressFn& progress,
                                                           std::vector<RetargetReport>* reports) {
    // First pass: load as the files are; a project on one skeleton stops here.
    std::optional<RetargetTarget> target;
    bool mixed = false;
    const auto plain = [&](const std::filesystem::path& f, const prep::ProjectMotion& entry) -> Result<Motion> {
        auto m = loadProjectMotion(f, entry);
        if (!m) return m;
        if (!target) target = projectSkeletonTarget(*m, entry.id);
        else if (!sameSkeleton(m->skeleton(), target->skeleton)) mixed = true;
        return m;
    };
    auto motions = prep::loadProjectMotions(project, projectFile, plain, progress);
    if (!motions || !mixed) return motions;
    // Mixed skeletons: every take, those already on the project skeleton
    // included, goes through the same retargeting, so poses from different
    // sources compare alike in the motion graph (same held joints, same
    // anatomical twist).
    const auto onto = [&](const std::filesystem::path&, const prep::ProjectMotion& entry) -> Result<Motion> {
        auto at = std::find_if(motions->begin(), motions->end(), [&](const auto& m) { return m.id == entry.id; });
        if (at == motions->end()) return makeError("motion \"" + entry.id + "\" was not loaded");
        RetargetReport report;
        auto r = retarget(at->motion, *target, {}, &report);
        if (!r) return r.error();
        if (reports && !sameSkeleton(at->motion.skeleton(), target->skeleton)) reports->push_back(std::move(report));
        return r;
    };
    // Progress runs again from 0 for this pass ("load <id>"); cancelling still works.
    auto retargeted = prep::loadProjectMotions(project, projectFile, onto, progress);
    if (!retargeted) return retargeted;
    // Their derived data depends on the project skeleton too.
    const std::uint64_t fp = skeletonFingerprint(target->skeleton) ^ prep::hashString("retarget 1");
    for (auto& m : *retargeted) m.fileKey = prep::hashBytes(&fp, sizeof fp, m.fileKey);
    return retargeted;
}

Result<Session> openSession(const std::filesystem::path& file, bool loadMotions, const ProgressFn& progress,
                            const NoteFn& note) {
    Session s;
    s.file = file;
    auto project = prep::loadProject(file);
    if (!project) return project.error();
    s.project = std::move(*project);
    s.asLoaded = s.project;
    if (loadMotions) {
        auto motions = loadSessionMotions(s.project, file, progress);
        if (!motions) return motions.error();
        s.motions = std::move(*motions);
        std::string why;
        bool damaged = false;
        s.cache = prep::readCache(file, &why, &damaged);
        if (damaged && note) note("note: " + why + "; rebuilding it");
    }
    return s;
}

Status importLabels(Session& s, const std::filesystem::path& labelsFile) {
    const auto text = readWholeFile(labelsFile, "the labels file");
    if (!text) return text.error();
    auto rows = prep::parseLabelsCsv(*text, labelsFile.string());
    if (!rows) return rows.error();
    std::map<std::string, std::vector<prep::ContactLabel>> byMotion;
    for (const auto& row : *rows) {
        const auto* m = s.project.findMotion(row.motion);
        const std::string where = labelsFile.string() + ":" + std::to_string(row.line) + ": ";
        if (!m) return makeError(where + "motion: no motion \"" + row.motion + "\" in the project");
        const int frames = m->actions.frameCount;
        if (row.label.lastFrame >= frames) {
            return makeError(where + "last_frame: frame " + std::to_string(row.label.lastFrame) +
                             " is past the end of \"" + row.motion + "\" (frames 0.." + std::to_string(frames - 1) +
                             ")");
        }
        byMotion[row.motion].push_back(row.label);
    }
    for (auto& [id, labels] : byMotion) s.project.findMotion(id)->contactLabels = std::move(labels);
    return {};
}

Result<ContactsSummary> computeContacts(Session& s, bool forceHeuristic, const ProgressFn& progress) {
    ContactsSummary summary;
    summary.svm = !forceHeuristic && std::any_of(s.project.motions.begin(), s.project.motions.end(),
                                                 [](const auto& m) { return !m.contactLabels.empty(); });
    const std::uint64_t training = prep::trainingKey(s.project, s.motions);

    // Fresh cache entries for every motion?
    std::vector<std::uint64_t> keys;
    bool allCached = true;
    for (const auto& m : s.motions) {
        keys.push_back(prep::contactsKey(m, training, summary.svm));
        const auto* c = s.cache.findContacts(m.id, keys.back());
        if (!c || c->contacts.frameCount() != m.signals.frameCount) allCached = false;
    }
    if (allCached) {
        for (std::size_t i = 0; i < s.motions.size(); ++i) {
            s.motions[i].contacts = s.cache.findContacts(s.motions[i].id, keys[i])->contacts;
            s.motions[i].contactSource = summary.svm ? prep::ContactSource::Svm : prep::ContactSource::Heuristic;
        }
        summary.fromCache = true;
        return summary;
    }

    std::optional<prep::ContactSvm> svm;
    if (summary.svm) {
        std::vector<prep::TrainingSample> samples;
        for (std::size_t i = 0; i < s.motions.size(); ++i) {
            const auto& entry = s.project.motions[i];
            if (entry.contactLabels.empty()) continue;
            auto labels = prep::expandLabels(entry.contactLabels, s.motions[i].signals.frameCount);
            if (!labels) return makeError(s.file.string() + ": motion \"" + entry.id + "\": " + labels.error().message);
            const auto part = prep::collectSamples(s.motions[i].signals, *labels);
            samples.insert(samples.end(), part.begin(), part.end());
        }
        auto trained = prep::ContactSvm::train(samples, {}, [&](double f, std::string_view) {
            return reportProgress(progress, f, "svm grid search");
        });
        if (!trained) return makeError("contact SVM: " + trained.error().message);
        const auto& r = trained->report();
        summary.seconds = r.seconds;
        summary.C = r.C;
        summary.gamma = r.gamma;
        summary.looAccuracy = r.looAccuracy;
        summary.samples = r.samples;
        summary.supportVectors = r.supportVectors;
        svm = std::move(*trained);
    }
    s.cache.contacts.clear();
    for (std::size_t i = 0; i < s.motions.size(); ++i) {
        auto& m = s.motions[i];
        m.contacts = svm ? svm->classify(m.signals) : prep::heuristicContacts(m.signals);
        m.contactSource = svm ? prep::ContactSource::Svm : prep::ContactSource::Heuristic;
        s.cache.contacts.emplace_back(m.id, prep::CachedContacts{keys[i], m.contactSource, m.contacts});
    }
    return summary;
}

Result<ProjectGraph> projectGraph(Session& s, const std::string& presetOverride, double thresholdOverride,
                                  const ProgressFn& progress) {
    ProjectGraph out;
    out.preset = presetOverride.empty() ? s.project.settings.graphPreset : presetOverride;
    const auto weights = prep::GraphWeights::preset(out.preset);
    if (!weights) return makeError("graph preset: expected fighting or locomotion, got '" + out.preset + "'");
    out.options.weights = *weights;
    const bool thresholdSet = thresholdOverride > 0 || s.project.settings.graphThreshold.has_value();
    if (thresholdOverride > 0) out.options.threshold = thresholdOverride;
    else if (s.project.settings.graphThreshold) out.options.threshold = *s.project.settings.graphThreshold;

    std::vector<const Motion*> motions;
    std::vector<StandardJoints> joints;
    std::vector<prep::ActionRef> actions;
    for (std::size_t i = 0; i < s.motions.size(); ++i) {
        motions.push_back(&s.motions[i].motion);
        joints.push_back(s.motions[i].joints);
        const auto& doc = s.project.motions[i].actions;
        for (int k = 0; k < doc.actionCount(); ++k) actions.push_back({static_cast<int>(i), doc.firstFrame(k), doc.lastFrame(k)});
    }
    if (actions.empty()) return makeError(s.file.string() + ": the project has no actions (import motions first)");
    // No threshold set: the data's own transition gaps may raise the default
    // (docs/MOTION_GRAPH.md, "Threshold from the data"). The key holds the
    // threshold used, so a project whose data keeps the default keeps its cache.
    ProgressFn graphProgress = progress;
    if (!thresholdSet) {
        auto gaps = prep::transitionGaps(motions, joints, actions, out.options.weights, prep::kDataThresholdMaxEnds,
                                         [&](double f, std::string_view what) { return reportProgress(progress, 0.2 * f, what); });
        if (!gaps) return gaps.error();
        out.dataThreshold = prep::thresholdFromGaps(*gaps);
        if (out.dataThreshold > out.options.threshold) {
            out.options.threshold = out.dataThreshold;
            out.thresholdFromData = true;
        }
        graphProgress = [&](double f, std::string_view what) { return reportProgress(progress, 0.2 + 0.8 * f, what); };
    }
    std::uint64_t key = prep::hashString(out.preset);
    key = prep::hashBytes(&out.options.threshold, sizeof out.options.threshold, key);
    for (std::size_t i = 0; i < s.motions.size(); ++i) {
        key = prep::hashBytes(&s.motions[i].fileKey, sizeof(std::uint64_t), key);
        for (int c : s.project.motions[i].actions.cuts) key = prep::hashBytes(&c, sizeof c, key);
    }
    // A fresh cached graph only needs reconnecting; otherwise cluster again.
    out.cached = s.cache.graph && s.cache.graph->key == key && s.cache.graph->startNode.size() == actions.size();
    if (out.cached) {
        out.graph.nodeCount = s.cache.graph->nodeCount;
        prep::connectNodes(out.graph, s.cache.graph->startNode, s.cache.graph->endNode, prep::naturalSuccessors(actions));
        return out;
    }
    auto graph = prep::buildMotionGraph(motions, joints, actions, out.options, graphProgress);
    if (!graph) return graph.error();
    out.graph = std::move(*graph);
    s.cache.graph = prep::CachedGraph{key, out.graph.nodeCount, out.graph.startNode, out.graph.endNode};
    return out;
}

Status saveSession(const Session& s, const NoteFn& note) {
    auto lock = FileLock::acquire(s.file);
    if (!lock) return lock.error();
    auto current = prep::loadProject(s.file);
    if (!current) return current.error();
    if (!(*current == s.asLoaded)) {
        return makeError(s.file.string() +
                         ": another program saved the project while this command ran; nothing was saved "
                         "(run the command again to apply it to the new version)");
    }
    if (auto st = prep::saveProject(s.project, s.file); !st) return st;
    if (auto st = prep::writeCache(s.file, s.cache); !st) {
        // The cache is derived data: losing it costs time, not work.
        if (note) note("warning: could not write the cache: " + st.error().message);
    }
    return {};
}

}  // namespace fray::pipeline

namespace fray::pipeline {

Status editProject(const std::filesystem::path& file, const std::function<Status(prep::Project&)>& edit) {
    // A file that is not a readable project gets its error without a lock
    // file being left beside a mistyped path.
    if (auto first = prep::loadProject(file); !first) return first.error();
    auto lock = FileLock::acquire(file);
    if (!lock) return lock.error();
    auto project = prep::loadProject(file);
    if (!project) return project.error();
    if (auto st = edit(*project); !st) return st;
    return prep::saveProject(*project, file);
}

Status checkOutputIsNotInput(const std::filesystem::path& projectFile, const prep::Project& project,
                             const std::filesystem::path& out) {
    namespace fs = std::filesystem;
    auto same = [&](const fs::path& input) {
        std::error_code ec;
        if (fs::equivalent(out, input, ec)) return true;  // both exist and are one file (links included)
        const auto a = fs::weakly_canonical(fs::absolute(out, ec), ec);
        const auto b = fs::weakly_canonical(fs::absolute(input, ec), ec);
        return !ec && a == b;
    };
    const std::string refuse = "; refusing to overwrite it (choose another output file)";
    if (same(projectFile)) return makeError(out.string() + ": is the project file" + refuse);
    if (same(prep::cachePath(projectFile))) return makeError(out.string() + ": is the project's cache" + refuse);
    if (same(FileLock::lockPathFor(projectFile))) return makeError(out.string() + ": is the project's lock file" + refuse);
    for (const auto& m : project.motions) {
        if (same(prep::resolveMotionPath(projectFile, m))) {
            return makeError(out.string() + ": is the capture of motion \"" + m.id + "\" in the project" + refuse);
        }
    }
    return {};
}

}  // namespace fray::pipeline
