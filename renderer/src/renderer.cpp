#include "fray/render/renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "fray/render/font.h"
#include "gpu.h"
#include "vk_init.h"
#include "overlay_builder.h"

// SPIR-V compiled from resources/shaders at build time.
#include "fray_shaders/body_card_vert.h"
#include "fray_shaders/body_frag.h"
#include "fray_shaders/body_skinned_vert.h"
#include "fray_shaders/body_vert.h"
#include "fray_shaders/floor_frag.h"
#include "fray_shaders/floor_vert.h"
#include "fray_shaders/overlay_frag.h"
#include "fray_shaders/overlay_vert.h"
#include "fray_shaders/shadow_skinned_vert.h"
#include "fray_shaders/shadow_vert.h"

namespace fray::render {

namespace {

// std140 layout of FrameUniforms in resources/shaders/common.glsl.
struct FrameUniforms {
    glm::mat4 viewProj;
    glm::mat4 lightViewProj;
    glm::vec4 cameraPos;
    glm::vec4 lightDir;
    glm::vec4 lightColor;
    glm::vec4 skyColor;
    glm::vec4 groundColor;
    glm::vec4 floorColor;
    glm::vec4 floorArea;
    glm::vec4 bitmapRect;
    glm::vec4 floorParams;
    glm::vec4 shadowParams;
    glm::vec4 highlightColor;
    glm::vec4 fogColor;
};

struct GpuInstance {
    std::uint32_t paletteOffset;
    std::uint32_t flags;
    std::uint32_t pad0;
    std::uint32_t pad1;
    glm::vec4 tint;
};
static_assert(sizeof(GpuInstance) == 32);

struct GpuJoint {
    glm::vec4 position;
    glm::vec4 rotation;  // x, y, z, w
};
static_assert(sizeof(GpuJoint) == 32);

// A capsule of the coarsest level of detail as a hexagonal card facing the
// camera (resources/shaders/body_card.vert): six vertices, four triangles.
struct CardVertex {
    glm::vec3 anchor;  // this end of the capsule, joint-local
    float radius;
    glm::vec3 other;      // the other end
    std::uint32_t corner;  // joint (24 bits) | corner << 24 | second end << 26
};
static_assert(sizeof(CardVertex) == 32);

// Levels of detail: [0] as configured, [1] 6-sided capsules with one cap ring,
// [2] 4-sided ones, [3] cards (kCardLod; Fast quality only, in their own
// buffers), [4] far cards (kFarCardLod: the cards of the largest capsules,
// the same vertices, fewer indices).
constexpr int kLevels = 5;
constexpr int kCardLod = 3;
constexpr int kFarCardLod = 4;
inline bool isCardLod(int lod) { return lod >= kCardLod; }
// The share of a body's side-on capsule area its far cards keep.
constexpr float kFarCardArea = 0.9f;

// A skeleton's body in every level of detail.
struct MeshEntry {
    std::uint64_t fingerprint = 0;
    int jointCount = 0;
    std::array<std::uint32_t, kLevels> firstIndex{};
    std::array<std::uint32_t, kLevels> indexCount{};
    std::array<std::int32_t, kLevels> vertexOffset{};
};

// A skeleton's rig (Renderer::setRig): its mesh (CPU copy; the GPU buffers
// hold every rig's, rebuilt when a rig is set or cleared) and the inverse
// binds that turn world joint transforms into skinning transforms.
struct RigEntry {
    std::uint64_t fingerprint = 0;
    int jointCount = 0;
    std::vector<SkinnedVertex> vertices;
    std::vector<std::uint32_t> indices;
    std::vector<RigidTransform> inverseBind;
    float reach = 0.0f;  // how far the body reaches beyond its joints (m)
    std::uint32_t firstIndex = 0;
    std::int32_t vertexOffset = 0;
};

// One instanced draw: instances [firstInstance, firstInstance + count) share a
// mesh and a level of detail; the first `visible` of them are in the view
// (the shadow pass draws them all, the main pass only those). `mesh` indexes
// the capsule bodies, or the rigs when `rig` is set (level 0 only).
struct DrawGroup {
    int mesh;
    int lod;
    std::uint32_t firstInstance;
    std::uint32_t count;
    std::uint32_t visible;
    bool rig;
};

constexpr std::array<BodyMeshOptions, 2> kCoarseBodies{{{6, 1}, {4, 1}}};

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;
// Frames whose per-frame buffers exist at once: the CPU fills one while the
// device draws the other.
constexpr std::uint32_t kFramesInFlight = 2;

template <std::size_t N>
VkShaderModule makeShader(VkDevice device, const std::uint32_t (&code)[N]) {
    auto ci = vkInit<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    ci.codeSize = sizeof(code);
    ci.pCode = code;
    VkShaderModule m = VK_NULL_HANDLE;
    if (vkCreateShaderModule(device, &ci, nullptr, &m) != VK_SUCCESS) return VK_NULL_HANDLE;
    return m;
}

struct PipelineDesc {
    VkShaderModule vs = VK_NULL_HANDLE;
    VkShaderModule fs = VK_NULL_HANDLE;  // none: depth only
    const VkVertexInputBindingDescription* binding = nullptr;
    std::span<const VkVertexInputAttributeDescription> attributes;
    VkCullModeFlags cull = VK_CULL_MODE_NONE;
    bool depthTest = true;
    bool depthWrite = true;
    bool blend = false;
    bool depthBias = false;
    VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
    VkRenderPass pass = VK_NULL_HANDLE;
    const VkSpecializationInfo* spec = nullptr;  // fragment stage constants
};

// Fragment specialisation constants: 0 = shadows, 1 = floor bitmap, 2 = fog.
struct Variant {
    VkBool32 shadows;
    VkBool32 bitmap;
    VkBool32 fog;
};

}  // namespace

struct Renderer::Impl {
    std::shared_ptr<VulkanDevice> dev;
    VkDevice device = VK_NULL_HANDLE;
    RendererOptions options;
    int width = 0, height = 0;
    VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
    VkFormat depthFormat = VK_FORMAT_D32_SFLOAT;
    std::uint32_t shadowSize = 2048;

    VkRenderPass mainPass = VK_NULL_HANDLE, shadowPass = VK_NULL_HANDLE;
    gpu::Image colorMs, depth, resolve, shadowMap, fontAtlas, bitmap;
    VkFramebuffer mainFb = VK_NULL_HANDLE, shadowFb = VK_NULL_HANDLE;
    VkSampler shadowSampler = VK_NULL_HANDLE, bitmapSampler = VK_NULL_HANDLE, fontSampler = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    // Body and floor pipelines per variant (shadows, bitmap; the floor's also
    // fog: [.][.][0] for the square where fog is 0), created on first use.
    std::array<VkPipeline, 2> bodyPipes{};
    VkPipeline cardPipe = VK_NULL_HANDLE;  // created when cards are first drawn
    std::array<std::array<std::array<VkPipeline, 2>, 2>, 2> floorPipes{};
    // Rigs: per shadow variant, and their shadow pass; created when a rig is first drawn.
    std::array<VkPipeline, 2> rigPipes{};
    VkPipeline rigShadowPipe = VK_NULL_HANDLE;
    VkPipeline bodyPipe = VK_NULL_HANDLE, rigPipe = VK_NULL_HANDLE;  // this frame's
    std::array<VkPipeline, 2> floorPipe{};                            // this frame's, without and with fog
    VkPipeline shadowPipe = VK_NULL_HANDLE, overlayDepthPipe = VK_NULL_HANDLE, overlayTopPipe = VK_NULL_HANDLE;
    VkShaderModule bodyV = VK_NULL_HANDLE, bodyF = VK_NULL_HANDLE, floorV = VK_NULL_HANDLE, floorF = VK_NULL_HANDLE;
    VkShaderModule rigV = VK_NULL_HANDLE, rigShadowV = VK_NULL_HANDLE, cardV = VK_NULL_HANDLE;
    bool linearShadowFilter = false;
    bool fast = false;
    gpu::Buffer meshVB, meshIB, cardVB, cardIB, rigVB, rigIB, readbackBuf;
    VkCommandPool cmdPool = VK_NULL_HANDLE;
    // Per-frame data, kFramesInFlight copies: render() fills one while the
    // device may still draw the frame before it from the other, so the CPU
    // side of frame n + 1 overlaps the device's work on frame n.
    struct FrameSlot {
        gpu::Buffer uniforms, instanceBuf, paletteBuf, overlayBuf;
        VkDescriptorSet set = VK_NULL_HANDLE;
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        VkFence fence = VK_NULL_HANDLE;    // render()'s own submission of this slot
        VkFence pending = VK_NULL_HANDLE;  // signalled once the last submission reading this slot is done
        VkQueryPool timer = VK_NULL_HANDLE;  // two timestamps round render()'s commands (when the queue has them)
        bool timed = false;                  // the last submission wrote them
        bool descriptorsDirty = true;
    };
    std::array<FrameSlot, kFramesInFlight> slots{};
    std::size_t cur = 0;  // the slot prepare() writes and record() binds
    double timestampMs = 0.0;  // milliseconds per timestamp tick; 0: no timestamps
    FrameSlot& slot() { return slots[cur]; }
    Status waitSlot(FrameSlot& f);
    Status waitAll();  // before a buffer or image every frame reads is replaced

    // Body meshes, one per distinct skeleton (by fingerprint); CPU copies are
    // kept so the GPU buffers can be rebuilt when a new skeleton appears.
    std::vector<MeshEntry> meshes;
    std::vector<BodyVertex> meshVertices;
    std::vector<std::uint32_t> meshIndices;
    std::vector<CardVertex> cardVertices;
    std::vector<std::uint32_t> cardIndices;
    // Rigs by skeleton fingerprint; uploaded in the next prepare() when dirty.
    std::vector<RigEntry> rigs;
    bool rigsDirty = false;

