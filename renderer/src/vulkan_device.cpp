#include "fray/render/vulkan_device.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include "vk_init.h"

namespace fray::render {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr const char* kNoDevice = "no Vulkan device found; install mesa-vulkan-drivers (lavapipe) or a GPU driver";

VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
    auto* log = static_cast<ValidationLog*>(user);
    log->add(severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
             data && data->pMessage ? data->pMessage : "(no message)");
    return VK_FALSE;
}

bool envIs(const char* name, std::string_view value) {
    const char* v = std::getenv(name);
    return v && std::string_view(v) == value;
}

int typeRank(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

const char* typeName(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
        default: return "other";
    }
}

}  // namespace

void ValidationLog::add(bool error, std::string message) {
    std::lock_guard lock(mutex_);
    if (echo_) std::fprintf(stderr, "vulkan validation %s: %s\n", error ? "error" : "warning", message.c_str());
    (error ? errors_ : warnings_)++;
    messages_.push_back(std::move(message));
}

int ValidationLog::errors() const {
    std::lock_guard lock(mutex_);
    return errors_;
}

int ValidationLog::warnings() const {
    std::lock_guard lock(mutex_);
    return warnings_;
}

std::vector<std::string> ValidationLog::messages() const {
    std::lock_guard lock(mutex_);
    return messages_;
}

void ValidationLog::setEcho(bool echo) {
    std::lock_guard lock(mutex_);
    echo_ = echo;
}

std::string vkResultName(VkResult r) {
    switch (r) {
#define FRAY_VK_CASE(x) \
    case x: return #x;
        FRAY_VK_CASE(VK_SUCCESS)
        FRAY_VK_CASE(VK_NOT_READY)
        FRAY_VK_CASE(VK_TIMEOUT)
        FRAY_VK_CASE(VK_INCOMPLETE)
        FRAY_VK_CASE(VK_SUBOPTIMAL_KHR)
        FRAY_VK_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        FRAY_VK_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        FRAY_VK_CASE(VK_ERROR_INITIALIZATION_FAILED)
        FRAY_VK_CASE(VK_ERROR_DEVICE_LOST)
        FRAY_VK_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        FRAY_VK_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        FRAY_VK_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        FRAY_VK_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        FRAY_VK_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        FRAY_VK_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        FRAY_VK_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        FRAY_VK_CASE(VK_ERROR_SURFACE_LOST_KHR)
        FRAY_VK_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
        FRAY_VK_CASE(VK_ERROR_OUT_OF_DATE_KHR)
#undef FRAY_VK_CASE
        default: return "VkResult " + std::to_string(static_cast<int>(r));
    }
}

Error vkError(const char* call, VkResult result) { return makeError(std::string(call) + " failed: " + vkResultName(result)); }

Result<std::shared_ptr<VulkanDevice>> VulkanDevice::create(const DeviceOptions& options) {
    std::shared_ptr<VulkanDevice> dev(new VulkanDevice());
    if (Status s = dev->init(options); !s) return s.error();
    return dev;
}

