#pragma once
// The data-preparation pipeline over a project file, shared by fray-cli, the
// editor, fray-play, the tests and the benches: open a project, load its
// motions, get foot contacts (from the cache when fresh), build the motion
// graph, save the project and the cache. Long steps take a ProgressFn: it
// reports progress and cancels (the step then fails with ErrorKind::Cancelled,
// which callers tell from a failure by the kind). What the user should be told
// on the side (a damaged cache rebuilt, a cache that could not be written)
// goes to a NoteFn. Plain C++: no Qt, no Vulkan.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/retarget.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/pipeline.h"
#include "fray/prep/project.h"

namespace fray::pipeline {

// Things to tell the user beside the result ("demo.frayproj.cache: checksum
// mismatch; rebuilding it"); an empty NoteFn says nothing.
using NoteFn = std::function<void(std::string_view note)>;

// Loads a motion as the project entry says (units/up overrides).
Result<Motion> loadProjectMotion(const std::filesystem::path& file, const prep::ProjectMotion& entry);

// One project skeleton (docs/DATA_PREP.md, "Mixed skeletons"): the first
// motion's skeleton, its first frame as the reference pose.
RetargetTarget projectSkeletonTarget(const Motion& first, const std::string& firstId);

// The project's motions as prep::loadProjectMotions loads them, on one
// skeleton: a motion whose skeleton differs from the first motion's (joint
// names or hierarchy) is retargeted onto it (fray/core/retarget.h) before its
// signals are computed, so the motion graph and the planners work across
// sources. A motion that cannot be retargeted (no feet, ...) is an error that
// names it. `reports` (when given) gets one entry per retargeted motion.
Result<std::vector<prep::LoadedMotion>> loadSessionMotions(const prep::Project& project,
                                                           const std::filesystem::path& projectFile,
                                                           const ProgressFn& progress,
                                                           std::vector<RetargetReport>* reports = nullptr);

struct Session {
    std::filesystem::path file;
    prep::Project project;
    prep::Project asLoaded;  // the project as read, to see whether another program changed the file since
    std::vector<prep::LoadedMotion> motions;
    prep::DerivedCache cache;
};

Result<Session> openSession(const std::filesystem::path& file, bool loadMotions, const ProgressFn& progress,
                            const NoteFn& note = {});

// Imports a labels CSV into the project: rows name motions by id; every
// range is checked against the motion's frame count. Replaces the labels of
// the motions the file mentions.
Status importLabels(Session& s, const std::filesystem::path& labelsFile);

struct ContactsSummary {
    bool svm = false;
    bool fromCache = false;
    double C = 0, gamma = 0, looAccuracy = 0;
    int samples = 0, supportVectors = 0;
    double seconds = 0;
};
// Fills motions[i].contacts: SVM when the project has labels (unless
// forceHeuristic), else the heuristic. Uses and refreshes s.cache.
Result<ContactsSummary> computeContacts(Session& s, bool forceHeuristic, const ProgressFn& progress);

struct ProjectGraph {
    prep::MotionGraph graph;
    std::string preset;
    prep::GraphOptions options;
    bool cached = false;  // reconnected from a fresh cache entry (s.cache is then unchanged)
    // When the project sets no threshold and none is given: the threshold its
    // transition gaps ask for (prep::thresholdFromGaps), and whether it was
    // used (it was above the default).
    double dataThreshold = 0;
    bool thresholdFromData = false;
};
// The project's action-level motion graph: from the cache when its key
// (preset, threshold, files, cuts) matches, else built and stored in s.cache
// (write the cache to keep it). Empty overrides use the project's settings;
// with no threshold set either, max(default, the data's threshold).
Result<ProjectGraph> projectGraph(Session& s, const std::string& presetOverride, double thresholdOverride,
                                  const ProgressFn& progress);

// Saves the project and the cache. The project is saved under its lock
// (FileLock) and only when the file still holds what openSession read:
// if another program saved it meanwhile, nothing is saved and the error says
// so (run the command again), so neither edit is lost.
Status saveSession(const Session& s, const NoteFn& note);

// One read-modify-write of a project file under its lock: lock, read the
// file afresh, apply `edit`, save atomically, unlock. Concurrent editors
// (other fray-cli processes) wait for each other instead of losing edits.
Status editProject(const std::filesystem::path& file, const std::function<Status(prep::Project&)>& edit);

// Refuses an output path that is the project, its cache or lock file, or
// one of the project's motion files ("OUT: is the project file; refusing to
// overwrite it").
Status checkOutputIsNotInput(const std::filesystem::path& projectFile, const prep::Project& project,
                             const std::filesystem::path& out);

}  // namespace fray::pipeline