    // Per-frame scratch, reused (no steady-state allocation).
    std::vector<std::pair<const Skeleton*, std::uint64_t>> bySkeleton;  // fingerprints seen this frame
    std::vector<std::uint32_t> groupStart, slotOf, bySlot, jointOffsetOf;  // counting sort of the characters into draw groups
    std::vector<std::uint64_t> characterFingerprint;
    std::vector<int> characterMesh;  // capsule body, or -1
    std::vector<int> characterRig;   // rig, or -1
    std::vector<std::uint8_t> characterLod;
    std::vector<std::uint8_t> characterVisible;
    std::vector<Bounds> characterBox;  // joint bounds, for culling and the blob shadows
    std::vector<DrawGroup> groups;
    std::array<float, 2> lodPixels{};  // below [k] pixels tall: level k + 1 (Fast: cards below [1])
    float farPixels = 0;               // below: far cards (Fast only; 0: none)
    OverlayBuilder overlays;
    std::array<std::uint32_t, 3> overlayFirst{}, overlayCount{};
    bool shadowsThisFrame = false;
    bool floorThisFrame = true;
    glm::mat4 viewProj{1.0f};
    glm::mat4 screenTransform{1.0f};
    glm::vec3 clearColor{0.6f};
    bool rendered = false;

    // Floor bitmap currently uploaded.
    const std::uint8_t* bitmapPixels = nullptr;
    int bitmapW = 0, bitmapH = 0;
    std::uint64_t bitmapRevision = 0;
    bool bitmapIsDefault = true;

    RenderStats stats;

