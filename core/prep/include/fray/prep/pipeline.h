#pragma once
// The data-preparation pipeline over a project: load every motion, compute
// its signals and foot contacts, segment, propose annotations, build the
// motion graph. Derived data (contacts, graph) lives in a versioned binary
// cache beside the project ("<project>.cache") and is rebuilt when stale:
// every entry carries a key hashed from everything it depends on (file size
// and time, import overrides, labels, cuts, settings).
//
// fray_prep does no file-format work itself: callers pass a MotionLoader
// (the CLI and the editor pass fray::loadMotion from fray_io).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fray/core/joint_guess.h"
#include "fray/core/motion.h"
#include "fray/core/progress.h"
#include "fray/prep/project.h"
#include "fray/prep/segmentation.h"
#include "fray/prep/signals.h"

namespace fray::prep {

using MotionLoader = std::function<Result<Motion>(const std::filesystem::path& file, const ProjectMotion& entry)>;

enum class ContactSource : std::uint8_t { Heuristic = 0, Svm = 1 };

struct LoadedMotion {
    std::string id;
    std::filesystem::path file;
    std::uint64_t fileKey = 0;  // hash of path, size, mtime and import overrides
    Motion motion;
    StandardJoints joints;
    MotionSignals signals;
    FootContacts contacts;
    ContactSource contactSource = ContactSource::Heuristic;
};

// Loads every motion of the project (in order) and computes its signals.
// Errors name the project, the motion's JSON path and the problem, e.g.
// "demo.frayproj: /motions/1/path: cannot open 'takes/walk.bvh'".
Result<std::vector<LoadedMotion>> loadProjectMotions(const Project& project, const std::filesystem::path& projectFile,
                                                     const MotionLoader& loader, const ProgressFn& progress = {});

// Derived data kept between runs.
struct CachedContacts {
    std::uint64_t key = 0;
    ContactSource source = ContactSource::Heuristic;
    FootContacts contacts;
};
struct CachedGraph {
    std::uint64_t key = 0;
    int nodeCount = 0;
    std::vector<int> startNode, endNode;  // per action, project order
};
struct DerivedCache {
    // 2: FNV-1a 64 checksum trailer. A version 1 cache reads as stale and is
    // rebuilt (it is derived data).
    static constexpr std::uint32_t kVersion = 2;
    std::vector<std::pair<std::string, CachedContacts>> contacts;  // by motion id
    std::optional<CachedGraph> graph;
    const CachedContacts* findContacts(const std::string& id, std::uint64_t key) const;
};

std::filesystem::path cachePath(const std::filesystem::path& projectFile);
std::vector<std::uint8_t> serializeCache(const DerivedCache& cache);
// Garbage, truncation, a checksum mismatch (any change confined to one byte
// is always caught) or another version give an error (callers rebuild).
Result<DerivedCache> deserializeCache(const std::vector<std::uint8_t>& bytes);
// A missing or unreadable cache reads as empty (with the reason in *why;
// *damaged is set when the file exists but cannot be trusted).
DerivedCache readCache(const std::filesystem::path& projectFile, std::string* why = nullptr, bool* damaged = nullptr);
Status writeCache(const std::filesystem::path& projectFile, const DerivedCache& cache);

// FNV-1a 64 over bytes; used for the cache keys.
std::uint64_t hashBytes(const void* data, std::size_t size, std::uint64_t seed = 1469598103934665603ull);
std::uint64_t hashString(std::string_view s, std::uint64_t seed = 1469598103934665603ull);

// What the contact SVM is trained on: the id, file key and labels of every
// labelled motion (motions and project.motions are parallel).
std::uint64_t trainingKey(const Project& project, const std::vector<LoadedMotion>& motions);
// Key of a motion's contacts: its file key, the method and, for the SVM, the
// training key.
std::uint64_t contactsKey(const LoadedMotion& motion, std::uint64_t training, bool svm);

SegmentationParams segmentationParams(const ProjectSettings& settings);

}  // namespace fray::prep
