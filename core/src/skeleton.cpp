#include "fray/core/skeleton.h"

#include <unordered_set>

namespace fray {

std::string_view toString(RotationOrder order) {
    switch (order) {
        case RotationOrder::XYZ: return "XYZ";
        case RotationOrder::XZY: return "XZY";
        case RotationOrder::YXZ: return "YXZ";
        case RotationOrder::YZX: return "YZX";
        case RotationOrder::ZXY: return "ZXY";
        case RotationOrder::ZYX: return "ZYX";
    }
    return "?";
}

std::string_view toString(Channel channel) {
    switch (channel) {
        case Channel::Xposition: return "Xposition";
        case Channel::Yposition: return "Yposition";
        case Channel::Zposition: return "Zposition";
        case Channel::Xrotation: return "Xrotation";
        case Channel::Yrotation: return "Yrotation";
        case Channel::Zrotation: return "Zrotation";
    }
    return "?";
}

std::optional<Channel> parseChannel(std::string_view name) {
    // Case-insensitive on the axis letter and the word, as exporters vary.
    if (name.size() != 9) return std::nullopt;
    auto lower = [](char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; };
    std::string s;
    for (char c : name) s.push_back(lower(c));
    if (s == "xposition") return Channel::Xposition;
    if (s == "yposition") return Channel::Yposition;
    if (s == "zposition") return Channel::Zposition;
    if (s == "xrotation") return Channel::Xrotation;
    if (s == "yrotation") return Channel::Yrotation;
    if (s == "zrotation") return Channel::Zrotation;
    return std::nullopt;
}

int Skeleton::find(std::string_view name) const {
    for (int i = 0; i < jointCount(); ++i)
        if (names[static_cast<std::size_t>(i)] == name) return i;
    return -1;
}

int Skeleton::channelCount() const {
    int n = 0;
    for (const auto& c : channels) n += static_cast<int>(c.size());
    return n;
}

bool Skeleton::hasPositionChannels(int joint) const {
    for (Channel c : channels[static_cast<std::size_t>(joint)])
        if (c == Channel::Xposition || c == Channel::Yposition || c == Channel::Zposition) return true;
    return false;
}

std::vector<int> Skeleton::children(int joint) const {
    std::vector<int> out;
    for (int i = 0; i < jointCount(); ++i)
        if (parents[static_cast<std::size_t>(i)] == joint) out.push_back(i);
    return out;
}

int Skeleton::addJoint(std::string name, int parent, glm::vec3 offset, std::vector<Channel> jointChannels,
                       RotationOrder order) {
    names.push_back(std::move(name));
    parents.push_back(parent);
    offsets.push_back(offset);
    channels.push_back(std::move(jointChannels));
    rotationOrders.push_back(order);
    endSites.emplace_back(std::nullopt);
    return jointCount() - 1;
}

std::optional<std::string> Skeleton::validate() const {
    const std::size_t n = names.size();
    if (n == 0) return "skeleton has no joints";
    if (parents.size() != n || offsets.size() != n || channels.size() != n || rotationOrders.size() != n ||
        endSites.size() != n)
        return "skeleton arrays have different sizes";
    if (parents[0] != -1) return "first joint must be the root";
    std::unordered_set<std::string> seen;
    for (std::size_t i = 0; i < n; ++i) {
        if (names[i].empty()) return "joint " + std::to_string(i) + " has an empty name";
        if (!seen.insert(names[i]).second) return "duplicate joint name '" + names[i] + "'";
        if (i > 0 && (parents[i] < 0 || static_cast<std::size_t>(parents[i]) >= i))
            return "joint '" + names[i] + "' must come after its parent";
    }
    return std::nullopt;
}

RotationOrder rotationOrderFromChannels(const std::vector<Channel>& channels) {
    char axes[3];
    int n = 0;
    for (Channel c : channels) {
        if (n == 3) break;
        if (c == Channel::Xrotation) axes[n++] = 'X';
        if (c == Channel::Yrotation) axes[n++] = 'Y';
        if (c == Channel::Zrotation) axes[n++] = 'Z';
    }
    if (n != 3) return RotationOrder::ZXY;
    const std::string_view s(axes, 3);
    if (s == "XYZ") return RotationOrder::XYZ;
    if (s == "XZY") return RotationOrder::XZY;
    if (s == "YXZ") return RotationOrder::YXZ;
    if (s == "YZX") return RotationOrder::YZX;
    if (s == "ZXY") return RotationOrder::ZXY;
    if (s == "ZYX") return RotationOrder::ZYX;
    return RotationOrder::ZXY;
}

}  // namespace fray