    ~Impl() { destroy(); }
    Status init();
    Status createTargets();
    void destroyTargets();
    Status createPipelines();
    Status variantPipelines(bool shadows, bool withBitmap, bool withRigs, bool withCards);
    Status ensureBuffer(gpu::Buffer& b, VkDeviceSize needed, VkBufferUsageFlags usage, VkDeviceSize minimum);
    Status registerMesh(const Skeleton& skeleton, std::uint64_t fingerprint, int& index);
    Status uploadRigs();
    int rigOf(std::uint64_t fingerprint, int jointCount) const;
    Status updateBitmap(const FloorBitmap* fb);
    void writeDescriptors();
    Status prepare(const FrameDescription& frame);
    void record(VkCommandBuffer c);
    void recordBodies(VkCommandBuffer c, VkPipeline capsules, VkPipeline rigged, bool visibleOnly);
    void recordReadback(VkCommandBuffer c);
    void copyReadback(Image& out);
    void destroy();
};

// ---------------------------------------------------------------- creation

Status Renderer::Impl::init() {
    device = dev->device();
    VkPhysicalDevice pd = dev->physicalDevice();
    const VkPhysicalDeviceLimits& limits = dev->properties().limits;

    // MSAA: the largest supported count not above the request, for both colour and depth.
    const VkSampleCountFlags supported = limits.framebufferColorSampleCounts & limits.framebufferDepthSampleCounts;
    samples = VK_SAMPLE_COUNT_1_BIT;
    // Automatic: 4x on GPUs; none on a CPU device, where every sample is
    // rasterised and resolved in software (about 1.7x the frame time at 720p).
    fast = options.quality == Quality::Fast || (options.quality == Quality::Auto && dev->isCpu());
    const int wanted = options.msaaSamples > 0 ? options.msaaSamples : (fast ? 1 : 4);
    if (options.body.sides <= 0) options.body.sides = 8;
    if (options.body.capRings <= 0) options.body.capRings = 2;
    // Fast keeps full detail for close-ups only; High for anything of a useful size.
    const float lod1 = options.lodPixels >= 0 ? static_cast<float>(options.lodPixels) : (fast ? 240.0f : 60.0f);
    lodPixels = {lod1, lod1 * 0.4f};
    farPixels = !fast || options.farPixels == 0 || (options.farPixels < 0 && options.lodPixels == 0)
                    ? 0.0f
                    : (options.farPixels > 0 ? static_cast<float>(options.farPixels) : 40.0f);
    for (int s : {8, 4, 2}) {
        if (s <= wanted && (supported & static_cast<VkSampleCountFlags>(s))) {
            samples = static_cast<VkSampleCountFlagBits>(s);
            break;
        }
    }
    // Depth: D32 when it can be both an attachment and sampled (the shadow map), else D16.
    depthFormat = VK_FORMAT_UNDEFINED;
    for (VkFormat f : {VK_FORMAT_D32_SFLOAT, VK_FORMAT_D16_UNORM}) {
        VkFormatProperties fp;
        vkGetPhysicalDeviceFormatProperties(pd, f, &fp);
        const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
        if ((fp.optimalTilingFeatures & need) == need) {
            depthFormat = f;
            linearShadowFilter = (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT) != 0;
            break;
        }
    }
    if (depthFormat == VK_FORMAT_UNDEFINED) return makeError("the Vulkan device supports no sampled depth format");
    // Fast mode draws blob shadows; its shadow map only keeps the descriptor valid.
    const int wantedShadow = fast ? 16 : (options.shadowMapSize > 0 ? options.shadowMapSize : 2048);
    shadowSize = static_cast<std::uint32_t>(std::clamp(wantedShadow, 16, static_cast<int>(limits.maxImageDimension2D)));

    VkResult r;
    // Render passes.
    {
        std::vector<VkAttachmentDescription> att;
        VkAttachmentReference colorRef{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
        VkAttachmentReference depthRef{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
        VkAttachmentReference resolveRef{2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
        const bool ms = samples != VK_SAMPLE_COUNT_1_BIT;
        att.push_back(attachment(kColorFormat, samples, VK_ATTACHMENT_LOAD_OP_CLEAR, ms ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE,
                                 VK_IMAGE_LAYOUT_UNDEFINED, ms ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL));
        att.push_back(attachment(depthFormat, samples, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_DONT_CARE, VK_IMAGE_LAYOUT_UNDEFINED,
                                 VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL));
        if (ms) {
            att.push_back(attachment(kColorFormat, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_DONT_CARE, VK_ATTACHMENT_STORE_OP_STORE,
                                     VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL));
        }
        VkSubpassDescription sub{};
        sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        sub.colorAttachmentCount = 1;
        sub.pColorAttachments = &colorRef;
        sub.pDepthStencilAttachment = &depthRef;
        sub.pResolveAttachments = ms ? &resolveRef : nullptr;
        std::array<VkSubpassDependency, 2> deps{};
        // The previous frame's copy/blit of the output and its depth use finish
        // before this frame writes them.
        deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
        deps[0].dstSubpass = 0;
        deps[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                               VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
        deps[0].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        deps[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                               VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
        deps[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT |
                                VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
        // The resolved output is then copied (readback) or blitted (presenter).
        deps[1].srcSubpass = 0;
        deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
        deps[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
        deps[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        deps[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
        deps[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        auto rp = vkInit<VkRenderPassCreateInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO);
        rp.attachmentCount = static_cast<std::uint32_t>(att.size());
        rp.pAttachments = att.data();
        rp.subpassCount = 1;
        rp.pSubpasses = &sub;
        rp.dependencyCount = static_cast<std::uint32_t>(deps.size());
        rp.pDependencies = deps.data();
        if ((r = vkCreateRenderPass(device, &rp, nullptr, &mainPass)) != VK_SUCCESS) return vkError("vkCreateRenderPass", r);
    }
    {
        const VkAttachmentDescription d = attachment(depthFormat, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                                                     VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
        VkSubpassDescription sub{};
        sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        sub.pDepthStencilAttachment = &ref;
        std::array<VkSubpassDependency, 2> deps{};
        deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
        deps[0].dstSubpass = 0;
        deps[0].srcStageMask = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
        deps[0].srcAccessMask = 0;
        deps[0].dstStageMask = VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
        deps[0].dstAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        deps[1].srcSubpass = 0;
        deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
        deps[1].srcStageMask = VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
        deps[1].srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        deps[1].dstStageMask = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
        deps[1].dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
        auto rp = vkInit<VkRenderPassCreateInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO);
        rp.attachmentCount = 1;
        rp.pAttachments = &d;
        rp.subpassCount = 1;
        rp.pSubpasses = &sub;
        rp.dependencyCount = static_cast<std::uint32_t>(deps.size());
        rp.pDependencies = deps.data();
        if ((r = vkCreateRenderPass(device, &rp, nullptr, &shadowPass)) != VK_SUCCESS) return vkError("vkCreateRenderPass", r);
    }

    // Shadow map (kept in SHADER_READ_ONLY between frames so frames without
    // shadows still bind a valid image).
    if (Status s = shadowMap.create(*dev, shadowSize, shadowSize, depthFormat,
                                    VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                    VK_SAMPLE_COUNT_1_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
        !s)
        return s;
    {
        auto fb = vkInit<VkFramebufferCreateInfo>(VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO);
        fb.renderPass = shadowPass;
        fb.attachmentCount = 1;
        fb.pAttachments = &shadowMap.view;
        fb.width = shadowSize;
        fb.height = shadowSize;
        fb.layers = 1;
        if ((r = vkCreateFramebuffer(device, &fb, nullptr, &shadowFb)) != VK_SUCCESS) return vkError("vkCreateFramebuffer", r);
    }
    if (Status s = dev->runOnce([&](VkCommandBuffer c) {
            gpu::imageBarrier(c, shadowMap.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                              VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, 0, VK_ACCESS_SHADER_READ_BIT,
                              VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
        });
        !s)
        return s;

    // Samplers.
    {
        auto sc = vkInit<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
        sc.magFilter = sc.minFilter = VK_FILTER_NEAREST;
        sc.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        sc.addressModeU = sc.addressModeV = sc.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER;
        sc.borderColor = VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE;
        sc.compareEnable = VK_TRUE;
        sc.compareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
        sc.maxLod = 0.0f;
        if ((r = vkCreateSampler(device, &sc, nullptr, &shadowSampler)) != VK_SUCCESS) return vkError("vkCreateSampler", r);
        sc = vkInit<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
        sc.magFilter = sc.minFilter = VK_FILTER_LINEAR;
        sc.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        sc.addressModeU = sc.addressModeV = sc.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        if ((r = vkCreateSampler(device, &sc, nullptr, &bitmapSampler)) != VK_SUCCESS) return vkError("vkCreateSampler", r);
        sc.magFilter = sc.minFilter = VK_FILTER_NEAREST;
        if ((r = vkCreateSampler(device, &sc, nullptr, &fontSampler)) != VK_SUCCESS) return vkError("vkCreateSampler", r);
    }

    // Font atlas and the default (transparent) floor bitmap.
    {
        const std::vector<std::uint8_t> atlas = font::buildAtlas();
        if (Status s = fontAtlas.create(*dev, font::kAtlasWidth, font::kAtlasHeight, VK_FORMAT_R8_UNORM,
                                        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_SAMPLE_COUNT_1_BIT,
                                        VK_IMAGE_ASPECT_COLOR_BIT);
            !s)
            return s;
        if (Status s = gpu::uploadImage(*dev, fontAtlas, atlas.data(), atlas.size()); !s) return s;
        if (Status s = updateBitmap(nullptr); !s) return s;
    }

    // Descriptors.
    {
        std::array<VkDescriptorSetLayoutBinding, 6> b{};
        const VkShaderStageFlags vf = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
        b[0] = {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, vf, nullptr};
        b[1] = {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, vf, nullptr};
        b[2] = {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, vf, nullptr};
        b[3] = {3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, vf, nullptr};
        b[4] = {4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, vf, nullptr};
        b[5] = {5, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, vf, nullptr};
        auto lci = vkInit<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
        lci.bindingCount = static_cast<std::uint32_t>(b.size());
        lci.pBindings = b.data();
        if ((r = vkCreateDescriptorSetLayout(device, &lci, nullptr, &setLayout)) != VK_SUCCESS)
            return vkError("vkCreateDescriptorSetLayout", r);
        const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4)};
        auto plci = vkInit<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
        plci.setLayoutCount = 1;
        plci.pSetLayouts = &setLayout;
        plci.pushConstantRangeCount = 1;
        plci.pPushConstantRanges = &push;
        if ((r = vkCreatePipelineLayout(device, &plci, nullptr, &layout)) != VK_SUCCESS) return vkError("vkCreatePipelineLayout", r);
        const std::array<VkDescriptorPoolSize, 3> sizes{{{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kFramesInFlight},
                                                         {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2 * kFramesInFlight},
                                                         {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 3 * kFramesInFlight}}};
        auto dpci = vkInit<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
        dpci.maxSets = kFramesInFlight;
        dpci.poolSizeCount = static_cast<std::uint32_t>(sizes.size());
        dpci.pPoolSizes = sizes.data();
        if ((r = vkCreateDescriptorPool(device, &dpci, nullptr, &pool)) != VK_SUCCESS) return vkError("vkCreateDescriptorPool", r);
        auto dsai = vkInit<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
        dsai.descriptorPool = pool;
        dsai.descriptorSetCount = 1;
        dsai.pSetLayouts = &setLayout;
        for (FrameSlot& f : slots)
            if ((r = vkAllocateDescriptorSets(device, &dsai, &f.set)) != VK_SUCCESS) return vkError("vkAllocateDescriptorSets", r);
    }

    // Buffers: sized for a few hundred characters, grown geometrically.
    const VkBufferUsageFlags ssbo = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    for (FrameSlot& f : slots) {
        if (Status s = f.uniforms.create(*dev, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUse::Dynamic); !s)
            return s;
        if (Status s = f.instanceBuf.create(*dev, 256 * sizeof(GpuInstance), ssbo, gpu::MemoryUse::Dynamic); !s) return s;
        if (Status s = f.paletteBuf.create(*dev, 256 * 32 * sizeof(GpuJoint), ssbo, gpu::MemoryUse::Dynamic); !s) return s;
        if (Status s = f.overlayBuf.create(*dev, 8192 * sizeof(OverlayVertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                           gpu::MemoryUse::Dynamic);
            !s)
            return s;
    }

    if (Status s = createPipelines(); !s) return s;
    if (Status s = createTargets(); !s) return s;

    auto pci = vkInit<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = dev->queueFamily();
    if ((r = vkCreateCommandPool(device, &pci, nullptr, &cmdPool)) != VK_SUCCESS) return vkError("vkCreateCommandPool", r);
    auto cai = vkInit<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    cai.commandPool = cmdPool;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    auto fci = vkInit<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    fci.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    // Device time per frame from two timestamps, where the queue keeps them.
    {
        std::uint32_t families = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(dev->physicalDevice(), &families, nullptr);
        std::vector<VkQueueFamilyProperties> props(families);
        vkGetPhysicalDeviceQueueFamilyProperties(dev->physicalDevice(), &families, props.data());
        const std::uint32_t q = dev->queueFamily();
        const float period = dev->properties().limits.timestampPeriod;
        if (q < families && props[q].timestampValidBits > 0 && period > 0.0f) timestampMs = 1e-6 * static_cast<double>(period);
    }
    for (FrameSlot& f : slots) {
        if ((r = vkAllocateCommandBuffers(device, &cai, &f.cmd)) != VK_SUCCESS) return vkError("vkAllocateCommandBuffers", r);
        if ((r = vkCreateFence(device, &fci, nullptr, &f.fence)) != VK_SUCCESS) return vkError("vkCreateFence", r);
        if (timestampMs > 0.0) {
            auto qci = vkInit<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
            qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
            qci.queryCount = 2;
            if ((r = vkCreateQueryPool(device, &qci, nullptr, &f.timer)) != VK_SUCCESS) return vkError("vkCreateQueryPool", r);
        }
    }
    return {};
}

Status Renderer::Impl::createTargets() {
    const auto w = static_cast<std::uint32_t>(width);
    const auto h = static_cast<std::uint32_t>(height);
    const bool ms = samples != VK_SAMPLE_COUNT_1_BIT;
    if (ms) {
        if (Status s = colorMs.create(*dev, w, h, kColorFormat,
                                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT, samples,
                                      VK_IMAGE_ASPECT_COLOR_BIT);
            !s)
            return s;
    }
    if (Status s = depth.create(*dev, w, h, depthFormat,
                                VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT, samples,
                                VK_IMAGE_ASPECT_DEPTH_BIT);
        !s)
        return s;
    if (Status s = resolve.create(*dev, w, h, kColorFormat,
                                  VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_SAMPLE_COUNT_1_BIT,
                                  VK_IMAGE_ASPECT_COLOR_BIT);
        !s)
        return s;
    std::array<VkImageView, 3> views{ms ? colorMs.view : resolve.view, depth.view, resolve.view};
    auto fb = vkInit<VkFramebufferCreateInfo>(VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO);
    fb.renderPass = mainPass;
    fb.attachmentCount = ms ? 3u : 2u;
    fb.pAttachments = views.data();
    fb.width = w;
    fb.height = h;
    fb.layers = 1;
    const VkResult r = vkCreateFramebuffer(device, &fb, nullptr, &mainFb);
    if (r != VK_SUCCESS) return vkError("vkCreateFramebuffer", r);
    if (Status s = readbackBuf.create(*dev, VkDeviceSize(w) * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUse::Readback); !s)
        return s;
    // Labels are laid out in pixels: pixel (x, y) -> clip (2x/w - 1, 2y/h - 1).
    screenTransform = glm::mat4(1.0f);
    screenTransform[0][0] = 2.0f / static_cast<float>(width);
    screenTransform[1][1] = 2.0f / static_cast<float>(height);
    screenTransform[3][0] = -1.0f;
    screenTransform[3][1] = -1.0f;
    rendered = false;
    return {};
}

void Renderer::Impl::destroyTargets() {
    if (mainFb) vkDestroyFramebuffer(device, mainFb, nullptr);
    mainFb = VK_NULL_HANDLE;
    colorMs.destroy(device);
    depth.destroy(device);
    resolve.destroy(device);
    readbackBuf.destroy(device);
}

namespace {

Result<VkPipeline> makePipeline(VkDevice device, VkPipelineLayout layout, const PipelineDesc& d) {
    std::array<VkPipelineShaderStageCreateInfo, 2> stages{};
    stages[0] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_VERTEX_BIT, d.vs, "main", nullptr};
    stages[1] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_FRAGMENT_BIT, d.fs, "main", d.spec};
    auto vi = vkInit<VkPipelineVertexInputStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO);
    if (d.binding) {
        vi.vertexBindingDescriptionCount = 1;
        vi.pVertexBindingDescriptions = d.binding;
        vi.vertexAttributeDescriptionCount = static_cast<std::uint32_t>(d.attributes.size());
        vi.pVertexAttributeDescriptions = d.attributes.data();
    }
    auto ia = vkInit<VkPipelineInputAssemblyStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO);
    ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    auto vp = vkInit<VkPipelineViewportStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO);
    vp.viewportCount = 1;
    vp.scissorCount = 1;
    auto rs = vkInit<VkPipelineRasterizationStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO);
    rs.polygonMode = VK_POLYGON_MODE_FILL;
    rs.cullMode = d.cull;
    rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    rs.lineWidth = 1.0f;
    rs.depthBiasEnable = d.depthBias ? VK_TRUE : VK_FALSE;
    rs.depthBiasConstantFactor = d.depthBias ? 1.0f : 0.0f;
    rs.depthBiasSlopeFactor = d.depthBias ? 1.75f : 0.0f;
    auto ms = vkInit<VkPipelineMultisampleStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
    ms.rasterizationSamples = d.samples;
    auto ds = vkInit<VkPipelineDepthStencilStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
    ds.depthTestEnable = d.depthTest ? VK_TRUE : VK_FALSE;
    ds.depthWriteEnable = d.depthWrite ? VK_TRUE : VK_FALSE;
    ds.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    VkPipelineColorBlendAttachmentState cb{};
    cb.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    if (d.blend) {
        cb.blendEnable = VK_TRUE;
        cb.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
        cb.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        cb.colorBlendOp = VK_BLEND_OP_ADD;
        cb.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
        cb.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        cb.alphaBlendOp = VK_BLEND_OP_ADD;
    }
    auto cbs = vkInit<VkPipelineColorBlendStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
    cbs.attachmentCount = d.fs ? 1u : 0u;
    cbs.pAttachments = &cb;
    const std::array<VkDynamicState, 2> dyn{VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    auto dy = vkInit<VkPipelineDynamicStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO);
    dy.dynamicStateCount = static_cast<std::uint32_t>(dyn.size());
    dy.pDynamicStates = dyn.data();
    auto gp = vkInit<VkGraphicsPipelineCreateInfo>(VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO);
    gp.stageCount = d.fs ? 2u : 1u;
    gp.pStages = stages.data();
    gp.pVertexInputState = &vi;
    gp.pInputAssemblyState = &ia;
    gp.pViewportState = &vp;
    gp.pRasterizationState = &rs;
    gp.pMultisampleState = &ms;
    gp.pDepthStencilState = &ds;
    gp.pColorBlendState = &cbs;
    gp.pDynamicState = &dy;
    gp.layout = layout;
    gp.renderPass = d.pass;
    gp.subpass = 0;
    VkPipeline p = VK_NULL_HANDLE;
    const VkResult r = vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &gp, nullptr, &p);
    if (r != VK_SUCCESS) return vkError("vkCreateGraphicsPipelines", r);
    return p;
}

}  // namespace

namespace {

const VkVertexInputBindingDescription kBodyBinding{0, sizeof(BodyVertex), VK_VERTEX_INPUT_RATE_VERTEX};
const std::array<VkVertexInputAttributeDescription, 3> kBodyAttrs{{
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(BodyVertex, position)},
    {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(BodyVertex, normal)},
    {2, 0, VK_FORMAT_R32_UINT, offsetof(BodyVertex, joint)},
}};
const VkVertexInputBindingDescription kCardBinding{0, sizeof(CardVertex), VK_VERTEX_INPUT_RATE_VERTEX};
const std::array<VkVertexInputAttributeDescription, 3> kCardAttrs{{
    {0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(CardVertex, anchor)},
    {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(CardVertex, other)},
    {2, 0, VK_FORMAT_R32_UINT, offsetof(CardVertex, corner)},
}};
const VkVertexInputBindingDescription kRigBinding{0, sizeof(SkinnedVertex), VK_VERTEX_INPUT_RATE_VERTEX};
const std::array<VkVertexInputAttributeDescription, 4> kRigAttrs{{
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SkinnedVertex, position)},
    {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SkinnedVertex, normal)},
    {2, 0, VK_FORMAT_R16G16B16A16_UINT, offsetof(SkinnedVertex, joints)},
    {3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(SkinnedVertex, weights)},
}};
const VkVertexInputBindingDescription kOverlayBinding{0, sizeof(OverlayVertex), VK_VERTEX_INPUT_RATE_VERTEX};
const std::array<VkVertexInputAttributeDescription, 4> kOverlayAttrs{{
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(OverlayVertex, position)},
    {1, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(OverlayVertex, uv)},
    {2, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(OverlayVertex, color)},
    {3, 0, VK_FORMAT_R32_UINT, offsetof(OverlayVertex, mode)},
}};

}  // namespace