Status VulkanDevice::init(const DeviceOptions& options) {
    const bool validation = options.validation || envIs("FRAY_VULKAN_VALIDATION", "1");
    ownsSurface_ = options.ownsSurface;

    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    for (const auto& e : options.instanceExtensions) extensions.push_back(e.c_str());
    if (validation) {
        std::uint32_t count = 0;
        vkEnumerateInstanceLayerProperties(&count, nullptr);
        std::vector<VkLayerProperties> props(count);
        vkEnumerateInstanceLayerProperties(&count, props.data());
        const bool found = std::any_of(props.begin(), props.end(),
                                       [](const VkLayerProperties& p) { return std::strcmp(p.layerName, kValidationLayer) == 0; });
        if (!found)
            return makeError("Vulkan validation was requested but VK_LAYER_KHRONOS_validation is not installed; "
                             "install vulkan-validationlayers");
        layers.push_back(kValidationLayer);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }

    auto app = vkInit<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
    app.pApplicationName = options.applicationName.c_str();
    app.applicationVersion = VK_MAKE_VERSION(0, 1, 0);
    app.pEngineName = "fray";
    app.engineVersion = VK_MAKE_VERSION(0, 1, 0);
    app.apiVersion = VK_API_VERSION_1_2;

    auto dbg = vkInit<VkDebugUtilsMessengerCreateInfoEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
    dbg.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    dbg.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    dbg.pfnUserCallback = debugCallback;
    dbg.pUserData = log_.get();

    auto ici = vkInit<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
    ici.pApplicationInfo = &app;
    ici.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
    ici.ppEnabledLayerNames = layers.data();
    ici.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
    ici.ppEnabledExtensionNames = extensions.data();
    if (validation) ici.pNext = &dbg;  // also covers vkCreateInstance / vkDestroyInstance
    VkResult r = vkCreateInstance(&ici, nullptr, &instance_);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED) return makeError(kNoDevice);
    if (r == VK_ERROR_EXTENSION_NOT_PRESENT)
        return makeError("the Vulkan driver lacks an instance extension the window system needs (vkCreateInstance: "
                         "VK_ERROR_EXTENSION_NOT_PRESENT)");
    if (r != VK_SUCCESS) return vkError("vkCreateInstance", r);

    if (validation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) return makeError("VK_EXT_debug_utils is not available with the validation layer");
        if ((r = create(instance_, &dbg, nullptr, &messenger_)) != VK_SUCCESS)
            return vkError("vkCreateDebugUtilsMessengerEXT", r);
    }

    if (options.createSurface) {
        auto surface = options.createSurface(instance_);
        if (!surface) return surface.error();
        surface_ = *surface;
    }

    std::uint32_t count = 0;
    r = vkEnumeratePhysicalDevices(instance_, &count, nullptr);
    if (r != VK_SUCCESS && r != VK_INCOMPLETE) return makeError(kNoDevice);
    if (count == 0) return makeError(kNoDevice);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance_, &count, devices.data());

    DevicePreference pref = options.preference;
    if (envIs("FRAY_VULKAN_DEVICE", "cpu")) pref = DevicePreference::Cpu;
    if (envIs("FRAY_VULKAN_DEVICE", "gpu")) pref = DevicePreference::Gpu;

    int bestRank = 1 << 30;
    std::string rejected;
    for (VkPhysicalDevice pd : devices) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(pd, &props);
        const bool cpu = props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
        if ((pref == DevicePreference::Cpu && !cpu) || (pref == DevicePreference::Gpu && cpu)) continue;
        if (props.apiVersion < VK_API_VERSION_1_2) {
            rejected += std::string(rejected.empty() ? "" : "; ") + props.deviceName + " supports only Vulkan " +
                        std::to_string(VK_API_VERSION_MAJOR(props.apiVersion)) + "." +
                        std::to_string(VK_API_VERSION_MINOR(props.apiVersion));
            continue;
        }
        std::uint32_t qcount = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(pd, &qcount, nullptr);
        std::vector<VkQueueFamilyProperties> qprops(qcount);
        vkGetPhysicalDeviceQueueFamilyProperties(pd, &qcount, qprops.data());
        int family = -1;
        for (std::uint32_t q = 0; q < qcount && family < 0; ++q) {
            if (!(qprops[q].queueFlags & VK_QUEUE_GRAPHICS_BIT)) continue;
            if (surface_) {
                VkBool32 present = VK_FALSE;
                vkGetPhysicalDeviceSurfaceSupportKHR(pd, q, surface_, &present);
                if (!present) continue;
            }
            family = static_cast<int>(q);
        }
        if (family < 0) {
            rejected += std::string(rejected.empty() ? "" : "; ") + props.deviceName +
                        (surface_ ? " cannot present to the window" : " has no graphics queue");
            continue;
        }
        const int rank = typeRank(props.deviceType);
        if (rank < bestRank) {
            bestRank = rank;
            physical_ = pd;
            queueFamily_ = static_cast<std::uint32_t>(family);
            properties_ = props;
        }
    }
    if (!physical_) {
        if (pref == DevicePreference::Cpu)
            return makeError("no CPU Vulkan device (lavapipe) found; install mesa-vulkan-drivers" +
                             (rejected.empty() ? std::string() : " (" + rejected + ")"));
        if (!rejected.empty()) return makeError("no usable Vulkan device: " + rejected);
        return makeError(kNoDevice);
    }
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

    const float priority = 1.0f;
    auto qci = vkInit<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
    qci.queueFamilyIndex = queueFamily_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    std::vector<const char*> devExtensions;
    if (surface_ || options.swapchain) {
        std::uint32_t n = 0;
        vkEnumerateDeviceExtensionProperties(physical_, nullptr, &n, nullptr);
        std::vector<VkExtensionProperties> props(n);
        vkEnumerateDeviceExtensionProperties(physical_, nullptr, &n, props.data());
        const bool has = std::any_of(props.begin(), props.end(), [](const VkExtensionProperties& e) {
            return std::strcmp(e.extensionName, VK_KHR_SWAPCHAIN_EXTENSION_NAME) == 0;
        });
        if (!has) return makeError(std::string(properties_.deviceName) + " cannot present to windows (no VK_KHR_swapchain)");
        devExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
        swapchainEnabled_ = true;
    }
    VkPhysicalDeviceFeatures features{};
    auto dci = vkInit<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.enabledExtensionCount = static_cast<std::uint32_t>(devExtensions.size());
    dci.ppEnabledExtensionNames = devExtensions.data();
    dci.pEnabledFeatures = &features;
    if ((r = vkCreateDevice(physical_, &dci, nullptr, &device_)) != VK_SUCCESS) return vkError("vkCreateDevice", r);
    vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);

    auto pci = vkInit<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = queueFamily_;
    if ((r = vkCreateCommandPool(device_, &pci, nullptr, &oncePool_)) != VK_SUCCESS) return vkError("vkCreateCommandPool", r);
    auto cai = vkInit<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    cai.commandPool = oncePool_;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    if ((r = vkAllocateCommandBuffers(device_, &cai, &onceCmd_)) != VK_SUCCESS) return vkError("vkAllocateCommandBuffers", r);
    auto fci = vkInit<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    if ((r = vkCreateFence(device_, &fci, nullptr, &onceFence_)) != VK_SUCCESS) return vkError("vkCreateFence", r);
    return {};
}

