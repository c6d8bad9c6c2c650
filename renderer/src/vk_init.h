#pragma once
// Zero-initialised Vulkan structure with its sType set (the aggregate form
// `VkFoo x{VK_STRUCTURE_TYPE_FOO}` trips -Wmissing-field-initializers).
#include <vulkan/vulkan.h>

namespace fray::render {

template <class T>
T vkInit(VkStructureType type) {
    T value{};
    value.sType = type;
    return value;
}

}  // namespace fray::render