// The shadow and overlay pipelines; body, floor and rig variants come on
// demand (variantPipelines), since pipeline creation compiles shaders (slow on
// lavapipe).
Status Renderer::Impl::createPipelines() {
    bodyV = makeShader(device, kSpirv_body_vert);
    bodyF = makeShader(device, kSpirv_body_frag);
    floorV = makeShader(device, kSpirv_floor_vert);
    floorF = makeShader(device, kSpirv_floor_frag);
    rigV = makeShader(device, kSpirv_body_skinned_vert);
    rigShadowV = makeShader(device, kSpirv_shadow_skinned_vert);
    cardV = makeShader(device, kSpirv_body_card_vert);
    VkShaderModule shadowV = makeShader(device, kSpirv_shadow_vert);
    VkShaderModule overlayV = makeShader(device, kSpirv_overlay_vert);
    VkShaderModule overlayF = makeShader(device, kSpirv_overlay_frag);
    const std::array<VkShaderModule, 10> modules{bodyV, bodyF, floorV, floorF, rigV, rigShadowV, cardV, shadowV, overlayV, overlayF};
    Status status;
    if (std::any_of(modules.begin(), modules.end(), [](VkShaderModule m) { return m == VK_NULL_HANDLE; })) {
        status = makeError("vkCreateShaderModule failed for an embedded shader");
    } else {
        struct Job {
            VkPipeline* out;
            PipelineDesc desc;
        };
        PipelineDesc shadow{shadowV, VK_NULL_HANDLE, &kBodyBinding, kBodyAttrs, VK_CULL_MODE_FRONT_BIT, true, true, false, true,
                            VK_SAMPLE_COUNT_1_BIT, shadowPass, nullptr};
        PipelineDesc overlayDepth{overlayV, overlayF, &kOverlayBinding, kOverlayAttrs, VK_CULL_MODE_NONE, true, false, true, false,
                                  samples, mainPass, nullptr};
        PipelineDesc overlayTop = overlayDepth;
        overlayTop.depthTest = false;
        for (const Job& job : {Job{&shadowPipe, shadow}, Job{&overlayDepthPipe, overlayDepth}, Job{&overlayTopPipe, overlayTop}}) {
            auto p = makePipeline(device, layout, job.desc);
            if (!p) {
                status = p.error();
                break;
            }
            *job.out = *p;
        }
    }
    for (VkShaderModule m : {shadowV, overlayV, overlayF})
        if (m) vkDestroyShaderModule(device, m, nullptr);
    return status;
}

Status Renderer::Impl::variantPipelines(bool shadows, bool withBitmap, bool withRigs, bool withCards) {
    const std::array<VkSpecializationMapEntry, 3> entries{{{0, offsetof(Variant, shadows), sizeof(VkBool32)},
                                                           {1, offsetof(Variant, bitmap), sizeof(VkBool32)},
                                                           {2, offsetof(Variant, fog), sizeof(VkBool32)}}};
    const Variant v{shadows ? VK_TRUE : VK_FALSE, withBitmap ? VK_TRUE : VK_FALSE, VK_TRUE};
    const VkSpecializationInfo spec{static_cast<std::uint32_t>(entries.size()), entries.data(), sizeof v, &v};
    VkPipeline& body = bodyPipes[shadows ? 1 : 0];
    if (!body) {
        auto p = makePipeline(device, layout, {bodyV, bodyF, &kBodyBinding, kBodyAttrs, VK_CULL_MODE_BACK_BIT, true, true, false,
                                               false, samples, mainPass, &spec});
        if (!p) return p.error();
        body = *p;
    }
    for (std::size_t fog = 0; fog < 2; ++fog) {
        VkPipeline& floor = floorPipes[shadows ? 1 : 0][withBitmap ? 1 : 0][fog];
        if (!floor) {
            Variant fv = v;
            fv.fog = fog ? VK_TRUE : VK_FALSE;
            const VkSpecializationInfo fspec{static_cast<std::uint32_t>(entries.size()), entries.data(), sizeof fv, &fv};
            auto p = makePipeline(device, layout,
                                  {floorV, floorF, nullptr, {}, VK_CULL_MODE_NONE, true, true, false, false, samples, mainPass, &fspec});
            if (!p) return p.error();
            floor = *p;
        }
        floorPipe[fog] = floor;
    }
    bodyPipe = body;
    // Cards face the camera (never culled) and only appear without a shadow map (Fast).
    if (withCards && !cardPipe) {
        auto p = makePipeline(device, layout, {cardV, bodyF, &kCardBinding, kCardAttrs, VK_CULL_MODE_NONE, true, true, false,
                                               false, samples, mainPass, &spec});
        if (!p) return p.error();
        cardPipe = *p;
    }
    rigPipe = VK_NULL_HANDLE;
    if (!withRigs) return {};
    VkPipeline& rig = rigPipes[shadows ? 1 : 0];
    if (!rig) {
        auto p = makePipeline(device, layout, {rigV, bodyF, &kRigBinding, kRigAttrs, VK_CULL_MODE_BACK_BIT, true, true, false,
                                               false, samples, mainPass, &spec});
        if (!p) return p.error();
        rig = *p;
    }
    if (shadows && !rigShadowPipe) {
        auto p = makePipeline(device, layout, {rigShadowV, VK_NULL_HANDLE, &kRigBinding, kRigAttrs, VK_CULL_MODE_FRONT_BIT, true, true,
                                               false, true, VK_SAMPLE_COUNT_1_BIT, shadowPass, nullptr});
        if (!p) return p.error();
        rigShadowPipe = *p;
    }
    rigPipe = rig;
    return {};
}

void Renderer::Impl::destroy() {
    if (!device) return;
    vkDeviceWaitIdle(device);
    destroyTargets();
    for (const auto& byBitmap : floorPipes)
        for (const auto& byFog : byBitmap)
            for (VkPipeline p : byFog)
                if (p) vkDestroyPipeline(device, p, nullptr);
    for (VkPipeline p : {bodyPipes[0], bodyPipes[1], rigPipes[0], rigPipes[1], rigShadowPipe, cardPipe, shadowPipe,
                         overlayDepthPipe, overlayTopPipe})
        if (p) vkDestroyPipeline(device, p, nullptr);
    for (VkShaderModule m : {bodyV, bodyF, floorV, floorF, rigV, rigShadowV, cardV})
        if (m) vkDestroyShaderModule(device, m, nullptr);
    if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
    if (pool) vkDestroyDescriptorPool(device, pool, nullptr);
    if (setLayout) vkDestroyDescriptorSetLayout(device, setLayout, nullptr);
    for (VkSampler s : {shadowSampler, bitmapSampler, fontSampler})
        if (s) vkDestroySampler(device, s, nullptr);
    if (shadowFb) vkDestroyFramebuffer(device, shadowFb, nullptr);
    shadowMap.destroy(device);
    fontAtlas.destroy(device);
    bitmap.destroy(device);
    for (gpu::Buffer* b : {&meshVB, &meshIB, &cardVB, &cardIB, &rigVB, &rigIB}) b->destroy(device);
    for (FrameSlot& f : slots) {
        for (gpu::Buffer* b : {&f.uniforms, &f.instanceBuf, &f.paletteBuf, &f.overlayBuf}) b->destroy(device);
        if (f.fence) vkDestroyFence(device, f.fence, nullptr);
        if (f.timer) vkDestroyQueryPool(device, f.timer, nullptr);
    }
    if (mainPass) vkDestroyRenderPass(device, mainPass, nullptr);
    if (shadowPass) vkDestroyRenderPass(device, shadowPass, nullptr);
    if (cmdPool) vkDestroyCommandPool(device, cmdPool, nullptr);
    device = VK_NULL_HANDLE;
}

// ---------------------------------------------------------------- per frame

