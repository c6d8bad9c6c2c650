#pragma once
// On-screen output: a swapchain on the device's window surface. Each frame the
// renderer draws into its own image, which is blitted into the swapchain image;
// then an optional UI pass (ImGui in fray-play) draws on top and the image is
// presented. The renderer follows the swapchain's size.
#include <functional>
#include <array>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "fray/core/result.h"
#include "fray/render/renderer.h"
#include "fray/render/vulkan_device.h"

namespace fray::render {

struct PresenterOptions {
    bool vsync = true;  // FIFO; otherwise mailbox or immediate when available
};

class Presenter {
public:
    // The device must have been created with a surface (DeviceOptions::createSurface).
    // width/height: the window's framebuffer size, used when the surface does not dictate one.
    static Result<std::unique_ptr<Presenter>> create(std::shared_ptr<VulkanDevice> device, int width, int height,
                                                     const PresenterOptions& options = {});
    ~Presenter();
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;

    using UiRecorder = std::function<void(VkCommandBuffer)>;
    // Renders, blits, runs `ui` inside uiRenderPass(), presents. An out-of-date
    // or zero-sized swapchain is recreated and the frame skipped (not an error).
    Status present(Renderer& renderer, const FrameDescription& frame, const UiRecorder* ui = nullptr);
    // The window's framebuffer size changed.
    void resize(int width, int height);

    // Copies the next presented image (scene and UI, as shown) into `out` as
    // RGBA8 once that frame has been submitted. False when the surface's images
    // cannot be copied from (then use Renderer::readback for the scene alone).
    bool captureNextFrame(Image* out);

    VkRenderPass uiRenderPass() const { return uiPass_; }
    VkFormat format() const { return format_; }
    VkExtent2D extent() const { return extent_; }
    std::uint32_t imageCount() const { return static_cast<std::uint32_t>(images_.size()); }
    std::uint32_t minImageCount() const { return minImages_; }
    int framesPresented() const { return presented_; }

private:
    Presenter() = default;
    Status init(int width, int height);
    Status createSwapchain();
    void destroySwapchainResources();

    std::shared_ptr<VulkanDevice> dev_;
    PresenterOptions options_;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkColorSpaceKHR colorSpace_ = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    VkPresentModeKHR presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
    VkExtent2D extent_{0, 0};
    VkExtent2D requested_{0, 0};
    std::uint32_t minImages_ = 2;
    std::vector<VkImage> images_;
    std::vector<VkImageView> views_;
    std::vector<VkFramebuffer> framebuffers_;
    std::vector<VkSemaphore> renderDone_;
    // Two frames in flight: the CPU records frame n + 1 while the device
    // draws frame n (each with its own semaphore, fence and commands).
    static constexpr std::size_t kFrames = 2;
    std::array<VkSemaphore, kFrames> acquired_{};
    std::array<VkFence, kFrames> fence_{};
    std::array<VkCommandBuffer, kFrames> cmd_{};
    std::size_t frame_ = 0;
    VkRenderPass uiPass_ = VK_NULL_HANDLE;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    bool recreate_ = false;
    int presented_ = 0;
    bool canCapture_ = false;
    Image* captureTarget_ = nullptr;
    struct Capture;  // readback buffer (presenter.cpp)
    std::unique_ptr<Capture> capture_;
};

}  // namespace fray::render
