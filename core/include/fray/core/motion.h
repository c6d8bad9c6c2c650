#pragma once
// Motion: one captured take. Stored structure-of-arrays: all joint local
// translations of all frames in one array, all local rotations in another, so
// a frame is one contiguous block per array and thousands of clips can be
// sampled without chasing pointers.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "fray/core/result.h"
#include "fray/core/skeleton.h"

namespace fray {

enum class UpAxis : std::uint8_t { Y, Z };

// Where the data came from and how it was normalised.
struct SourceInfo {
    std::string path;
    std::string format;              // "bvh", "fbx", "gltf", ...
    double unitScale = 1.0;          // file units -> metres factor applied
    std::string unitName = "m";      // "m", "cm", "mm", "inch", "cmu"
    UpAxis sourceUp = UpAxis::Y;     // up axis of the source file
    bool normalized = false;         // true once in metres, Y-up
    std::vector<std::string> warnings;  // things the importer fixed or ignored
};

// A pose: local translation and rotation per joint.
struct Pose {
    std::vector<glm::vec3> translations;
    std::vector<glm::quat> rotations;
};

class Motion {
public:
    Motion() = default;
    Motion(Skeleton skeleton, double fps, int frameCount);

    const Skeleton& skeleton() const { return skeleton_; }
    Skeleton& skeleton() { return skeleton_; }
    double fps() const { return fps_; }
    void setFps(double fps) { fps_ = fps; }
    int frameCount() const { return frameCount_; }
    int jointCount() const { return skeleton_.jointCount(); }
    double duration() const { return frameCount_ > 1 ? (frameCount_ - 1) / fps_ : 0.0; }

    SourceInfo& source() { return source_; }
    const SourceInfo& source() const { return source_; }

    // Per-frame views (jointCount entries each).
    std::span<glm::vec3> translations(int frame);
    std::span<const glm::vec3> translations(int frame) const;
    std::span<glm::quat> rotations(int frame);
    std::span<const glm::quat> rotations(int frame) const;
    glm::vec3 rootTranslation(int frame) const { return translations_[index(frame, 0)]; }

    // Whole arrays, frame-major: [frame * jointCount + joint].
    std::vector<glm::vec3>& allTranslations() { return translations_; }
    const std::vector<glm::vec3>& allTranslations() const { return translations_; }
    std::vector<glm::quat>& allRotations() { return rotations_; }
    const std::vector<glm::quat>& allRotations() const { return rotations_; }

    // Appends one frame (used by streaming readers).
    void appendFrame(std::span<const glm::vec3> translations, std::span<const glm::quat> rotations);
    void reserveFrames(std::size_t frames);

    // Samples the pose at time t (seconds, clamped): translations lerp, rotations slerp.
    void sample(double t, Pose& out) const;

private:
    std::size_t index(int frame, int joint) const {
        return static_cast<std::size_t>(frame) * static_cast<std::size_t>(skeleton_.jointCount()) +
               static_cast<std::size_t>(joint);
    }

    Skeleton skeleton_;
    double fps_ = 60.0;
    int frameCount_ = 0;
    std::vector<glm::vec3> translations_;
    std::vector<glm::quat> rotations_;
    SourceInfo source_;
};

// Resamples to a target frame rate (e.g. 120 -> 60) by slerp sampling.
Result<Motion> resample(const Motion& motion, double targetFps);
// Frames [first, last] inclusive.
Result<Motion> trim(const Motion& motion, int first, int last);
// Appends b after a. Skeletons must match (same names and parents). With
// alignRoot, b is moved on the floor and turned about Y so its first root
// position and heading continue a's last frame.
Result<Motion> concatenate(const Motion& a, const Motion& b, bool alignRoot);

}  // namespace fray
