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

// A render pass attachment without stencil (its stencil neither loaded nor stored).
inline VkAttachmentDescription attachment(VkFormat format, VkSampleCountFlagBits samples, VkAttachmentLoadOp load, VkAttachmentStoreOp store,
                                          VkImageLayout initialLayout, VkImageLayout finalLayout) {
    VkAttachmentDescription a{};
    a.format = format;
    a.samples = samples;
    a.loadOp = load;
    a.storeOp = store;
    a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    a.initialLayout = initialLayout;
    a.finalLayout = finalLayout;
    return a;
}

}  // namespace fray::render
