#include "project_analysis.h"

#include "fray/prep/contacts.h"
#include "fray/prep/pipeline.h"
#include "fray/prep/segmentation.h"
#include "fray/pipeline/sim_session.h"

#include <optional>

namespace fray::editor {

QString actionLabel(const prep::ActionInfo& info) {
    if (!info.name.empty()) return QString::fromStdString(info.name);
    if (!info.annotations.empty()) return QString::fromStdString(info.annotations.front());
    if (!info.proposed.empty()) return QString::fromStdString(info.proposed.front()) + "?";
    return "?";
}

Result<ProjectAnalysis> analyseProject(const prep::Project& project, const std::filesystem::path& file,
                                       const ProgressFn& progress) {
    // Stages share the bar: loading 0-0.5, contacts 0.5-0.7, segmentation
    // profiles 0.7-0.8, graph 0.8-1.
    const auto stage = [&](double from, double to) -> ProgressFn {
        if (!progress) return {};
        return [=](double f, std::string_view name) { return progress(from + (to - from) * f, name); };
    };
    std::optional<pipeline::Session> session(std::in_place);
    session->file = file;
    session->project = project;
    auto motions = pipeline::loadSessionMotions(project, file, stage(0.0, 0.5));
    if (!motions) return motions.error();
    session->motions = std::move(*motions);
    std::string why;
    session->cache = prep::readCache(file, &why);
    auto contacts = pipeline::computeContacts(*session, false, stage(0.5, 0.7));
    if (!contacts) return contacts.error();

    ProjectAnalysis out;
    out.file = file;
    out.project = session->project;
    if (contacts->svm && contacts->fromCache)
        out.contactsSummary = "SVM contacts (trained earlier, from the cache)";
    else if (contacts->svm)
        out.contactsSummary = "SVM contacts, leave-one-out accuracy " + std::to_string(contacts->looAccuracy * 100.0).substr(0, 5) + " %";
    else
        out.contactsSummary = "heuristic contacts (label some frames and train for SVM contacts)";
    const prep::SegmentationParams params = prep::segmentationParams(session->project.settings);
    const double count = static_cast<double>(std::max<std::size_t>(1, session->motions.size()));
    for (std::size_t i = 0; i < session->motions.size(); ++i) {
        const prep::LoadedMotion& m = session->motions[i];
        if (!reportProgress(progress, 0.7 + 0.1 * static_cast<double>(i) / count, "profile " + m.id))
            return cancelled();
        const prep::ProjectMotion& entry = session->project.motions[i];
        const prep::SegmentationResult seg = prep::segment(m.signals, m.contacts, params);
        MotionAnalysis a;
        a.id = m.id;
        TimelineData& t = a.timeline;
        t.frameCount = m.signals.frameCount;
        t.fps = m.signals.fps;
        t.acceleration = seg.smoothed;
        t.threshold = seg.threshold;
        t.highAccel = seg.highAccel;
        t.contactLeft = m.contacts.left;
        t.contactRight = m.contacts.right;
        t.cuts = entry.actions.cuts;
        for (const prep::ActionInfo& info : entry.actions.actions) t.actionNames.push_back(actionLabel(info));
        for (const prep::ContactLabel& l : entry.contactLabels) t.labels.push_back({l.firstFrame, l.lastFrame, l.left, l.right});
        out.motions.push_back(std::move(a));
        for (int k = 0; k < entry.actions.actionCount(); ++k) out.graphActions.emplace_back(static_cast<int>(i), k);
    }
    auto graph = pipeline::projectGraph(*session, "", 0.0, stage(0.8, 1.0));
    if (!graph) return graph.error();
    out.graph.nodeCount = graph->graph.nodeCount;
    out.graph.startNode = graph->graph.startNode;
    out.graph.endNode = graph->graph.endNode;
    out.graph.inLargestScc = graph->graph.inLargestScc;
    out.graphStats = graph->graph.stats;
    out.graphPreset = graph->preset;
    out.graphThreshold = graph->options.threshold;
    const prep::GraphStats& s = out.graphStats;
    out.graph.summary = QString("%1 nodes, %2 edges, largest SCC %3 %  (%4, threshold %5)")
                            .arg(s.nodes)
                            .arg(s.edges)
                            .arg(s.sccShare * 100.0, 0, 'f', 1)
                            .arg(QString::fromStdString(out.graphPreset))
                            .arg(out.graphThreshold, 0, 'f', 2);
    reportProgress(progress, 1.0, "done");
    return out;
}

}  // namespace fray::editor
