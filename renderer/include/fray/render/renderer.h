#pragma once
// The renderer: draws a FrameDescription into its own colour image (MSAA,
// resolved to RGBA8). Offscreen callers read the image back (PNG frames,
// tests); on-screen callers let a Presenter blit it into a swapchain image.
//
// Per frame: a shadow pass from the sun (depth only, skinned), then one main
// pass: bodies (instanced GPU skinning, one draw per distinct skeleton),
// floor (grid, painted bitmap, shadows), then overlays. See docs/RENDERER.md.
//
// Not thread-safe: one thread records and submits.
#include <cstdint>
#include <memory>

#include <vulkan/vulkan.h>

#include "fray/core/result.h"
#include "fray/render/body_mesh.h"
#include "fray/render/frame.h"
#include "fray/render/image.h"
#include "fray/render/vulkan_device.h"

namespace fray::render {

struct RendererOptions {
    int width = 1280;
    int height = 720;
    int msaaSamples = 4;        // clamped to what the device supports (1 disables MSAA)
    int shadowMapSize = 2048;
    BodyMeshOptions body;
};

struct RenderStats {
    int characters = 0;
    int drawCalls = 0;             // body draws (one per distinct skeleton) + floor + overlay groups
    std::uint64_t triangles = 0;   // body triangles of the main pass
    int overlayVertices = 0;
    int bufferGrowths = 0;         // GPU buffer reallocations since creation (geometric growth)
    int meshes = 0;                // distinct body meshes on the GPU
};

class Renderer {
public:
    static Result<std::unique_ptr<Renderer>> create(std::shared_ptr<VulkanDevice> device, const RendererOptions& options);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    int width() const;
    int height() const;
    int msaaSamples() const;  // the sample count actually used
    const std::shared_ptr<VulkanDevice>& device() const;

    // Changes the output size (waits for the device); no-op when unchanged.
    Status resize(int width, int height);

    // Offscreen: renders one frame and waits for it; with `out`, also reads the
    // image back (RGBA8, rows top to bottom, reusing out's storage).
    Status render(const FrameDescription& frame, Image* out = nullptr);

    // On-screen: writes this frame's data into the GPU buffers, then records
    // the passes into the caller's command buffer. Any earlier submission that
    // used this renderer must have completed before prepare().
    Status prepare(const FrameDescription& frame);
    void record(VkCommandBuffer cmd);
    // The colour image record() leaves in TRANSFER_SRC_OPTIMAL (R8G8B8A8_UNORM).
    VkImage outputImage() const;
    VkFormat outputFormat() const;

    // Copies the last rendered image to `out` (waits for the device).
    Status readback(Image& out);

    const RenderStats& stats() const;

private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace fray::render