Status Renderer::Impl::ensureBuffer(gpu::Buffer& b, VkDeviceSize needed, VkBufferUsageFlags usage, VkDeviceSize minimum) {
    if (b.buffer && b.size >= needed) return {};
    const VkDeviceSize size = std::max({needed, b.size * 2, minimum});
    b.destroy(device);
    ++stats.bufferGrowths;
    slot().descriptorsDirty = true;
    return b.create(*dev, size, usage, gpu::MemoryUse::Dynamic);
}

Status Renderer::Impl::registerMesh(const Skeleton& skeleton, std::uint64_t fingerprint, int& index) {
    // Cards keep the joint in 24 bits.
    if (skeleton.jointCount() >= (1 << 24))
        return makeError("a skeleton of " + std::to_string(skeleton.jointCount()) + " joints is more than the renderer draws (16,777,215)");
    MeshEntry e;
    e.fingerprint = fingerprint;
    e.jointCount = skeleton.jointCount();
    for (std::size_t lod = 0; lod < kCardLod; ++lod) {
        const BodyMesh mesh = buildBodyMesh(skeleton, lod == 0 ? options.body : kCoarseBodies[lod - 1]);
        e.firstIndex[lod] = static_cast<std::uint32_t>(meshIndices.size());
        e.indexCount[lod] = static_cast<std::uint32_t>(mesh.indices.size());
        e.vertexOffset[lod] = static_cast<std::int32_t>(meshVertices.size());
        meshVertices.insert(meshVertices.end(), mesh.vertices.begin(), mesh.vertices.end());
        meshIndices.insert(meshIndices.end(), mesh.indices.begin(), mesh.indices.end());
    }
    // Cards: per capsule the hexagon tip, side, side at the first end, then
    // side, side, tip at the second. A corner's side is the camera-facing
    // perpendicular of the direction to the other end, so a second-end
    // corner 2 lies on the first end's corner-1 side.
    e.firstIndex[kCardLod] = static_cast<std::uint32_t>(cardIndices.size());
    e.vertexOffset[kCardLod] = static_cast<std::int32_t>(cardVertices.size());
    std::uint32_t base = 0;
    const std::vector<BodyCapsule> capsules = bodyCapsules(skeleton);
    for (const BodyCapsule& c : capsules) {
        const std::uint32_t first = c.joint, second = c.joint | (1u << 26);
        for (std::uint32_t corner : {0u, 1u, 2u}) cardVertices.push_back({c.a, c.radius, c.b, first | corner << 24});
        for (std::uint32_t corner : {2u, 1u, 0u}) cardVertices.push_back({c.b, c.radius, c.a, second | corner << 24});
        // Around the hexagon: 0 tip, 1 side, 3 side, 5 tip, 4 side, 2 side.
        for (std::uint32_t k : {0u, 1u, 2u, 1u, 3u, 4u, 1u, 4u, 2u, 3u, 5u, 4u}) cardIndices.push_back(base + k);
        base += 6;
    }
    e.indexCount[kCardLod] = static_cast<std::uint32_t>(cardIndices.size()) - e.firstIndex[kCardLod];
    // Far cards: the same card vertices, indices for the largest capsules
    // (side-on area: length with the caps times the diameter) up to
    // kFarCardArea of the whole, in the body's own order. Small bones
    // (fingers, toes, clavicles, short spine links) go first.
    {
        std::vector<float> area(capsules.size());
        std::vector<std::size_t> bySize(capsules.size());
        float total = 0;
        for (std::size_t k = 0; k < capsules.size(); ++k) {
            const BodyCapsule& c = capsules[k];
            area[k] = (glm::length(c.b - c.a) + 2.0f * c.radius) * 2.0f * c.radius;
            total += area[k];
            bySize[k] = k;
        }
        std::stable_sort(bySize.begin(), bySize.end(), [&](std::size_t x, std::size_t y) { return area[x] > area[y]; });
        std::vector<std::uint8_t> keep(capsules.size(), 0);
        float kept = 0;
        for (std::size_t k : bySize) {
            if (kept >= kFarCardArea * total) break;
            keep[k] = 1;
            kept += area[k];
        }
        e.firstIndex[kFarCardLod] = static_cast<std::uint32_t>(cardIndices.size());
        e.vertexOffset[kFarCardLod] = e.vertexOffset[kCardLod];
        for (std::size_t k = 0; k < capsules.size(); ++k) {
            if (!keep[k]) continue;
            const std::size_t from = e.firstIndex[kCardLod] + 12 * k;
            for (std::size_t i = 0; i < 12; ++i) {
                const std::uint32_t corner = cardIndices[from + i];
                cardIndices.push_back(corner);
            }
        }
        e.indexCount[kFarCardLod] = static_cast<std::uint32_t>(cardIndices.size()) - e.firstIndex[kFarCardLod];
    }
    meshes.push_back(e);
    index = static_cast<int>(meshes.size()) - 1;
    if (meshVertices.empty() || meshIndices.empty()) return {};
    // Rebuild the static buffers with every mesh (rare: once per new skeleton),
    // once no frame in flight draws from the old ones.
    if (Status s = waitAll(); !s) return s;
    for (gpu::Buffer* b : {&meshVB, &meshIB, &cardVB, &cardIB}) b->destroy(device);
    if (Status s = gpu::createStaticBuffer(*dev, meshVB, meshVertices.data(), meshVertices.size() * sizeof(BodyVertex),
                                           VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        !s)
        return s;
    if (Status s = gpu::createStaticBuffer(*dev, meshIB, meshIndices.data(), meshIndices.size() * sizeof(std::uint32_t),
                                           VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
        !s)
        return s;
    if (Status s = gpu::createStaticBuffer(*dev, cardVB, cardVertices.data(), cardVertices.size() * sizeof(CardVertex),
                                           VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        !s)
        return s;
    return gpu::createStaticBuffer(*dev, cardIB, cardIndices.data(), cardIndices.size() * sizeof(std::uint32_t),
                                   VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
}

// All rigs in one vertex and one index buffer (rebuilt when a rig is set or
// cleared: rare). Called from prepare(), when no submission uses the old ones.
Status Renderer::Impl::uploadRigs() {
    if (Status s = waitAll(); !s) return s;
    rigVB.destroy(device);
    rigIB.destroy(device);
    rigsDirty = false;
    std::vector<SkinnedVertex> vertices;
    std::vector<std::uint32_t> indices;
    for (RigEntry& r : rigs) {
        r.firstIndex = static_cast<std::uint32_t>(indices.size());
        r.vertexOffset = static_cast<std::int32_t>(vertices.size());
        vertices.insert(vertices.end(), r.vertices.begin(), r.vertices.end());
        indices.insert(indices.end(), r.indices.begin(), r.indices.end());
    }
    if (rigs.empty()) return {};
    if (Status s = gpu::createStaticBuffer(*dev, rigVB, vertices.data(), vertices.size() * sizeof(SkinnedVertex),
                                           VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        !s)
        return s;
    return gpu::createStaticBuffer(*dev, rigIB, indices.data(), indices.size() * sizeof(std::uint32_t),
                                   VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
}

int Renderer::Impl::rigOf(std::uint64_t fingerprint, int jointCount) const {
    for (std::size_t r = 0; r < rigs.size(); ++r)
        if (rigs[r].fingerprint == fingerprint && rigs[r].jointCount == jointCount) return static_cast<int>(r);
    return -1;
}

Status Renderer::Impl::updateBitmap(const FloorBitmap* fb) {
    const bool wantDefault = !fb || !fb->rgba || fb->width <= 0 || fb->height <= 0;
    if (wantDefault) {
        if (bitmap.image && bitmapIsDefault) return {};
    } else if (bitmap.image && !bitmapIsDefault && fb->rgba == bitmapPixels && fb->width == bitmapW &&
               fb->height == bitmapH && fb->revision == bitmapRevision) {
        return {};
    }
    const std::uint32_t w = wantDefault ? 1u : static_cast<std::uint32_t>(fb->width);
    const std::uint32_t h = wantDefault ? 1u : static_cast<std::uint32_t>(fb->height);
    if (!bitmap.image || bitmap.width != w || bitmap.height != h) {
        bitmap.destroy(device);
        if (Status s = bitmap.create(*dev, w, h, VK_FORMAT_R8G8B8A8_UNORM,
                                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_SAMPLE_COUNT_1_BIT,
                                     VK_IMAGE_ASPECT_COLOR_BIT);
            !s)
            return s;
        for (FrameSlot& f : slots) f.descriptorsDirty = true;
    }
    const std::array<std::uint8_t, 4> clear{0, 0, 0, 0};
    if (Status s = waitAll(); !s) return s;  // a frame in flight may still sample the old pixels
    const void* pixels = wantDefault ? static_cast<const void*>(clear.data()) : static_cast<const void*>(fb->rgba);
    if (Status s = gpu::uploadImage(*dev, bitmap, pixels, VkDeviceSize(w) * h * 4); !s) return s;
    bitmapIsDefault = wantDefault;
    bitmapPixels = wantDefault ? nullptr : fb->rgba;
    bitmapW = static_cast<int>(w);
    bitmapH = static_cast<int>(h);
    bitmapRevision = wantDefault ? 0 : fb->revision;
    return {};
}

void Renderer::Impl::writeDescriptors() {
    FrameSlot& f = slot();
    const VkDescriptorBufferInfo ub{f.uniforms.buffer, 0, VK_WHOLE_SIZE};
    const VkDescriptorBufferInfo ib{f.instanceBuf.buffer, 0, VK_WHOLE_SIZE};
    const VkDescriptorBufferInfo pb{f.paletteBuf.buffer, 0, VK_WHOLE_SIZE};
    const VkDescriptorImageInfo shadowInfo{shadowSampler, shadowMap.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    const VkDescriptorImageInfo bitmapInfo{bitmapSampler, bitmap.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    const VkDescriptorImageInfo fontInfo{fontSampler, fontAtlas.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    std::array<VkWriteDescriptorSet, 6> w{};
    for (std::uint32_t i = 0; i < w.size(); ++i) {
        w[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        w[i].dstSet = f.set;
        w[i].dstBinding = i;
        w[i].descriptorCount = 1;
    }
    w[0].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    w[0].pBufferInfo = &ub;
    w[1].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w[1].pBufferInfo = &ib;
    w[2].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w[2].pBufferInfo = &pb;
    w[3].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    w[3].pImageInfo = &shadowInfo;
    w[4].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    w[4].pImageInfo = &bitmapInfo;
    w[5].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    w[5].pImageInfo = &fontInfo;
    vkUpdateDescriptorSets(device, static_cast<std::uint32_t>(w.size()), w.data(), 0, nullptr);
    f.descriptorsDirty = false;
}

Status Renderer::Impl::waitSlot(FrameSlot& f) {
    if (!f.pending) return {};
    const auto t0 = std::chrono::steady_clock::now();
    if (VkResult r = vkWaitForFences(device, 1, &f.pending, VK_TRUE, UINT64_MAX); r != VK_SUCCESS)
        return vkError("vkWaitForFences", r);
    stats.waitMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    f.pending = VK_NULL_HANDLE;
    if (f.timed) {
        f.timed = false;
        std::array<std::uint64_t, 2> ticks{};
        if (vkGetQueryPoolResults(device, f.timer, 0, 2, sizeof ticks, ticks.data(), sizeof(std::uint64_t),
                                  VK_QUERY_RESULT_64_BIT) == VK_SUCCESS &&
            ticks[1] >= ticks[0])
            stats.deviceMs = timestampMs * static_cast<double>(ticks[1] - ticks[0]);
    }
    return {};
}

Status Renderer::Impl::waitAll() {
    for (FrameSlot& f : slots)
        if (Status s = waitSlot(f); !s) return s;
    return {};
}

Status Renderer::Impl::prepare(const FrameDescription& frame) {
    stats.waitMs = 0.0;
    if (Status s = waitSlot(slot()); !s) return s;
    const auto chars = frame.characters;
    const std::size_t n = chars.size();

    // Check the input and find each character's body mesh: skeletons are
    // fingerprinted once per distinct pointer (sorted runs), then meshes are
    // looked up in character order so the draw order is deterministic.
    std::size_t jointTotal = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const CharacterInstance& c = chars[i];
        if (!c.skeleton) return makeError("character " + std::to_string(i) + " has no skeleton");
        const auto jc = static_cast<std::size_t>(c.skeleton->jointCount());
        if (c.jointPositions.size() != jc || c.jointRotations.size() != jc)
            return makeError("character " + std::to_string(i) + ": " + std::to_string(c.jointPositions.size()) +
                             " joint positions and " + std::to_string(c.jointRotations.size()) +
                             " rotations for a skeleton of " + std::to_string(jc) + " joints");
        jointTotal += jc;
    }
    // Fingerprints per distinct skeleton pointer: crowds share a handful of
    // skeletons, so the last pointer seen answers almost every look-up and a
    // sorted table of the others answers the rest (no per-frame sort of n).
    characterFingerprint.resize(n);
    {
        const Skeleton* last = nullptr;
        std::uint64_t lastFp = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const Skeleton* sk = chars[i].skeleton;
            if (sk != last) {
                auto it = std::lower_bound(bySkeleton.begin(), bySkeleton.end(), sk,
                                           [](const auto& e, const Skeleton* k) { return e.first < k; });
                if (it == bySkeleton.end() || it->first != sk)
                    it = bySkeleton.insert(it, {sk, skeletonFingerprint(*sk)});
                last = sk;
                lastFp = it->second;
            }
            characterFingerprint[i] = lastFp;
        }
        // Forget skeletons no longer drawn so a freed pointer reused by a new
        // skeleton is fingerprinted afresh next frame.
        bySkeleton.clear();
    }
    if (rigsDirty)
        if (Status s = uploadRigs(); !s) return s;
    characterMesh.resize(n);
    characterRig.resize(n);
    float rigReach = 0.0f;  // furthest a drawn rig reaches beyond its joints
    stats.rigged = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const int jc = chars[i].skeleton->jointCount();
        characterRig[i] = rigOf(characterFingerprint[i], jc);
        characterMesh[i] = -1;
        if (characterRig[i] >= 0) {
            rigReach = std::max(rigReach, rigs[static_cast<std::size_t>(characterRig[i])].reach);
            ++stats.rigged;
            continue;
        }
        int mesh = -1;
        if (i > 0 && characterMesh[i - 1] >= 0 && characterFingerprint[i - 1] == characterFingerprint[i] &&
            chars[i - 1].skeleton->jointCount() == jc) {
            mesh = characterMesh[i - 1];
        } else {
            for (std::size_t m = 0; m < meshes.size(); ++m)
                if (meshes[m].fingerprint == characterFingerprint[i] && meshes[m].jointCount == jc) mesh = static_cast<int>(m);
        }
        if (mesh < 0)
            if (Status s = registerMesh(*chars[i].skeleton, characterFingerprint[i], mesh); !s) return s;
        characterMesh[i] = mesh;
    }
    stats.meshes = static_cast<int>(meshes.size() + rigs.size());

    // Camera first: visibility and level of detail per character.
    const RenderSettings& st = frame.settings;
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    viewProj = frame.camera.viewProjection(aspect);
    shadowsThisFrame = st.shadows && n > 0 && !fast;
    {
        // Frustum planes (Gribb-Hartmann) of Vulkan clip space: -w<=x<=w, -w<=y<=w, 0<=z<=w.
        const glm::mat4 m = glm::transpose(viewProj);
        const std::array<glm::vec4, 6> planes{m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[2], m[3] - m[2]};
        const glm::vec3 eye = frame.camera.eye();
        const glm::vec3 fwd = frame.camera.forward();
        const float focalPx = 0.5f * static_cast<float>(height) / std::tan(0.5f * frame.camera.fovY);
        characterLod.resize(n);
        characterVisible.resize(n);
        characterBox.resize(n);
        auto classify = [&](std::size_t i) {
            Bounds& b = characterBox[i];
            glm::vec3 lo(1e30f), hi(-1e30f);
            for (const glm::vec3& p : chars[i].jointPositions) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
            b.min = lo;
            b.max = hi;
            const glm::vec3 c = b.center();
            // Capsules stay within 0.25 m of the joints; a rig reaches as far as it measured.
            const int rig = characterRig[i];
            const float r = b.radius() + (rig >= 0 ? std::max(0.25f, rigs[static_cast<std::size_t>(rig)].reach) : 0.25f);
            bool inside = true;
            for (const glm::vec4& pl : planes)
                if (glm::dot(glm::vec3(pl), c) + pl.w < -r * glm::length(glm::vec3(pl))) inside = false;
            characterVisible[i] = inside ? 1 : 0;
            const float ahead = glm::dot(c - eye, fwd);
            const float pixels = ahead > frame.camera.nearPlane ? 2.0f * r * focalPx / ahead : 1e9f;
            const int coarsest = fast ? (pixels < farPixels ? kFarCardLod : kCardLod) : 2;
            characterLod[i] = rig >= 0 ? 0 : (pixels < lodPixels[1] ? coarsest : (pixels < lodPixels[0] ? 1 : 0));
        };
        if (n < 2048) {
            for (std::size_t i = 0; i < n; ++i) classify(i);
        } else {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t i = r.begin(); i != r.end(); ++i) classify(i);
            });
        }
    }

    // Instances and joint palettes, written straight into the mapped buffers,
    // grouped by mesh and detail (one instanced draw per group), the
    // characters in view first. Without a shadow map the others are left out.
    if (Status s = ensureBuffer(slot().instanceBuf, std::max<std::size_t>(n, 1) * sizeof(GpuInstance), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                256 * sizeof(GpuInstance));
        !s)
        return s;
    if (Status s = ensureBuffer(slot().paletteBuf, std::max<std::size_t>(jointTotal, 1) * sizeof(GpuJoint),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 256 * 32 * sizeof(GpuJoint));
        !s)
        return s;
    auto* inst = static_cast<GpuInstance*>(slot().instanceBuf.mapped);
    auto* pal = static_cast<GpuJoint*>(slot().paletteBuf.mapped);
    groups.clear();
    stats.triangles = 0;
    stats.culled = 0;
    // Draw order: per capsule mesh and level of detail, then per rig, the
    // characters in view first and (with a shadow map) the others after
    // them, each run in character order. A counting sort gives every
    // character its slot in O(n); the slots are then written in parallel.
    const std::size_t pass2 = shadowsThisFrame ? 2 : 1;
    const std::size_t capsuleKeys = meshes.size() * kLevels * 2;
    const std::size_t keys = capsuleKeys + rigs.size() * 2;
    constexpr std::uint32_t kNoSlot = 0xffffffffu;
    auto keyOf = [&](std::size_t i) -> std::size_t {
        const std::size_t pass = characterVisible[i] ? 0 : 1;
        if (pass >= pass2) return keys;  // not drawn at all
        if (characterRig[i] >= 0) return capsuleKeys + static_cast<std::size_t>(characterRig[i]) * 2 + pass;
        return (static_cast<std::size_t>(characterMesh[i]) * kLevels + characterLod[i]) * 2 + pass;
    };
    groupStart.assign(keys + 2, 0);
    for (std::size_t i = 0; i < n; ++i) ++groupStart[keyOf(i) + 1];
    for (std::size_t k = 0; k <= keys; ++k) groupStart[k + 1] += groupStart[k];
    const std::uint32_t written = groupStart[keys];
    slotOf.resize(n);
    {
        // The counts' prefix sums become each key's next free slot.
        std::vector<std::uint32_t>& next = jointOffsetOf;
        next.assign(groupStart.begin(), groupStart.end());
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t k = keyOf(i);
            slotOf[i] = k < keys ? next[k]++ : kNoSlot;
        }
    }
    // Palette offsets follow the slots: a prefix sum of joint counts in slot order.
    bySlot.resize(written);
    for (std::size_t i = 0; i < n; ++i)
        if (slotOf[i] != kNoSlot) bySlot[slotOf[i]] = static_cast<std::uint32_t>(i);
    jointOffsetOf.resize(static_cast<std::size_t>(written) + 1);
    jointOffsetOf[0] = 0;
    for (std::uint32_t sl = 0; sl < written; ++sl)
        jointOffsetOf[sl + 1] = jointOffsetOf[sl] + static_cast<std::uint32_t>(chars[bySlot[sl]].jointPositions.size());
    // A capsule body's palette is the world joint transforms; a rig's is the
    // skinning transforms world_j * inverseBind_j (still rigid: a position
    // and a quaternion).
    auto write = [&](std::uint32_t sl) {
        const std::size_t i = bySlot[sl];
        const CharacterInstance& c = chars[i];
        const RigEntry* rig = characterRig[i] >= 0 ? &rigs[static_cast<std::size_t>(characterRig[i])] : nullptr;
        const std::uint32_t jointOffset = jointOffsetOf[sl];
        inst[sl] = GpuInstance{jointOffset, c.selected ? 1u : 0u, 0u, 0u, glm::vec4(c.tint, 1.0f)};
        for (std::size_t j = 0; j < c.jointPositions.size(); ++j) {
            glm::quat q = c.jointRotations[j];
            const float len = glm::length(glm::vec4(q.x, q.y, q.z, q.w));
            q = len > 1e-8f ? q / len : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
            glm::vec3 p = c.jointPositions[j];
            if (rig) {
                const RigidTransform& ib = rig->inverseBind[j];
                p += q * ib.translation;
                q = glm::normalize(q * ib.rotation);
            }
            pal[jointOffset + j] = GpuJoint{glm::vec4(p, 1.0f), glm::vec4(q.x, q.y, q.z, q.w)};
        }
    };
    if (written < 2048) {
        for (std::uint32_t sl = 0; sl < written; ++sl) write(sl);
    } else {
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, written, 512), [&](const tbb::blocked_range<std::uint32_t>& r) {
            for (std::uint32_t sl = r.begin(); sl != r.end(); ++sl) write(sl);
        });
    }
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        for (int lod = 0; lod < kLevels; ++lod) {
            const std::size_t k = (m * kLevels + static_cast<std::size_t>(lod)) * 2;
            const std::uint32_t first = groupStart[k], end = groupStart[k + 2];
            const std::uint32_t visible = groupStart[k + 1] - groupStart[k];
            const std::uint32_t indexCount = meshes[m].indexCount[static_cast<std::size_t>(lod)];
            if (end > first && indexCount > 0) {
                groups.push_back({static_cast<int>(m), lod, first, end - first, visible, false});
                stats.triangles += static_cast<std::uint64_t>(indexCount / 3) * visible;
            }
        }
    }
    // Rigs: full detail only, one group each.
    for (std::size_t r = 0; r < rigs.size(); ++r) {
        const std::size_t k = capsuleKeys + r * 2;
        const std::uint32_t first = groupStart[k], end = groupStart[k + 2];
        const std::uint32_t visible = groupStart[k + 1] - groupStart[k];
        if (end > first) {
            groups.push_back({static_cast<int>(r), 0, first, end - first, visible, true});
            stats.triangles += static_cast<std::uint64_t>(rigs[r].indices.size() / 3) * visible;
        }
    }
    const bool rigsThisFrame = std::any_of(groups.begin(), groups.end(), [](const DrawGroup& g) { return g.rig; });
    const bool cardsThisFrame = std::any_of(groups.begin(), groups.end(), [](const DrawGroup& g) { return isCardLod(g.lod); });
    {
        // In view: the first run of every key.
        std::uint32_t inView = 0;
        for (std::size_t k = 0; k < keys; k += 2) inView += groupStart[k + 1] - groupStart[k];
        stats.culled = static_cast<int>(n - inView);
    }

    // The sun and the shadow volume around the characters.
    shadowsThisFrame = shadowsThisFrame && !groups.empty();
    glm::vec3 lightDir = st.lightDirection;
    if (glm::length(lightDir) < 1e-6f) lightDir = glm::vec3(0.0f, -1.0f, 0.0f);
    lightDir = glm::normalize(lightDir);
    if (lightDir.y > -0.1f) lightDir = glm::normalize(glm::vec3(lightDir.x, -0.1f, lightDir.z));
    glm::mat4 lightViewProj(1.0f);
    float texelWorld = 0.0f, depthRange = 1.0f;
    if (shadowsThisFrame) {
        const Bounds bounds = characterBounds(chars);
        const glm::vec3 c = bounds.center();
        const float r = bounds.radius() + std::max(0.35f, rigReach + 0.1f);
        const glm::vec3 up = std::abs(lightDir.y) > 0.99f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
        const glm::mat4 lightView = glm::lookAt(c - lightDir * (r + 2.0f), c, up);
        depthRange = 2.0f * r + 4.0f;
        lightViewProj = orthoVk(-r, r, -r, r, 0.0f, depthRange) * lightView;
        texelWorld = 2.0f * r / static_cast<float>(shadowSize);
    }

    FrameUniforms u{};
    u.viewProj = viewProj;
    u.lightViewProj = lightViewProj;
    u.cameraPos = glm::vec4(frame.camera.eye(), 1.0f);
    u.lightDir = glm::vec4(lightDir, 0.0f);
    u.lightColor = glm::vec4(1.25f, 1.2f, 1.1f, 0.0f);
    u.skyColor = glm::vec4(0.36f, 0.4f, 0.47f, 0.0f);
    u.groundColor = glm::vec4(0.17f, 0.16f, 0.15f, 0.0f);
    u.floorColor = glm::vec4(st.floorColor, 1.0f);
    const float half = std::max(30.0f, frame.camera.distance * 3.0f);
    u.floorArea = glm::vec4(frame.camera.target.x, frame.camera.target.z, half, half * 0.45f);
    const FloorBitmap* fb = frame.floorBitmap;
    const bool haveBitmap = fb && fb->rgba && fb->width > 0 && fb->height > 0 && fb->max.x > fb->min.x && fb->max.y > fb->min.y;
    u.bitmapRect = haveBitmap ? glm::vec4(fb->min.x, fb->min.y, fb->max.x, fb->max.y) : glm::vec4(0.0f);
    u.floorParams = glm::vec4(haveBitmap ? std::clamp(fb->opacity, 0.0f, 1.0f) : 0.0f, st.grid ? 1.0f : 0.0f, half * 0.95f, 0.0f);
    u.shadowParams = glm::vec4(shadowsThisFrame ? 1.0f : 0.0f, 1.0f / static_cast<float>(shadowSize), texelWorld * 1.5f,
                               texelWorld / depthRange);
    u.highlightColor = glm::vec4(st.highlightColor, 1.0f);
    u.fogColor = glm::vec4(st.clearColor, 1.0f);
    std::memcpy(slot().uniforms.mapped, &u, sizeof u);

    if (Status s = updateBitmap(haveBitmap ? fb : nullptr); !s) return s;
    if (Status s = variantPipelines(shadowsThisFrame, haveBitmap && u.floorParams.x > 0.0f, rigsThisFrame, cardsThisFrame); !s)
        return s;

    // Overlays.
    buildOverlays(frame, viewProj, glm::vec2(static_cast<float>(width), static_cast<float>(height)), st.shadows && fast,
                  overlays, characterBox);
    const std::size_t ov = overlays.vertexCount();
    if (Status s = ensureBuffer(slot().overlayBuf, std::max<std::size_t>(ov, 1) * sizeof(OverlayVertex),
                                VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, 8192 * sizeof(OverlayVertex));
        !s)
        return s;
    auto* ovOut = static_cast<OverlayVertex*>(slot().overlayBuf.mapped);
    std::uint32_t at = 0;
    for (int g = 0; g < 3; ++g) {
        const auto& verts = overlays.group(static_cast<OverlayGroup>(g));
        if (verts.size() > 65536) {
            // A crowd's blob shadows: tens of megabytes into mapped memory, in parallel.
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, verts.size(), 16384), [&](const tbb::blocked_range<std::size_t>& r) {
                std::memcpy(ovOut + at + r.begin(), verts.data() + r.begin(), r.size() * sizeof(OverlayVertex));
            });
        } else if (!verts.empty()) {
            std::memcpy(ovOut + at, verts.data(), verts.size() * sizeof(OverlayVertex));
        }
        overlayFirst[static_cast<std::size_t>(g)] = at;
        overlayCount[static_cast<std::size_t>(g)] = static_cast<std::uint32_t>(verts.size());
        at += static_cast<std::uint32_t>(verts.size());
    }
    clearColor = st.clearColor;

    if (slot().descriptorsDirty) writeDescriptors();
    stats.characters = static_cast<int>(n);
    stats.overlayVertices = static_cast<int>(ov);
    stats.drawCalls = static_cast<int>(groups.size()) + 2 + (overlayCount[0] ? 1 : 0) + (overlayCount[1] ? 1 : 0) +
                      (overlayCount[2] ? 1 : 0);
    return {};
}

