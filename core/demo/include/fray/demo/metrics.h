#pragma once
// Quality measures of a take against its ground truth: foot skate during
// contact, floor penetration, joint angular speeds, effector speeds. The tests
// put thresholds on these; `fray-cli demo-library --report` prints them.
#include <string>
#include <vector>

#include "fray/core/motion.h"
#include "fray/demo/ground_truth.h"

namespace fray::demo {

struct ActionMetrics {
    std::string name;
    std::string style;
    double seconds = 0;
    double peakEffectorSpeed = 0;  // attacks: m/s of the first joint in `joints` before the apex
    double maxAngularSpeed = 0;    // deg/s, largest over non-root joints
    std::string fastestJoint;
};

struct TakeMetrics {
    double maxSkate = 0;          // m per frame, foot (ankle and toe) motion while in contact
    double meanSkate = 0;
    int contactFrames = 0;        // frames with at least one foot in contact
    double minJointHeight = 0;    // lowest joint over the take (m)
    double maxAngularSpeed = 0;   // deg/s, non-root joints
    std::string fastestJoint;
    double maxRootSpeed = 0;      // m/s
    std::vector<ActionMetrics> actions;
};

TakeMetrics measureTake(const Motion& motion, const GroundTruth& truth);

}  // namespace fray::demo
