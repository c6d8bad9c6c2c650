#pragma once
// What the editor's panels show of a project, computed off the UI thread:
// every motion's signals, foot contacts (SVM when the project has labels,
// from the cache when fresh) and segmentation profile, and the action-level
// motion graph. Plain C++ over fray_prep and the CLI's session plumbing; the
// window runs it in a worker thread and cancels through the progress
// callback.
#include <QString>
#include <filesystem>
#include <string>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/project.h"
#include "graph_view.h"
#include "timeline_view.h"

namespace fray::editor {

struct MotionAnalysis {
    std::string id;
    TimelineData timeline;  // actionNames filled from the project
};

struct ProjectAnalysis {
    std::filesystem::path file;
    prep::Project project;
    std::vector<MotionAnalysis> motions;  // project order
    GraphViewData graph;
    prep::GraphStats graphStats;
    std::string graphPreset;
    double graphThreshold = 0;
    // Graph action index -> (motion, action), project order.
    std::vector<std::pair<int, int>> graphActions;
    std::string contactsSummary;
};

// The label an action shows: its name, else its first annotation, else its
// first proposal with '?', else "?".
QString actionLabel(const prep::ActionInfo& info);

// Analyses `project` as it is now (the document's, edits included); `file` is
// where it lives (relative motion paths resolve from its folder, and the
// derived-data cache beside it is read, never written).
Result<ProjectAnalysis> analyseProject(const prep::Project& project, const std::filesystem::path& file,
                                       const ProgressFn& progress);

}  // namespace fray::editor