void Renderer::Impl::record(VkCommandBuffer c) {
    const VkDeviceSize zero = 0;
    // The frame before may still be on the device, drawing into the same
    // targets and sampling the same shadow map: its writes and reads finish
    // before this frame's start.
    auto mb = vkInit<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    mb.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(c, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &mb, 0, nullptr, 0,
                         nullptr);
    if (shadowsThisFrame) {
        VkClearValue clear{};
        clear.depthStencil = {1.0f, 0};
        auto bi = vkInit<VkRenderPassBeginInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO);
        bi.renderPass = shadowPass;
        bi.framebuffer = shadowFb;
        bi.renderArea = {{0, 0}, {shadowSize, shadowSize}};
        bi.clearValueCount = 1;
        bi.pClearValues = &clear;
        vkCmdBeginRenderPass(c, &bi, VK_SUBPASS_CONTENTS_INLINE);
        const VkViewport vp{0.0f, 0.0f, static_cast<float>(shadowSize), static_cast<float>(shadowSize), 0.0f, 1.0f};
        const VkRect2D sc{{0, 0}, {shadowSize, shadowSize}};
        vkCmdSetViewport(c, 0, 1, &vp);
        vkCmdSetScissor(c, 0, 1, &sc);
        vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &slot().set, 0, nullptr);
        recordBodies(c, shadowPipe, rigShadowPipe, false);
        vkCmdEndRenderPass(c);
    }

    std::array<VkClearValue, 3> clears{};
    clears[0].color = {{clearColor.x, clearColor.y, clearColor.z, 1.0f}};
    clears[1].depthStencil = {1.0f, 0};
    clears[2].color = clears[0].color;
    auto bi = vkInit<VkRenderPassBeginInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO);
    bi.renderPass = mainPass;
    bi.framebuffer = mainFb;
    bi.renderArea = {{0, 0}, {static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height)}};
    bi.clearValueCount = samples != VK_SAMPLE_COUNT_1_BIT ? 3u : 2u;
    bi.pClearValues = clears.data();
    vkCmdBeginRenderPass(c, &bi, VK_SUBPASS_CONTENTS_INLINE);
    const VkViewport vp{0.0f, 0.0f, static_cast<float>(width), static_cast<float>(height), 0.0f, 1.0f};
    const VkRect2D sc{{0, 0}, {static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height)}};
    vkCmdSetViewport(c, 0, 1, &vp);
    vkCmdSetScissor(c, 0, 1, &sc);
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &slot().set, 0, nullptr);
    // Bodies first so the floor's fragments behind them fail the depth test early.
    recordBodies(c, bodyPipe, rigPipe, true);
    // The floor: the square where fog is 0 without fog, then the ring around it.
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, floorPipe[0]);
    vkCmdDraw(c, 6, 1, 0, 0);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, floorPipe[1]);
    vkCmdDraw(c, 24, 1, 6, 0);
    if (overlayCount[0] + overlayCount[1] + overlayCount[2] > 0) {
        vkCmdBindVertexBuffers(c, 0, 1, &slot().overlayBuf.buffer, &zero);
        if (overlayCount[0]) {
            vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, overlayDepthPipe);
            vkCmdPushConstants(c, layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4), &viewProj);
            vkCmdDraw(c, overlayCount[0], 1, overlayFirst[0], 0);
        }
        if (overlayCount[1] || overlayCount[2]) vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, overlayTopPipe);
        if (overlayCount[1]) {
            vkCmdPushConstants(c, layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4), &viewProj);
            vkCmdDraw(c, overlayCount[1], 1, overlayFirst[1], 0);
        }
        if (overlayCount[2]) {
            vkCmdPushConstants(c, layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4), &screenTransform);
            vkCmdDraw(c, overlayCount[2], 1, overlayFirst[2], 0);
        }
    }
    vkCmdEndRenderPass(c);
    rendered = true;
}

