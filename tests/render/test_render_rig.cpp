// Rigs in the renderer (Renderer::setRig) on lavapipe with validation on: the
// demo skeleton exported as a skinned GLB by Fray's exporter, loaded back with
// fray::loadRig, drawn instead of the capsules. The exported body is built
// from the same skeleton, so both must cover the same pixels; a raised arm
// moves the rig's arm and nothing else; mixed frames, clearing, bad rigs, and
// no allocation once warm.
#include <gtest/gtest.h>

#include <cstdio>
#include <stdexcept>

#include "alloc_counter.h"
#include "fray/io/rig_import.h"
#include "render_fixture.h"
#include "rig_fixture.h"
#include "temp_dir.h"

namespace fray::render::test {
namespace {

using fray::test::TempDir;

const glm::vec3 kTint(0.8f, 0.3f, 0.25f);

// The demo skeleton's GLB rig, written and loaded once per process.
const SkinnedMesh& exportedRig() {
    static const SkinnedMesh rig = [] {
        TempDir dir("fray_render_rig_");
        fray::test::writeExportedRig(demoSkeleton(), dir / "demo.glb", false);
        auto r = loadRig(dir / "demo.glb", demoSkeleton());
        if (!r) throw std::runtime_error(r.error().message);
        return std::move(*r);
    }();
    return rig;
}

// Pixels where `img` differs from the empty scene: the body's silhouette.
std::vector<std::uint8_t> silhouette(const Image& img, const Image& empty) {
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(img.width * img.height), 0);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const std::uint8_t* p = img.pixel(x, y);
            const std::uint8_t* q = empty.pixel(x, y);
            for (int k = 0; k < 3; ++k)
                if (std::abs(int(p[k]) - int(q[k])) > 8) mask[static_cast<std::size_t>(y * img.width + x)] = 1;
        }
    return mask;
}

double intersectionOverUnion(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    int inter = 0, uni = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        inter += a[i] && b[i];
        uni += a[i] || b[i];
    }
    return uni ? static_cast<double>(inter) / uni : 0.0;
}

// One character seen from the front, close up, without shadows (so the
// silhouette is the body alone).
FrameDescription closeUp() {
    FrameDescription f;
    f.camera = goldenCamera();
    f.camera.yaw = 0.0f;
    f.camera.distance = 4.0f;
    f.settings.shadows = false;
    return f;
}

using RenderRig = GpuTest;

TEST_F(RenderRig, TheExportedRigCoversTheCapsulesPixels) {
    const SkinnedMesh& rig = exportedRig();
    const Character c = posedCharacter({0.0f, 0.0f, 0.0f}, 25.0f,
                                       {{"LeftForeArm", aboutAxis(-50.0f, {0, 1, 0})}, {"RightUpLeg", aboutAxis(-30.0f, {1, 0, 0})}});
    FrameDescription f = closeUp();
    const Image empty = renderImage(f);
    const std::vector<CharacterInstance> one{instanceOf(c, kTint)};
    f.characters = one;
    const Image capsules = renderImage(f);
    const std::uint64_t capsuleTriangles = renderer->stats().triangles;
    EXPECT_EQ(renderer->stats().rigged, 0);
    ASSERT_TRUE(renderer->setRig(demoSkeleton(), rig).ok());
    const Image rigged = renderImage(f);
    EXPECT_EQ(renderer->stats().rigged, 1);
    EXPECT_EQ(renderer->stats().triangles, rig.indices.size() / 3);
    EXPECT_EQ(renderer->stats().triangles, capsuleTriangles) << "the exported body is the full-detail capsule body";
    const auto a = silhouette(capsules, empty);
    const auto b = silhouette(rigged, empty);
    const double iou = intersectionOverUnion(a, b);
    int area = 0;
    for (std::uint8_t m : a) area += m;
    std::printf("silhouette: %d px, IoU rig/capsules %.4f, pixels differing %d\n", area, iou,
                compareImages(capsules, rigged, 8).differing);
    EXPECT_GT(area, 1000);
    EXPECT_GT(iou, 0.95);
    // Lit and shadowed too: the rig's shadow pass runs (validation checks it).
    f.settings.shadows = true;
    const Image shadowed = renderImage(f);
    EXPECT_GT(compareImages(shadowed, rigged, 8).differing, 100);
    // Cleared, the capsules come back pixel for pixel.
    renderer->clearRig(demoSkeleton());
    f.settings.shadows = false;
    EXPECT_EQ(compareImages(renderImage(f), capsules, 0).differing, 0);
    EXPECT_EQ(renderer->stats().rigged, 0);
}

