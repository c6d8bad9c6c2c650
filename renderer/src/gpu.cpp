#include "gpu.h"

#include <cstring>

namespace fray::render::gpu {

Status Buffer::create(VulkanDevice& dev, VkDeviceSize bytes, VkBufferUsageFlags usage, MemoryUse use) {
    VkDevice device = dev.device();
    auto bci = vkInit<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    bci.size = bytes;
    bci.usage = usage;
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkResult r = vkCreateBuffer(device, &bci, nullptr, &buffer);
    if (r != VK_SUCCESS) return vkError("vkCreateBuffer", r);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, buffer, &req);
    std::uint32_t type = UINT32_MAX;
    const VkMemoryPropertyFlags hostVisible = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    switch (use) {
        case MemoryUse::Dynamic:
            type = dev.findMemoryType(req.memoryTypeBits, hostVisible, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
            break;
        case MemoryUse::Static:
            type = dev.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, hostVisible);
            if (type == UINT32_MAX) type = dev.findMemoryType(req.memoryTypeBits, hostVisible);
            break;
        case MemoryUse::Readback:
            type = dev.findMemoryType(req.memoryTypeBits, hostVisible, VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
            break;
    }
    if (type == UINT32_MAX) return makeError("no suitable Vulkan memory type for a buffer");
    auto mai = vkInit<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = type;
    if ((r = vkAllocateMemory(device, &mai, nullptr, &memory)) != VK_SUCCESS) return vkError("vkAllocateMemory", r);
    if ((r = vkBindBufferMemory(device, buffer, memory, 0)) != VK_SUCCESS) return vkError("vkBindBufferMemory", r);
    size = bytes;
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(dev.physicalDevice(), &mp);
    if ((mp.memoryTypes[type].propertyFlags & hostVisible) == hostVisible) {
        if ((r = vkMapMemory(device, memory, 0, VK_WHOLE_SIZE, 0, &mapped)) != VK_SUCCESS) return vkError("vkMapMemory", r);
    }
    return {};
}

void Buffer::destroy(VkDevice device) {
    if (mapped) vkUnmapMemory(device, memory);
    if (buffer) vkDestroyBuffer(device, buffer, nullptr);
    if (memory) vkFreeMemory(device, memory, nullptr);
    *this = Buffer{};
}

Status createStaticBuffer(VulkanDevice& dev, Buffer& out, const void* data, VkDeviceSize bytes, VkBufferUsageFlags usage) {
    if (Status s = out.create(dev, bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Static); !s) return s;
    if (out.mapped) {
        std::memcpy(out.mapped, data, bytes);
        return {};
    }
    Buffer staging;
    Status s = staging.create(dev, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Dynamic);
    if (s) {
        std::memcpy(staging.mapped, data, bytes);
        s = dev.runOnce([&](VkCommandBuffer cmd) {
            const VkBufferCopy region{0, 0, bytes};
            vkCmdCopyBuffer(cmd, staging.buffer, out.buffer, 1, &region);
        });
    }
    staging.destroy(dev.device());
    return s;
}

Status Image::create(VulkanDevice& dev, std::uint32_t w, std::uint32_t h, VkFormat fmt, VkImageUsageFlags usage,
                     VkSampleCountFlagBits samples, VkImageAspectFlags aspect) {
    VkDevice device = dev.device();
    auto ici = vkInit<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
    ici.imageType = VK_IMAGE_TYPE_2D;
    ici.format = fmt;
    ici.extent = {w, h, 1};
    ici.mipLevels = 1;
    ici.arrayLayers = 1;
    ici.samples = samples;
    ici.tiling = VK_IMAGE_TILING_OPTIMAL;
    ici.usage = usage;
    ici.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkResult r = vkCreateImage(device, &ici, nullptr, &image);
    if (r != VK_SUCCESS) return vkError("vkCreateImage", r);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device, image, &req);
    const std::uint32_t type = dev.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type == UINT32_MAX) return makeError("no device-local Vulkan memory for an image");
    auto mai = vkInit<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = type;
    if ((r = vkAllocateMemory(device, &mai, nullptr, &memory)) != VK_SUCCESS) return vkError("vkAllocateMemory", r);
    if ((r = vkBindImageMemory(device, image, memory, 0)) != VK_SUCCESS) return vkError("vkBindImageMemory", r);
    auto vci = vkInit<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
    vci.image = image;
    vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vci.format = fmt;
    vci.subresourceRange = {aspect, 0, 1, 0, 1};
    if ((r = vkCreateImageView(device, &vci, nullptr, &view)) != VK_SUCCESS) return vkError("vkCreateImageView", r);
    format = fmt;
    width = w;
    height = h;
    return {};
}

void Image::destroy(VkDevice device) {
    if (view) vkDestroyImageView(device, view, nullptr);
    if (image) vkDestroyImage(device, image, nullptr);
    if (memory) vkFreeMemory(device, memory, nullptr);
    *this = Image{};
}

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                  VkAccessFlags srcAccess, VkAccessFlags dstAccess, VkPipelineStageFlags srcStage,
                  VkPipelineStageFlags dstStage) {
    auto b = vkInit<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

Status uploadImage(VulkanDevice& dev, Image& image, const void* pixels, VkDeviceSize bytes) {
    Buffer staging;
    Status s = staging.create(dev, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Dynamic);
    if (s) {
        std::memcpy(staging.mapped, pixels, bytes);
        s = dev.runOnce([&](VkCommandBuffer cmd) {
            imageBarrier(cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
            VkBufferImageCopy region{};
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.imageExtent = {image.width, image.height, 1};
            vkCmdCopyBufferToImage(cmd, staging.buffer, image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
            imageBarrier(cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
        });
    }
    staging.destroy(dev.device());
    return s;
}

}  // namespace fray::render::gpu