// The body groups: capsule bodies with `capsules` (cards with cardPipe), then
// rigs with `rigged` (groups are in that order); only the characters in view
// when `visibleOnly`. Cards come only in Fast quality, which has no shadow pass.
void Renderer::Impl::recordBodies(VkCommandBuffer c, VkPipeline capsules, VkPipeline rigged, bool visibleOnly) {
    const VkDeviceSize zero = 0;
    bool rigBound = false, capsulesBound = false, cardsBound = false;
    for (const DrawGroup& g : groups) {
        const std::uint32_t count = visibleOnly ? g.visible : g.count;
        if (count == 0) continue;
        if (g.rig) {
            if (!rigBound) {
                vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, rigged);
                vkCmdBindVertexBuffers(c, 0, 1, &rigVB.buffer, &zero);
                vkCmdBindIndexBuffer(c, rigIB.buffer, 0, VK_INDEX_TYPE_UINT32);
                rigBound = true;
            }
            const RigEntry& r = rigs[static_cast<std::size_t>(g.mesh)];
            vkCmdDrawIndexed(c, static_cast<std::uint32_t>(r.indices.size()), count, r.firstIndex, r.vertexOffset, g.firstInstance);
            continue;
        }
        if (isCardLod(g.lod) && !cardsBound) {
            vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, cardPipe);
            vkCmdBindVertexBuffers(c, 0, 1, &cardVB.buffer, &zero);
            vkCmdBindIndexBuffer(c, cardIB.buffer, 0, VK_INDEX_TYPE_UINT32);
            cardsBound = true;
            capsulesBound = false;
        } else if (!isCardLod(g.lod) && !capsulesBound) {
            vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, capsules);
            vkCmdBindVertexBuffers(c, 0, 1, &meshVB.buffer, &zero);
            vkCmdBindIndexBuffer(c, meshIB.buffer, 0, VK_INDEX_TYPE_UINT32);
            capsulesBound = true;
            cardsBound = false;
        }
        const MeshEntry& m = meshes[static_cast<std::size_t>(g.mesh)];
        const auto l = static_cast<std::size_t>(g.lod);
        vkCmdDrawIndexed(c, m.indexCount[l], count, m.firstIndex[l], m.vertexOffset[l], g.firstInstance);
    }
}

