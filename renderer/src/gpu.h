#pragma once
// Small owning wrappers for buffers and images (one allocation each: the
// renderer has a few dozen, so a sub-allocator would be weight without gain).
#include <cstdint>

#include <vulkan/vulkan.h>

#include "fray/core/result.h"
#include "fray/render/vulkan_device.h"
#include "vk_init.h"

namespace fray::render::gpu {

enum class MemoryUse {
    Dynamic,   // written by the CPU every frame: host-visible, coherent, persistently mapped
    Static,    // written once: device-local; mapped too when the device-local memory is host-visible
    Readback,  // read by the CPU: host-visible, coherent (cached preferred), mapped
};

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    void* mapped = nullptr;

    Status create(VulkanDevice& dev, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use);
    void destroy(VkDevice device);
};

// Creates a Static buffer holding data (through a staging copy when the
// device-local memory cannot be mapped).
Status createStaticBuffer(VulkanDevice& dev, Buffer& out, const void* data, VkDeviceSize size, VkBufferUsageFlags usage);

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    std::uint32_t width = 0, height = 0;

    Status create(VulkanDevice& dev, std::uint32_t w, std::uint32_t h, VkFormat format, VkImageUsageFlags usage,
                  VkSampleCountFlagBits samples, VkImageAspectFlags aspect);
    void destroy(VkDevice device);
};

// Uploads tightly packed pixels into a sampled image and leaves it in
// SHADER_READ_ONLY_OPTIMAL.
Status uploadImage(VulkanDevice& dev, Image& image, const void* pixels, VkDeviceSize bytes);

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                  VkAccessFlags srcAccess, VkAccessFlags dstAccess, VkPipelineStageFlags srcStage,
                  VkPipelineStageFlags dstStage);

}  // namespace fray::render::gpu