TEST_F(RenderRig, BlendedWeightsLandWhereCpuSkinningPutsThem) {
    // Every vertex of the exported body shared half and half with the hips:
    // the shader must blend the two joints' transforms. The reference is the
    // same body skinned on the CPU and baked onto the hips alone.
    const Skeleton& sk = demoSkeleton();
    SkinnedMesh blended = exportedRig();
    for (SkinnedVertex& v : blended.vertices) {
        if (v.joints[0] == 0) continue;
        v.joints = {v.joints[0], 0, 0, 0};
        v.weights = glm::vec4(0.5f, 0.5f, 0.0f, 0.0f);
    }
    const Character c = posedCharacter({0.2f, 0.0f, 0.0f}, 40.0f, {{"Spine", aboutAxis(25.0f, {1, 0, 0})},
                                                                  {"RightArm", aboutAxis(-60.0f, {0, 0, 1})}});
    const auto world = fray::test::skinOnCpu(blended, c.positions, c.rotations);
    SkinnedMesh baked = blended;
    const RigidTransform toHips = invert(RigidTransform{c.positions[0], c.rotations[0]} * baked.inverseBind[0]);
    for (std::size_t i = 0; i < baked.vertices.size(); ++i) {
        baked.vertices[i].position = toHips.translation + toHips.rotation * world[i];
        baked.vertices[i].joints = {0, 0, 0, 0};
        baked.vertices[i].weights = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
    }
    FrameDescription f = closeUp();
    const Image empty = renderImage(f);
    const std::vector<CharacterInstance> one{instanceOf(c, kTint)};
    f.characters = one;
    ASSERT_TRUE(renderer->setRig(sk, exportedRig()).ok());
    const auto rigid = silhouette(renderImage(f), empty);
    ASSERT_TRUE(renderer->setRig(sk, blended).ok());
    const auto gpu = silhouette(renderImage(f), empty);
    ASSERT_TRUE(renderer->setRig(sk, baked).ok());
    const auto cpu = silhouette(renderImage(f), empty);
    const double iouCpu = intersectionOverUnion(gpu, cpu), iouRigid = intersectionOverUnion(gpu, rigid);
    std::printf("blended body: IoU with CPU skinning %.4f, with the rigid body %.4f\n", iouCpu, iouRigid);
    EXPECT_GT(iouCpu, 0.97);
    EXPECT_LT(iouRigid, 0.8) << "blending with the hips must visibly move the limbs";
}

TEST_F(RenderRig, RaisingAnArmMovesTheRigsArmOnly) {
    ASSERT_TRUE(renderer->setRig(demoSkeleton(), exportedRig()).ok());
    const Character down = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f);
    const Character up = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f, {{"RightArm", aboutAxis(-60.0f, {0, 0, 1})}});
    FrameDescription f = closeUp();
    const std::vector<CharacterInstance> a{instanceOf(down, kTint)};
    const std::vector<CharacterInstance> b{instanceOf(up, kTint)};
    f.characters = a;
    const Image imgDown = renderImage(f);
    f.characters = b;
    const Image imgUp = renderImage(f);
    EXPECT_EQ(renderer->stats().rigged, 1);
    const ArmChange change = armChange(f, down, up, imgDown, imgUp);
    EXPECT_GT(change.inside, 150) << "raising the arm must change the rig's picture around the arm";
    EXPECT_EQ(change.outside, 0) << "pixels changed away from the arm (box " << change.box << ")";
}