void Renderer::Impl::recordReadback(VkCommandBuffer c) {
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), 1};
    vkCmdCopyImageToBuffer(c, resolve.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readbackBuf.buffer, 1, &region);
    auto b = vkInit<VkBufferMemoryBarrier>(VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER);
    b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.buffer = readbackBuf.buffer;
    b.size = VK_WHOLE_SIZE;
    vkCmdPipelineBarrier(c, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &b, 0, nullptr);
}

void Renderer::Impl::copyReadback(Image& out) {
    out.resize(width, height);
    std::memcpy(out.rgba.data(), readbackBuf.mapped, out.rgba.size());
}

// ---------------------------------------------------------------- public

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create(std::shared_ptr<VulkanDevice> device, const RendererOptions& options) {
    if (!device) return makeError("no Vulkan device");
    if (options.width < 1 || options.height < 1 || options.width > 16384 || options.height > 16384)
        return makeError("image size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                         " is out of range (1..16384)");
    auto impl = std::make_unique<Impl>();
    impl->dev = std::move(device);
    impl->options = options;
    impl->width = options.width;
    impl->height = options.height;
    if (Status s = impl->init(); !s) return s.error();
    return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

int Renderer::width() const { return impl_->width; }
int Renderer::height() const { return impl_->height; }
int Renderer::msaaSamples() const { return static_cast<int>(impl_->samples); }
Quality Renderer::quality() const { return impl_->fast ? Quality::Fast : Quality::High; }
const std::shared_ptr<VulkanDevice>& Renderer::device() const { return impl_->dev; }
VkImage Renderer::outputImage() const { return impl_->resolve.image; }
VkFormat Renderer::outputFormat() const { return kColorFormat; }
const RenderStats& Renderer::stats() const { return impl_->stats; }

Status Renderer::resize(int width, int height) {
    if (width == impl_->width && height == impl_->height) return {};
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return makeError("image size " + std::to_string(width) + "x" + std::to_string(height) + " is out of range (1..16384)");
    if (Status s = impl_->dev->waitIdle(); !s) return s;
    impl_->destroyTargets();
    impl_->width = width;
    impl_->height = height;
    return impl_->createTargets();
}

Status Renderer::prepare(const FrameDescription& frame) { return impl_->prepare(frame); }

void Renderer::record(VkCommandBuffer cmd) { impl_->record(cmd); }

void Renderer::submitted(VkFence fence) {
    Impl& m = *impl_;
    m.slot().pending = fence;
    m.cur = (m.cur + 1) % m.slots.size();
}

Status Renderer::render(const FrameDescription& frame, Image* out) {
    Impl& m = *impl_;
    const auto t0 = std::chrono::steady_clock::now();
    if (Status s = m.prepare(frame); !s) return s;  // waits until the slot's last frame is done
    const auto t1 = std::chrono::steady_clock::now();
    m.stats.prepareMs = std::chrono::duration<double, std::milli>(t1 - t0).count() - m.stats.waitMs;
    Impl::FrameSlot& f = m.slot();
    VkResult r = vkResetCommandBuffer(f.cmd, 0);
    if (r != VK_SUCCESS) return vkError("vkResetCommandBuffer", r);
    auto bi = vkInit<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if ((r = vkBeginCommandBuffer(f.cmd, &bi)) != VK_SUCCESS) return vkError("vkBeginCommandBuffer", r);
    if (f.timer) {
        vkCmdResetQueryPool(f.cmd, f.timer, 0, 2);
        vkCmdWriteTimestamp(f.cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, f.timer, 0);
    }
    m.record(f.cmd);
    if (out) m.recordReadback(f.cmd);
    if (f.timer) vkCmdWriteTimestamp(f.cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, f.timer, 1);
    if ((r = vkEndCommandBuffer(f.cmd)) != VK_SUCCESS) return vkError("vkEndCommandBuffer", r);
    if ((r = vkResetFences(m.device, 1, &f.fence)) != VK_SUCCESS) return vkError("vkResetFences", r);
    auto si = vkInit<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    si.commandBufferCount = 1;
    si.pCommandBuffers = &f.cmd;
    if ((r = vkQueueSubmit(m.dev->queue(), 1, &si, f.fence)) != VK_SUCCESS) return vkError("vkQueueSubmit", r);
    f.timed = f.timer != VK_NULL_HANDLE;
    submitted(f.fence);
    if (out) {
        if (Status s = m.waitSlot(f); !s) return s;
        m.copyReadback(*out);
    }
    return {};
}

Status Renderer::setRig(const Skeleton& skeleton, const SkinnedMesh& rig) {
    if (Status s = checkSkinnedMesh(rig, skeleton); !s) return s;
    Impl& m = *impl_;
    RigEntry e;
    e.fingerprint = rig.skeletonFingerprint;
    e.jointCount = rig.jointCount;
    e.vertices = rig.vertices;
    e.indices = rig.indices;
    e.inverseBind = rig.inverseBind;
    e.reach = rig.reach;
    const int old = m.rigOf(e.fingerprint, e.jointCount);
    if (old >= 0) m.rigs[static_cast<std::size_t>(old)] = std::move(e);
    else m.rigs.push_back(std::move(e));
    m.rigsDirty = true;
    return {};
}

void Renderer::clearRig(const Skeleton& skeleton) {
    Impl& m = *impl_;
    const int r = m.rigOf(skeletonFingerprint(skeleton), skeleton.jointCount());
    if (r < 0) return;
    m.rigs.erase(m.rigs.begin() + r);
    m.rigsDirty = true;
}

Status Renderer::readback(Image& out) {
    Impl& m = *impl_;
    if (!m.rendered) return makeError("nothing has been rendered at this size yet");
    if (Status s = m.dev->waitIdle(); !s) return s;
    if (Status s = m.dev->runOnce([&](VkCommandBuffer c) { m.recordReadback(c); }); !s) return s;
    m.copyReadback(out);
    return {};
}

}  // namespace fray::render