VulkanDevice::~VulkanDevice() {
    if (device_) {
        vkDeviceWaitIdle(device_);
        if (onceFence_) vkDestroyFence(device_, onceFence_, nullptr);
        if (oncePool_) vkDestroyCommandPool(device_, oncePool_, nullptr);
        vkDestroyDevice(device_, nullptr);
    }
    if (instance_) {
        if (surface_ && ownsSurface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
        if (messenger_) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
            if (destroy) destroy(instance_, messenger_, nullptr);
        }
        vkDestroyInstance(instance_, nullptr);
    }
}

std::string VulkanDevice::description() const {
    const std::uint32_t v = properties_.apiVersion;
    return std::string(properties_.deviceName) + ", " + typeName(properties_.deviceType) + ", Vulkan " +
           std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
           std::to_string(VK_API_VERSION_PATCH(v));
}

std::uint32_t VulkanDevice::findMemoryType(std::uint32_t typeBits, VkMemoryPropertyFlags required,
                                           VkMemoryPropertyFlags preferred) const {
    std::uint32_t fallback = UINT32_MAX;
    for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
        if (!(typeBits & (1u << i))) continue;
        const VkMemoryPropertyFlags f = memory_.memoryTypes[i].propertyFlags;
        if ((f & required) != required) continue;
        if ((f & preferred) == preferred) return i;
        if (fallback == UINT32_MAX) fallback = i;
    }
    return fallback;
}

Status VulkanDevice::runOnce(const std::function<void(VkCommandBuffer)>& record) {
    VkResult r = vkResetCommandBuffer(onceCmd_, 0);
    if (r != VK_SUCCESS) return vkError("vkResetCommandBuffer", r);
    auto bi = vkInit<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if ((r = vkBeginCommandBuffer(onceCmd_, &bi)) != VK_SUCCESS) return vkError("vkBeginCommandBuffer", r);
    record(onceCmd_);
    if ((r = vkEndCommandBuffer(onceCmd_)) != VK_SUCCESS) return vkError("vkEndCommandBuffer", r);
    auto si = vkInit<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    si.commandBufferCount = 1;
    si.pCommandBuffers = &onceCmd_;
    if ((r = vkResetFences(device_, 1, &onceFence_)) != VK_SUCCESS) return vkError("vkResetFences", r);
    if ((r = vkQueueSubmit(queue_, 1, &si, onceFence_)) != VK_SUCCESS) return vkError("vkQueueSubmit", r);
    if ((r = vkWaitForFences(device_, 1, &onceFence_, VK_TRUE, UINT64_MAX)) != VK_SUCCESS) return vkError("vkWaitForFences", r);
    return {};
}

Status VulkanDevice::attachSurface(VkSurfaceKHR surface, bool owns) {
    if (!swapchainEnabled_) return makeError("the Vulkan device was created without swapchain support");
    if (!surface) return makeError("no window surface");
    VkBool32 present = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(physical_, queueFamily_, surface, &present);
    if (!present) return makeError(std::string(properties_.deviceName) + " cannot present to this window");
    detachSurface();
    surface_ = surface;
    ownsSurface_ = owns;
    return {};
}

void VulkanDevice::detachSurface() {
    if (surface_ && ownsSurface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
    surface_ = VK_NULL_HANDLE;
}

Status VulkanDevice::waitIdle() {
    const VkResult r = vkDeviceWaitIdle(device_);
    if (r != VK_SUCCESS) return vkError("vkDeviceWaitIdle", r);
    return {};
}

}  // namespace fray::render
