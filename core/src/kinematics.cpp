#include "fray/core/kinematics.h"

namespace fray {

void forwardKinematics(const Skeleton& skeleton, std::span<const glm::vec3> localTranslations,
                       std::span<const glm::quat> localRotations, std::span<glm::vec3> worldPositions,
                       std::span<glm::quat> worldRotations) {
    const int n = skeleton.jointCount();
    const int* parents = skeleton.parents.data();
    for (int j = 0; j < n; ++j) {
        const int p = parents[j];
        if (p < 0) {
            worldPositions[j] = localTranslations[j];
            worldRotations[j] = localRotations[j];
        } else {
            worldPositions[j] = worldPositions[p] + worldRotations[p] * localTranslations[j];
            worldRotations[j] = worldRotations[p] * localRotations[j];
        }
    }
}

void worldTransforms(const Motion& motion, int frame, std::span<glm::vec3> positions,
                     std::span<glm::quat> rotations) {
    forwardKinematics(motion.skeleton(), motion.translations(frame), motion.rotations(frame), positions, rotations);
}

void worldPositions(const Motion& motion, int frame, std::span<glm::vec3> out) {
    std::vector<glm::quat> rot(static_cast<std::size_t>(motion.jointCount()));
    worldTransforms(motion, frame, out, rot);
}

std::vector<glm::vec3> worldPositions(const Motion& motion, int first, int last) {
    const auto jc = static_cast<std::size_t>(motion.jointCount());
    if (first < 0) first = 0;
    if (last >= motion.frameCount()) last = motion.frameCount() - 1;
    if (last < first) return {};
    std::vector<glm::vec3> out(static_cast<std::size_t>(last - first + 1) * jc);
    std::vector<glm::quat> rot(jc);
    for (int f = first; f <= last; ++f)
        worldTransforms(motion, f, std::span<glm::vec3>(out.data() + static_cast<std::size_t>(f - first) * jc, jc),
                        rot);
    return out;
}

}  // namespace fray