TEST_F(RenderRig, RiggedAndCapsuleCharactersShareAFrame) {
    ASSERT_TRUE(renderer->setRig(demoSkeleton(), exportedRig()).ok());
    Skeleton other = demoSkeleton();  // another skeleton: capsules
    other.offsets[static_cast<std::size_t>(other.find("LeftLeg"))].y -= 0.05f;
    const Skeleton copy = demoSkeleton();  // a copy of the rigged one: the rig
    const Character c1 = posedCharacter({-0.8f, 0.0f, 0.0f}, 0.0f);
    const Character c2 = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f);
    const Character c3 = posedCharacter({0.8f, 0.0f, 0.0f}, 0.0f);
    std::vector<CharacterInstance> v{instanceOf(c1, kTint), instanceOf(c2, kTint), instanceOf(c3, kTint)};
    v[1].skeleton = &other;
    v[2].skeleton = &copy;
    FrameDescription f = closeUp();
    f.settings.shadows = true;
    f.characters = v;
    ASSERT_TRUE(renderer->render(f).ok());
    EXPECT_EQ(renderer->stats().rigged, 2);
    EXPECT_EQ(renderer->stats().meshes, 2);  // the capsule body of `other` and the rig
    EXPECT_EQ(renderer->stats().characters, 3);
}

TEST_F(RenderRig, ARigOfAnotherSkeletonIsRefused) {
    Skeleton other = demoSkeleton();
    other.offsets[1].y += 0.1f;
    const Status s = renderer->setRig(other, exportedRig());
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("bound to another skeleton"), std::string::npos) << s.error().message;
    SkinnedMesh broken = exportedRig();
    broken.vertices[3].joints[0] = 999;
    EXPECT_FALSE(renderer->setRig(demoSkeleton(), broken).ok());
    // Nothing was set: the capsules are drawn.
    const Character c = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f);
    const std::vector<CharacterInstance> one{instanceOf(c, kTint)};
    FrameDescription f = closeUp();
    f.characters = one;
    ASSERT_TRUE(renderer->render(f).ok());
    EXPECT_EQ(renderer->stats().rigged, 0);
}

TEST_F(RenderRig, FastQualityAndSteadyStateWithoutAllocation) {
    // As RenderEngine.SteadyStateFramesDoNotAllocate, on a device without
    // the validation layer (which allocates for itself), with a rig.
    DeviceOptions o;
    o.preference = DevicePreference::Cpu;
    auto plain = VulkanDevice::create(o);
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    for (Quality q : {Quality::High, Quality::Fast}) {
        RendererOptions ro;
        ro.width = kWidth;
        ro.height = kHeight;
        ro.quality = q;
        auto r = Renderer::create(*plain, ro);
        ASSERT_TRUE(r.ok()) << r.error().message;
        ASSERT_TRUE((*r)->setRig(demoSkeleton(), exportedRig()).ok());
        const Character a = posedCharacter({-0.6f, 0.0f, 0.0f}, 90.0f);
        const Character b = posedCharacter({0.6f, 0.0f, 0.0f}, -90.0f);
        std::vector<CharacterInstance> v{instanceOf(a, kTint), instanceOf(b, glm::vec3(0.25f, 0.45f, 0.8f))};
        v[0].label = "jab";
        v[1].selected = true;
        FrameDescription f;
        f.camera = goldenCamera();
        f.characters = v;
        Image img;
        ASSERT_TRUE((*r)->render(f, &img).ok());
        ASSERT_TRUE((*r)->render(f, &img).ok());
        EXPECT_EQ((*r)->stats().rigged, 2);
        const long before = allocationCount();
        for (int i = 0; i < 3; ++i) {
            f.camera.yaw += 0.1f;
            ASSERT_TRUE((*r)->render(f, &img).ok());
        }
        EXPECT_EQ(allocationCount() - before, 0) << "C++ allocations during steady-state frames with a rig";
    }
}

}  // namespace
}  // namespace fray::render::test
