#pragma once
// The Vulkan instance, physical device, logical device and graphics queue one
// process renders with. Shared (shared_ptr) by the Renderer, a Presenter and
// an application's UI layer (ImGui, Qt), and outlives all of them.
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "fray/core/result.h"

namespace fray::render {

// Messages of VK_LAYER_KHRONOS_validation (through VK_EXT_debug_utils).
// Warnings and errors are counted and kept; tests require both counts to be 0.
class ValidationLog {
public:
    void add(bool error, std::string message);
    int errors() const;
    int warnings() const;
    std::vector<std::string> messages() const;
    void setEcho(bool echo);  // also print each message on stderr (default on)

private:
    mutable std::mutex mutex_;
    int errors_ = 0;
    int warnings_ = 0;
    bool echo_ = true;
    std::vector<std::string> messages_;
};

enum class DevicePreference {
    Any,  // discrete GPU, then integrated, virtual, CPU (FRAY_VULKAN_DEVICE=cpu|gpu overrides)
    Cpu,  // a CPU implementation (lavapipe) only: reproducible pictures for tests
    Gpu,  // a hardware GPU only
};

struct DeviceOptions {
    std::string applicationName = "fray";
    bool validation = false;  // VK_LAYER_KHRONOS_validation + a debug messenger (also FRAY_VULKAN_VALIDATION=1)
    DevicePreference preference = DevicePreference::Any;
    std::vector<std::string> instanceExtensions;  // e.g. the window system's surface extensions
    // On-screen use: creates the window surface once the instance exists; the
    // device is then chosen among those whose graphics queue can present to it.
    std::function<Result<VkSurfaceKHR>(VkInstance)> createSurface;
    bool ownsSurface = true;  // destroy the surface with the device (false when e.g. Qt owns it)
    // Enable VK_KHR_swapchain without a surface yet, for toolkits whose window
    // surface exists only once the window is shown (Qt); see attachSurface.
    bool swapchain = false;
};

class VulkanDevice {
public:
    // Errors a user can act on: no Vulkan driver or device ("no Vulkan device
    // found; install mesa-vulkan-drivers (lavapipe) or a GPU driver"), missing
    // validation layer, no device that can present to the window.
    static Result<std::shared_ptr<VulkanDevice>> create(const DeviceOptions& options);
    ~VulkanDevice();
    VulkanDevice(const VulkanDevice&) = delete;
    VulkanDevice& operator=(const VulkanDevice&) = delete;

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physicalDevice() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    std::uint32_t queueFamily() const { return queueFamily_; }
    VkSurfaceKHR surface() const { return surface_; }
    const VkPhysicalDeviceProperties& properties() const { return properties_; }
    // "llvmpipe (LLVM 15.0.6, 256 bits), CPU, Vulkan 1.3.230"
    std::string description() const;
    bool isCpu() const { return properties_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }

    bool validationEnabled() const { return messenger_ != VK_NULL_HANDLE; }
    const std::shared_ptr<ValidationLog>& validationLog() const { return log_; }

    // First memory type allowed by typeBits that has all of `required`;
    // prefers one that also has `preferred`. UINT32_MAX when none.
    std::uint32_t findMemoryType(std::uint32_t typeBits, VkMemoryPropertyFlags required,
                                 VkMemoryPropertyFlags preferred = 0) const;

    // Records with `record`, submits and waits (uploads, one-off transitions).
    Status runOnce(const std::function<void(VkCommandBuffer)>& record);

    Status waitIdle();

    // A window surface created after the device (DeviceOptions::swapchain).
    // Fails when the device's queue cannot present to it.
    Status attachSurface(VkSurfaceKHR surface, bool owns);
    // Forgets (and destroys, when owned) the surface; call after the swapchain is gone.
    void detachSurface();

private:
    VulkanDevice() = default;
    Status init(const DeviceOptions& options);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    bool ownsSurface_ = true;
    bool swapchainEnabled_ = false;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties properties_{};
    VkPhysicalDeviceMemoryProperties memory_{};
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    std::uint32_t queueFamily_ = 0;
    VkCommandPool oncePool_ = VK_NULL_HANDLE;
    VkCommandBuffer onceCmd_ = VK_NULL_HANDLE;
    VkFence onceFence_ = VK_NULL_HANDLE;
    std::shared_ptr<ValidationLog> log_ = std::make_shared<ValidationLog>();
};

// "vkCreateDevice: VK_ERROR_OUT_OF_HOST_MEMORY".
std::string vkResultName(VkResult result);
Error vkError(const char* call, VkResult result);

}  // namespace fray::render
