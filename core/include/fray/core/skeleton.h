#pragma once
// Skeleton: the joint hierarchy of one motion (names, parents, rest offsets,
// channel layout, per-joint Euler rotation order). Joints are stored in
// depth-first order, so parents[j] < j for every non-root joint; kinematics
// relies on that to run in one forward pass.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace fray {

enum class RotationOrder : std::uint8_t { XYZ, XZY, YXZ, YZX, ZXY, ZYX };

// BVH channel kinds. The order of a joint's channels in the file is kept so a
// writer can reproduce the source layout.
enum class Channel : std::uint8_t { Xposition, Yposition, Zposition, Xrotation, Yrotation, Zrotation };

std::string_view toString(RotationOrder order);
std::string_view toString(Channel channel);
std::optional<Channel> parseChannel(std::string_view name);

struct Skeleton {
    std::vector<std::string> names;
    std::vector<int> parents;                       // -1 for the root
    std::vector<glm::vec3> offsets;                 // rest offset from the parent
    std::vector<std::vector<Channel>> channels;     // channel layout as in the source
    std::vector<RotationOrder> rotationOrders;      // Euler order of the rotation channels
    std::vector<std::optional<glm::vec3>> endSites; // BVH "End Site" offset, if any

    int jointCount() const { return static_cast<int>(names.size()); }
    int find(std::string_view name) const;          // -1 when absent
    int channelCount() const;                       // sum of channel counts
    bool hasPositionChannels(int joint) const;
    std::vector<int> children(int joint) const;

    // Appends a joint; returns its index. The parent must already exist.
    int addJoint(std::string name, int parent, glm::vec3 offset, std::vector<Channel> jointChannels,
                 RotationOrder order);

    // Checks structural invariants (sizes agree, parents precede children,
    // unique non-empty names). Returns a readable message on failure.
    std::optional<std::string> validate() const;
};

// Derives the Euler order from a joint's rotation channels (the order in which
// they appear, e.g. Z X Y -> ZXY). Joints without three rotation channels get ZXY.
RotationOrder rotationOrderFromChannels(const std::vector<Channel>& channels);

}  // namespace fray
