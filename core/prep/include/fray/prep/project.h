#pragma once
// The project file (*.frayproj): versioned, human-readable JSON holding the
// relative paths of the source motions and everything the user authored
// (cuts, action descriptions, contact labels, vocabulary, combination table).
// Sections of later issues (PatternLists, paintings, trajectories, scene
// settings) are kept verbatim so an older build never drops them.
// Written atomically; a load error names the file and the JSON path of the
// bad field ("demo.frayproj: /motions/2/cuts/5: must be an integer").
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fray/core/result.h"
#include "fray/prep/actions.h"
#include "fray/prep/combos.h"
#include "fray/prep/labels.h"

namespace fray::prep {

inline constexpr int kProjectVersion = 1;

struct ProjectMotion {
    std::string id;          // unique within the project (defaults to the file stem)
    std::string path;        // as written: relative to the project folder, or absolute
    std::string units;       // import override: "" (detect), m, cm, mm, inch, cmu
    std::string up;          // import override: "" (detect), y, z
    MotionActions actions;   // frameCount is the motion's frame count when last segmented
    std::vector<ContactLabel> contactLabels;
    friend bool operator==(const ProjectMotion&, const ProjectMotion&) = default;
};

struct ProjectSettings {
    std::string graphPreset = "fighting";       // motion-graph weight preset
    std::optional<double> graphThreshold;       // unset: the preset's default
    std::optional<double> segmentThresholdFactor;  // unset: SegmentationParams default
    friend bool operator==(const ProjectSettings&, const ProjectSettings&) = default;
};

struct Project {
    std::string name;
    std::vector<std::string> vocabulary;  // annotation words (defaults + the user's)
    ProjectSettings settings;
    std::vector<ProjectMotion> motions;
    ComboTable combos;
    // Raw JSON of the sections later issues define, keyed by section name.
    std::map<std::string, std::string> laterSections;

    ProjectMotion* findMotion(std::string_view id);
    const ProjectMotion* findMotion(std::string_view id) const;
    friend bool operator==(const Project&, const Project&) = default;
};

// A new project with the default vocabulary.
Project makeProject(std::string name);

std::string projectToJson(const Project& project);
Result<Project> projectFromJson(std::string_view text, std::string_view fileName);

// Loads and validates. Relative motion paths stay as written; resolve them
// with resolveMotionPath.
Result<Project> loadProject(const std::filesystem::path& file);
// Writes atomically (temporary file, flush, rename): on any error the old
// file is untouched.
Status saveProject(const Project& project, const std::filesystem::path& file);

std::filesystem::path resolveMotionPath(const std::filesystem::path& projectFile, const ProjectMotion& motion);
// Path to store for a motion file: relative to the project folder when possible.
std::string relativeMotionPath(const std::filesystem::path& projectFile, const std::filesystem::path& motionFile);

}  // namespace fray::prep
