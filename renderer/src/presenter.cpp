#include "fray/render/presenter.h"

#include <algorithm>
#include <array>

#include "gpu.h"
#include "vk_init.h"

namespace fray::render {

struct Presenter::Capture {
    gpu::Buffer buffer;
};

Result<std::unique_ptr<Presenter>> Presenter::create(std::shared_ptr<VulkanDevice> device, int width, int height,
                                                     const PresenterOptions& options) {
    if (!device || !device->surface()) return makeError("the Vulkan device was created without a window surface");
    std::unique_ptr<Presenter> p(new Presenter());
    p->dev_ = std::move(device);
    p->options_ = options;
    if (Status s = p->init(width, height); !s) return s.error();
    return p;
}

Status Presenter::init(int width, int height) {
    VkDevice device = dev_->device();
    VkPhysicalDevice pd = dev_->physicalDevice();
    requested_ = {static_cast<std::uint32_t>(std::max(width, 1)), static_cast<std::uint32_t>(std::max(height, 1))};

    // Format: an 8-bit UNORM format, so the renderer's display-encoded pixels
    // are copied unchanged (an sRGB format would encode them twice).
    std::uint32_t count = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(pd, dev_->surface(), &count, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(count);
    vkGetPhysicalDeviceSurfaceFormatsKHR(pd, dev_->surface(), &count, formats.data());
    if (formats.empty()) return makeError("the window surface offers no pixel format");
    format_ = formats[0].format;
    colorSpace_ = formats[0].colorSpace;
    for (const VkSurfaceFormatKHR& f : formats) {
        if ((f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) &&
            f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) {
            format_ = f.format;
            colorSpace_ = f.colorSpace;
            break;
        }
    }
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(pd, format_, &fp);
    if (!(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT))
        return makeError("the window's pixel format cannot be a blit destination on this Vulkan device");

    count = 0;
    vkGetPhysicalDeviceSurfacePresentModesKHR(pd, dev_->surface(), &count, nullptr);
    std::vector<VkPresentModeKHR> modes(count);
    vkGetPhysicalDeviceSurfacePresentModesKHR(pd, dev_->surface(), &count, modes.data());
    presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
    if (!options_.vsync) {
        for (VkPresentModeKHR want : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
            if (std::find(modes.begin(), modes.end(), want) != modes.end()) {
                presentMode_ = want;
                break;
            }
    }

    VkResult r;
    {
        const VkAttachmentDescription a = attachment(format_, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_STORE,
                                                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
        VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
        VkSubpassDescription sub{};
        sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        sub.colorAttachmentCount = 1;
        sub.pColorAttachments = &ref;
        VkSubpassDependency dep{};
        dep.srcSubpass = VK_SUBPASS_EXTERNAL;
        dep.dstSubpass = 0;
        dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
        dep.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
        dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        auto rp = vkInit<VkRenderPassCreateInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO);
        rp.attachmentCount = 1;
        rp.pAttachments = &a;
        rp.subpassCount = 1;
        rp.pSubpasses = &sub;
        rp.dependencyCount = 1;
        rp.pDependencies = &dep;
        if ((r = vkCreateRenderPass(device, &rp, nullptr, &uiPass_)) != VK_SUCCESS) return vkError("vkCreateRenderPass", r);
    }
    auto sci = vkInit<VkSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO);
    auto fci = vkInit<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    fci.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    for (std::size_t f = 0; f < kFrames; ++f) {
        if ((r = vkCreateSemaphore(device, &sci, nullptr, &acquired_[f])) != VK_SUCCESS) return vkError("vkCreateSemaphore", r);
        if ((r = vkCreateFence(device, &fci, nullptr, &fence_[f])) != VK_SUCCESS) return vkError("vkCreateFence", r);
    }
    auto pci = vkInit<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = dev_->queueFamily();
    if ((r = vkCreateCommandPool(device, &pci, nullptr, &pool_)) != VK_SUCCESS) return vkError("vkCreateCommandPool", r);
    auto cai = vkInit<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    cai.commandPool = pool_;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = static_cast<std::uint32_t>(kFrames);
    if ((r = vkAllocateCommandBuffers(device, &cai, cmd_.data())) != VK_SUCCESS) return vkError("vkAllocateCommandBuffers", r);
    return createSwapchain();
}

Status Presenter::createSwapchain() {
    VkDevice device = dev_->device();
    VkSurfaceCapabilitiesKHR caps;
    VkResult r = vkGetPhysicalDeviceSurfaceCapabilitiesKHR(dev_->physicalDevice(), dev_->surface(), &caps);
    if (r != VK_SUCCESS) return vkError("vkGetPhysicalDeviceSurfaceCapabilitiesKHR", r);
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        return makeError("the window surface's images cannot be transfer destinations on this Vulkan device");
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == UINT32_MAX) {
        extent.width = std::clamp(requested_.width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(requested_.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (extent.width == 0 || extent.height == 0) {  // minimised: try again later
        extent_ = extent;
        recreate_ = true;
        return {};
    }
    std::uint32_t want = std::max(caps.minImageCount + 1, 2u);
    if (caps.maxImageCount > 0) want = std::min(want, caps.maxImageCount);
    minImages_ = std::max(caps.minImageCount, 2u);
    VkCompositeAlphaFlagBitsKHR alpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    if (!(caps.supportedCompositeAlpha & alpha)) {
        for (VkCompositeAlphaFlagBitsKHR a : {VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR, VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR,
                                              VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR})
            if (caps.supportedCompositeAlpha & a) {
                alpha = a;
                break;
            }
    }
    auto ci = vkInit<VkSwapchainCreateInfoKHR>(VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR);
    ci.surface = dev_->surface();
    ci.minImageCount = want;
    ci.imageFormat = format_;
    ci.imageColorSpace = colorSpace_;
    ci.imageExtent = extent;
    ci.imageArrayLayers = 1;
    canCapture_ = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;
    ci.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                    (canCapture_ ? static_cast<VkImageUsageFlags>(VK_IMAGE_USAGE_TRANSFER_SRC_BIT) : 0u);
    ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.preTransform = caps.currentTransform;
    ci.compositeAlpha = alpha;
    ci.presentMode = presentMode_;
    ci.clipped = VK_TRUE;
    ci.oldSwapchain = swapchain_;
    VkSwapchainKHR created = VK_NULL_HANDLE;
    r = vkCreateSwapchainKHR(device, &ci, nullptr, &created);
    destroySwapchainResources();
    if (swapchain_) vkDestroySwapchainKHR(device, swapchain_, nullptr);
    swapchain_ = created;
    if (r != VK_SUCCESS) return vkError("vkCreateSwapchainKHR", r);
    extent_ = extent;

    std::uint32_t n = 0;
    vkGetSwapchainImagesKHR(device, swapchain_, &n, nullptr);
    images_.resize(n);
    vkGetSwapchainImagesKHR(device, swapchain_, &n, images_.data());
    for (VkImage img : images_) {
        auto vci = vkInit<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
        vci.image = img;
        vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
        vci.format = format_;
        vci.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view = VK_NULL_HANDLE;
        if ((r = vkCreateImageView(device, &vci, nullptr, &view)) != VK_SUCCESS) return vkError("vkCreateImageView", r);
        views_.push_back(view);
        auto fb = vkInit<VkFramebufferCreateInfo>(VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO);
        fb.renderPass = uiPass_;
        fb.attachmentCount = 1;
        fb.pAttachments = &view;
        fb.width = extent.width;
        fb.height = extent.height;
        fb.layers = 1;
        VkFramebuffer f = VK_NULL_HANDLE;
        if ((r = vkCreateFramebuffer(device, &fb, nullptr, &f)) != VK_SUCCESS) return vkError("vkCreateFramebuffer", r);
        framebuffers_.push_back(f);
        auto sci = vkInit<VkSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO);
        VkSemaphore s = VK_NULL_HANDLE;
        if ((r = vkCreateSemaphore(device, &sci, nullptr, &s)) != VK_SUCCESS) return vkError("vkCreateSemaphore", r);
        renderDone_.push_back(s);
    }
    recreate_ = false;
    return {};
}

void Presenter::destroySwapchainResources() {
    VkDevice device = dev_->device();
    for (VkFramebuffer f : framebuffers_) vkDestroyFramebuffer(device, f, nullptr);
    for (VkImageView v : views_) vkDestroyImageView(device, v, nullptr);
    for (VkSemaphore s : renderDone_) vkDestroySemaphore(device, s, nullptr);
    framebuffers_.clear();
    views_.clear();
    renderDone_.clear();
    images_.clear();
}

Presenter::~Presenter() {
    if (!dev_) return;
    VkDevice device = dev_->device();
    vkDeviceWaitIdle(device);
    if (capture_) capture_->buffer.destroy(device);
    destroySwapchainResources();
    if (swapchain_) vkDestroySwapchainKHR(device, swapchain_, nullptr);
    for (VkSemaphore s : acquired_)
        if (s) vkDestroySemaphore(device, s, nullptr);
    for (VkFence f : fence_)
        if (f) vkDestroyFence(device, f, nullptr);
    if (pool_) vkDestroyCommandPool(device, pool_, nullptr);
    if (uiPass_) vkDestroyRenderPass(device, uiPass_, nullptr);
}

bool Presenter::captureNextFrame(Image* out) {
    if (!canCapture_) return false;
    captureTarget_ = out;
    return true;
}

void Presenter::resize(int width, int height) {
    const VkExtent2D e{static_cast<std::uint32_t>(std::max(width, 0)), static_cast<std::uint32_t>(std::max(height, 0))};
    if (e.width != requested_.width || e.height != requested_.height) {
        requested_ = e;
        recreate_ = true;
    }
}

Status Presenter::present(Renderer& renderer, const FrameDescription& frame, const UiRecorder* ui) {
    VkDevice device = dev_->device();
    // This frame's semaphore, fence and command buffer were last used two frames ago.
    VkFence fence = fence_[frame_];
    VkCommandBuffer cmd = cmd_[frame_];
    VkSemaphore acquired = acquired_[frame_];
    VkResult r = vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX);
    if (r != VK_SUCCESS) return vkError("vkWaitForFences", r);
    if (recreate_ || !swapchain_) {
        if (Status s = dev_->waitIdle(); !s) return s;
        if (Status s = createSwapchain(); !s) return s;
        if (recreate_) return {};  // still zero-sized
    }
    std::uint32_t index = 0;
    r = vkAcquireNextImageKHR(device, swapchain_, UINT64_MAX, acquired, VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        recreate_ = true;
        return {};
    }
    if (r == VK_SUBOPTIMAL_KHR) recreate_ = true;
    else if (r != VK_SUCCESS) return vkError("vkAcquireNextImageKHR", r);

    if (static_cast<std::uint32_t>(renderer.width()) != extent_.width ||
        static_cast<std::uint32_t>(renderer.height()) != extent_.height) {
        if (Status s = renderer.resize(static_cast<int>(extent_.width), static_cast<int>(extent_.height)); !s) return s;
    }
    // The acquire semaphore is signalled now or soon; if prepare fails the
    // frame must still consume it, so errors are reported after the submit.
    Status prepared = renderer.prepare(frame);

    if ((r = vkResetCommandBuffer(cmd, 0)) != VK_SUCCESS) return vkError("vkResetCommandBuffer", r);
    auto bi = vkInit<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if ((r = vkBeginCommandBuffer(cmd, &bi)) != VK_SUCCESS) return vkError("vkBeginCommandBuffer", r);
    const VkImage target = images_[index];
    if (prepared) renderer.record(cmd);
    gpu::imageBarrier(cmd, target, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                      VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    if (prepared) {
        VkImageBlit blit{};
        blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        blit.srcOffsets[1] = {renderer.width(), renderer.height(), 1};
        blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        blit.dstOffsets[1] = {static_cast<std::int32_t>(extent_.width), static_cast<std::int32_t>(extent_.height), 1};
        vkCmdBlitImage(cmd, renderer.outputImage(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_NEAREST);
    } else {
        const VkClearColorValue black{{0.0f, 0.0f, 0.0f, 1.0f}};
        const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &range);
    }
    gpu::imageBarrier(cmd, target, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
    auto rbi = vkInit<VkRenderPassBeginInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO);
    rbi.renderPass = uiPass_;
    rbi.framebuffer = framebuffers_[index];
    rbi.renderArea = {{0, 0}, extent_};
    vkCmdBeginRenderPass(cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
    if (ui && *ui && prepared) (*ui)(cmd);
    vkCmdEndRenderPass(cmd);
    Image* capture = prepared ? captureTarget_ : nullptr;
    if (capture) {
        const VkDeviceSize bytes = VkDeviceSize(extent_.width) * extent_.height * 4;
        if (!capture_) capture_ = std::make_unique<Capture>();
        if (capture_->buffer.size < bytes) {
            capture_->buffer.destroy(device);
            if (Status s = capture_->buffer.create(*dev_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUse::Readback); !s)
                return s;
        }
        // The image is in PRESENT_SRC after the UI pass: copy, then back.
        gpu::imageBarrier(cmd, target, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                          VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                          VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {extent_.width, extent_.height, 1};
        vkCmdCopyImageToBuffer(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, capture_->buffer.buffer, 1, &region);
        gpu::imageBarrier(cmd, target, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                          VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_ACCESS_TRANSFER_READ_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT,
                          VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
        VkBufferMemoryBarrier hb = vkInit<VkBufferMemoryBarrier>(VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER);
        hb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        hb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        hb.srcQueueFamilyIndex = hb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        hb.buffer = capture_->buffer.buffer;
        hb.size = VK_WHOLE_SIZE;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &hb, 0, nullptr);
    }
    if ((r = vkEndCommandBuffer(cmd)) != VK_SUCCESS) return vkError("vkEndCommandBuffer", r);

    const VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    auto si = vkInit<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &acquired;
    si.pWaitDstStageMask = &waitStage;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &renderDone_[index];
    if ((r = vkResetFences(device, 1, &fence)) != VK_SUCCESS) return vkError("vkResetFences", r);
    if ((r = vkQueueSubmit(dev_->queue(), 1, &si, fence)) != VK_SUCCESS) return vkError("vkQueueSubmit", r);
    if (prepared) renderer.submitted(fence);

    auto pi = vkInit<VkPresentInfoKHR>(VK_STRUCTURE_TYPE_PRESENT_INFO_KHR);
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &renderDone_[index];
    pi.swapchainCount = 1;
    pi.pSwapchains = &swapchain_;
    pi.pImageIndices = &index;
    r = vkQueuePresentKHR(dev_->queue(), &pi);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) recreate_ = true;
    else if (r != VK_SUCCESS) return vkError("vkQueuePresentKHR", r);
    ++presented_;
    frame_ = (frame_ + 1) % kFrames;
    if (capture) {
        if ((r = vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX)) != VK_SUCCESS) return vkError("vkWaitForFences", r);
        capture->resize(static_cast<int>(extent_.width), static_cast<int>(extent_.height));
        const auto* src = static_cast<const std::uint8_t*>(capture_->buffer.mapped);
        const bool bgra = format_ == VK_FORMAT_B8G8R8A8_UNORM || format_ == VK_FORMAT_B8G8R8A8_SRGB;
        for (std::size_t i = 0; i < capture->rgba.size(); i += 4) {
            capture->rgba[i + 0] = src[i + (bgra ? 2 : 0)];
            capture->rgba[i + 1] = src[i + 1];
            capture->rgba[i + 2] = src[i + (bgra ? 0 : 2)];
            capture->rgba[i + 3] = 255;
        }
        captureTarget_ = nullptr;
    }
    return prepared;
}

}  // namespace fray::render
