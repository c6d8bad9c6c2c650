#pragma once
// The demo project: the demo library's takes as a Fray project, authored the
// way an animator would leave it: cuts, names and annotations from the ground
// truth, about 20 s of labelled foot contacts (so the SVM has something to
// learn from) and a starter combination table.
#include <string>
#include <vector>

#include "fray/demo/ground_truth.h"
#include "fray/prep/project.h"

namespace fray::demo {

// One take of the project: its ground truth and its motion path relative to
// the project file.
struct ProjectTake {
    GroundTruth truth;
    std::string motionPath;
};

prep::Project makeDemoProject(const std::vector<ProjectTake>& takes);

}  // namespace fray::demo
