#pragma once
// The renderer: draws a FrameDescription into its own colour image (MSAA,
// resolved to RGBA8). Offscreen callers read the image back (PNG frames,
// tests); on-screen callers let a Presenter blit it into a swapchain image.
//
// Per frame: a shadow pass from the sun (depth only, skinned), then one main
// pass: bodies (instanced GPU skinning, one draw per distinct skeleton: its
// capsules, or the rig set for it), floor (grid, painted bitmap, shadows),
// then overlays. See docs/RENDERER.md.
//
// Not thread-safe: one thread records and submits.
#include <cstdint>
#include <memory>

#include <vulkan/vulkan.h>

#include "fray/core/result.h"
#include "fray/core/skinned_mesh.h"
#include "fray/render/body_mesh.h"
#include "fray/render/frame.h"
#include "fray/render/image.h"
#include "fray/render/vulkan_device.h"

namespace fray::render {

// High: 4x MSAA, a 2048 shadow map (bodies and floor receive shadows), full
// detail down to 60 px tall characters. Fast: no MSAA, soft blob shadows under
// each character, coarser bodies below 240 px and cards (a camera-facing
// hexagon per capsule) below 96 px; for the viewport on a CPU
// device (lavapipe), where the shadow pass alone (another single-threaded
// vertex pass) would halve the frame rate. Auto picks Fast on CPU devices and
// High on GPUs.
enum class Quality { Auto, Fast, High };

struct RendererOptions {
    int width = 1280;
    int height = 720;
    Quality quality = Quality::Auto;
    // 0: from the quality. MSAA is clamped to what the device supports.
    int msaaSamples = 0;
    int shadowMapSize = 0;
    BodyMeshOptions body{0, 0};
    // Characters shorter than this on screen (pixels) use a coarser body
    // (6-sided capsules; below 40 % of it 4-sided ones in High, camera-facing
    // cards in Fast); -1: from the quality (Fast 240, High 60), 0: always full detail.
    int lodPixels = -1;
    // Far field (Fast quality): characters smaller than this on screen
    // (pixels, the same measure) are drawn as far cards, the cards of their
    // largest capsules only (those covering 90 % of the body's side-on
    // area); -1: 40 in Fast unless lodPixels is 0, none in High; 0: never.
    int farPixels = -1;
};

struct RenderStats {
    int characters = 0;
    int culled = 0;                // characters outside the view (not drawn in the main pass)
    int drawCalls = 0;             // body draws (one per skeleton and level of detail) + floor (2) + overlay groups
    std::uint64_t triangles = 0;   // body triangles of the main pass (after culling and level of detail)
    int overlayVertices = 0;
    int bufferGrowths = 0;         // GPU buffer reallocations since creation (geometric growth)
    int meshes = 0;                // distinct body meshes on the GPU (capsule bodies and rigs)
    int rigged = 0;                // characters drawn with a rig instead of capsules (in view or not)
    double prepareMs = 0.0;        // wall time of the last frame's CPU side (instances, palettes, overlays)
    double deviceMs = 0.0;         // device time of the last frame render() found finished (GPU timestamps; 0 where
                                   // the queue has none)
    double waitMs = 0.0;           // wall time the last prepare() waited for an earlier frame to leave the device
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
    Quality quality() const;  // Fast or High (Auto resolved)
    const std::shared_ptr<VulkanDevice>& device() const;

    // Changes the output size (waits for the device); no-op when unchanged.
    Status resize(int width, int height);

    // Offscreen: renders one frame. Without `out` it returns once the frame is
    // submitted: the renderer keeps two sets of per-frame buffers, so the
    // caller's work on the next frame (posing, prepare) overlaps the device's
    // work on this one, and the next render() waits only if the device is
    // still on the frame before. With `out` it waits and reads the image back
    // (RGBA8, rows top to bottom, reusing out's storage).
    Status render(const FrameDescription& frame, Image* out = nullptr);

    // On-screen: writes this frame's data into the GPU buffers, then records
    // the passes into the caller's command buffer. prepare() waits for the
    // fence passed to submitted() two frames before (the buffers it writes);
    // a caller that never calls submitted() must instead let every earlier
    // submission that used this renderer complete before prepare().
    Status prepare(const FrameDescription& frame);
    void record(VkCommandBuffer cmd);
    // After submitting record()'s commands: `fence` is signalled when the
    // device is done with them. The next prepare() writes the other buffers.
    void submitted(VkFence fence);
    // The colour image record() leaves in TRANSFER_SRC_OPTIMAL (R8G8B8A8_UNORM).
    VkImage outputImage() const;
    VkFormat outputFormat() const;

    // Copies the last rendered image to `out` (waits for the device).
    Status readback(Image& out);

    const RenderStats& stats() const;

    // From the next frame on, characters with this skeleton (by content
    // fingerprint, so copies count) are drawn as `rig` (e.g. from
    // fray::loadRig) instead of capsules: linear blend skinning on the GPU,
    // full detail at every size. Replaces an earlier rig of the skeleton. The
    // rig is copied and uploaded by the next prepare(); call these between
    // frames, not between prepare() and record(). An error (a rig bound to
    // another skeleton, bad indices or weights) leaves the renderer as it was.
    Status setRig(const Skeleton& skeleton, const SkinnedMesh& rig);
    // Back to capsules for this skeleton (no-op when it has no rig).
    void clearRig(const Skeleton& skeleton);

private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace fray::render
