// Rendering on lavapipe with validation on: golden images (one per overlay
// kind), checks that each overlay changes the picture where it should, that a
// pose change changes only the moved limb's pixels, determinism, buffer
// growth, and input errors.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include <dlfcn.h>


#include "fray/render/motion_stage.h"
#include "alloc_counter.h"
#include "render_fixture.h"

namespace fray::render::test {
namespace {

const glm::vec3 kRed(0.8f, 0.3f, 0.25f);
const glm::vec3 kBlue(0.25f, 0.45f, 0.8f);

// Two fighters facing each other across the origin.
struct Duel {
    Character red = posedCharacter({-0.6f, 0.0f, 0.0f}, 90.0f, {{"RightArm", aboutAxis(10.0f, {0, 1, 0})}});
    Character blue = posedCharacter({0.6f, 0.0f, 0.0f}, -90.0f);
    std::vector<CharacterInstance> instances{instanceOf(red, kRed), instanceOf(blue, kBlue)};

    FrameDescription frame() const {
        FrameDescription f;
        f.camera = goldenCamera();
        f.characters = instances;
        return f;
    }
};

glm::vec3 pixelOf(const FrameDescription& f, glm::vec3 p) {
    auto px = projectToPixel(f.camera.viewProjection(static_cast<float>(kWidth) / kHeight), p,
                             glm::vec2(kWidth, kHeight));
    EXPECT_TRUE(px.has_value());
    return px.value_or(glm::vec3(0.0f));
}

const std::uint8_t* at(const Image& img, glm::vec3 px) {
    return img.pixel(std::clamp(static_cast<int>(px.x), 0, img.width - 1), std::clamp(static_cast<int>(px.y), 0, img.height - 1));
}

int jointIndex(const char* name) { return demoSkeleton().find(name); }

// A body's pixel: one that differs from the empty floor's by more than 8 in a channel.
bool differs(const Image& img, const Image& empty, int x, int y) {
    for (int k = 0; k < 3; ++k)
        if (std::abs(int(img.pixel(x, y)[k]) - int(empty.pixel(x, y)[k])) > 8) return true;
    return false;
}

using RenderGolden = GpuTest;

TEST_F(RenderGolden, TwoCharactersOnALitFloor) {
    const Duel d;
    const FrameDescription f = d.frame();
    const Image img = renderImage(f);
    expectMatchesGolden(img, "two_characters");
    const ImageStats st = imageStats(img);
    EXPECT_GT(st.distinctColors, 200);
    EXPECT_GT(st.lumaStdDev, 10.0);
    // Team tints reach the picture: the chests are red and blue.
    const auto* r = at(img, pixelOf(f, d.red.positions[static_cast<std::size_t>(jointIndex("Spine1"))]));
    const auto* b = at(img, pixelOf(f, d.blue.positions[static_cast<std::size_t>(jointIndex("Spine1"))]));
    EXPECT_GT(r[0], r[2] + 40);
    EXPECT_GT(b[2], b[0] + 40);
}

TEST_F(RenderGolden, ShadowsDarkenTheFloorAwayFromTheLight) {
    const Duel d;
    FrameDescription f = d.frame();
    const Image lit = renderImage(f);
    f.settings.shadows = false;
    const Image flat = renderImage(f);
    const ImageDiff diff = compareImages(lit, flat, 8);
    EXPECT_GT(diff.differing, 300);
    // The sun travels towards -x, -z: shadows fall on that side of the feet.
    const glm::vec3 feet = pixelOf(f, {0.0f, 0.0f, 0.0f});
    const glm::vec3 shadowSide = pixelOf(f, {-0.9f, 0.0f, -0.7f});
    EXPECT_LT(static_cast<float>(diff.minX), std::max(feet.x, shadowSide.x));
    // Shadowed pixels are darker, never brighter.
    int darker = 0, brighter = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const int a = lit.pixel(x, y)[1], b = flat.pixel(x, y)[1];
            darker += a + 8 < b;
            brighter += a > b + 8;
        }
    EXPECT_GT(darker, 300);
    EXPECT_LT(brighter, darker / 20);
}

// The viewport quality on CPU devices: no MSAA, blob shadows.
TEST_F(RenderGolden, FastQualityWithBlobShadows) {
    RendererOptions o;
    o.width = kWidth;
    o.height = kHeight;
    o.quality = Quality::Fast;
    o.lodPixels = 0;  // both in full detail, whatever their size on screen
    auto fast = Renderer::create(GpuEnvironment::device(), o);
    ASSERT_TRUE(fast.ok()) << fast.error().message;
    EXPECT_EQ((*fast)->quality(), Quality::Fast);
    EXPECT_EQ((*fast)->msaaSamples(), 1);
    const Duel d;
    FrameDescription f = d.frame();
    Image img, flat;
    ASSERT_TRUE((*fast)->render(f, &img).ok());
    expectMatchesGolden(img, "fast_two_characters");
    EXPECT_EQ((*fast)->stats().triangles, 2u * 28u * 64u);
    f.settings.shadows = false;
    ASSERT_TRUE((*fast)->render(f, &flat).ok());
    const ImageDiff diff = compareImages(img, flat, 8);
    EXPECT_GT(diff.differing, 200);
    // The blobs lie on the floor around the feet, below the knees.
    const glm::vec3 feet = pixelOf(f, {0.0f, 0.0f, 0.0f});
    const glm::vec3 knee = pixelOf(f, d.red.positions[static_cast<std::size_t>(jointIndex("LeftLeg"))]);
    EXPECT_LE(static_cast<float>(diff.minY), feet.y);
    EXPECT_GE(static_cast<float>(diff.minY), knee.y);
}

TEST_F(RenderGolden, TrajectoryAndCheckpoints) {
    const Duel d;
    FrameDescription f = d.frame();
    const Image base = renderImage(f);
    std::vector<glm::vec3> path;
    for (int i = 0; i <= 24; ++i) {
        const float a = -1.2f + 2.4f * static_cast<float>(i) / 24.0f;
        path.emplace_back(1.6f * std::sin(a), 0.0f, 1.2f - 0.9f * std::cos(a));
    }
    const std::vector<Polyline> lines{{path, {1.0f, 0.75f, 0.15f, 0.95f}, 0.07f}};
    const std::vector<Checkpoint> marks{{path.front(), {0.2f, 0.9f, 0.4f, 1.0f}, 0.3f, "start"},
                                        {path[12], {1.0f, 0.75f, 0.15f, 1.0f}, 0.25f, {}},
                                        {path.back(), {0.95f, 0.3f, 0.3f, 1.0f}, 0.3f, "end"}};
    f.trajectories = lines;
    f.checkpoints = marks;
    const Image img = renderImage(f);
    expectMatchesGolden(img, "trajectory_checkpoints");
    // The path's middle (in front of the fighters) turned path-coloured.
    const auto* mid = at(img, pixelOf(f, path[6]));
    EXPECT_GT(mid[0], mid[2] + 60) << "trajectory colour expected at its midpoint";
    const ImageDiff diff = compareImages(img, base, 8);
    EXPECT_GT(diff.differing, 400);
}

TEST_F(RenderGolden, FloorBitmap) {
    const Duel d;
    FrameDescription f = d.frame();
    const Image base = renderImage(f);
    // A 64x32 painting: blue background, a white border and the word FRAY.
    Image paint;
    paint.resize(64, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) {
            std::uint8_t* p = paint.pixel(x, y);
            const bool border = x < 2 || y < 2 || x >= 62 || y >= 30;
            p[0] = border ? 255 : 40;
            p[1] = border ? 255 : 90;
            p[2] = border ? 255 : 200;
            p[3] = 220;
        }
    const std::uint8_t yellow[4] = {255, 220, 40, 255};
    drawText(paint, 10, 8, "FRAY", 2, yellow, false);
    FloorBitmap bmp = floorBitmapOf(paint);
    f.floorBitmap = &bmp;
    const Image img = renderImage(f);
    expectMatchesGolden(img, "floor_bitmap");
    // Inside the rectangle (in front of the fighters) the floor is blue.
    const auto* inside = at(img, pixelOf(f, {-1.5f, 0.0f, 2.0f}));
    EXPECT_GT(inside[2], inside[0] + 60);
    const ImageDiff diff = compareImages(img, base, 8);
    EXPECT_GT(diff.differing, 2000);
    const float farEdge = std::min(pixelOf(f, {-2.0f, 0.0f, 0.4f}).y, pixelOf(f, {2.0f, 0.0f, 0.4f}).y);
    EXPECT_GE(static_cast<float>(diff.minY), farEdge - 2.0f) << "nothing above the bitmap's far edge changes";
    // Changing pixels in place with a new revision is picked up.
    std::fill(paint.rgba.begin(), paint.rgba.end(), std::uint8_t(0));
    bmp.revision = 1;
    EXPECT_EQ(compareImages(renderImage(f), base, 8).differing, 0);
}

TEST_F(RenderGolden, SelectionHighlight) {
    Duel d;
    const FrameDescription f0 = d.frame();
    const Image base = renderImage(f0);
    d.instances[1].selected = true;
    const FrameDescription f = d.frame();
    const Image img = renderImage(f);
    expectMatchesGolden(img, "selection");
    const ImageDiff diff = compareImages(img, base, 8);
    EXPECT_GT(diff.differing, 150);
    // Only the blue fighter and the ring under it change: the red one does not.
    const glm::vec3 redChest = pixelOf(f, d.red.positions[static_cast<std::size_t>(jointIndex("Spine1"))]);
    const auto* a = at(img, redChest);
    const auto* b = at(base, redChest);
    EXPECT_EQ(a[0], b[0]);
    const glm::vec3 blueFeet = pixelOf(f, {0.6f, 0.0f, 0.0f});
    EXPECT_LE(static_cast<float>(diff.minX), blueFeet.x);
    EXPECT_GE(static_cast<float>(diff.maxX), blueFeet.x);
}

TEST_F(RenderGolden, HitFlash) {
    const Duel d;
    FrameDescription f = d.frame();
    const Image base = renderImage(f);
    const glm::vec3 hand = d.red.positions[static_cast<std::size_t>(jointIndex("RightHand"))];
    const std::vector<Flash> flashes{{glm::vec3(0.0f, 1.45f, 0.0f), 0.22f, {1.0f, 0.35f, 0.1f, 0.95f}},
                                     {hand, 0.1f, {1.0f, 0.9f, 0.2f, 0.9f}}};
    f.flashes = flashes;
    const Image img = renderImage(f);
    expectMatchesGolden(img, "hit_flash");
    // The core of the flash is nearly white, drawn over the bodies.
    const glm::vec3 c = pixelOf(f, flashes[0].position);
    const auto* p = at(img, c);
    EXPECT_GT(p[0], 235);
    EXPECT_GT(p[1], 200);
    const ImageDiff diff = compareImages(img, base, 8);
    EXPECT_GT(diff.differing, 100);
    const float r = std::abs(pixelOf(f, flashes[0].position + f.camera.right() * 0.22f).x - c.x);
    EXPECT_GE(static_cast<float>(diff.minY), c.y - r - 2.0f);
}

TEST_F(RenderGolden, ActionLabels) {
    Duel d;
    const Image base = renderImage(d.frame());
    d.instances[0].label = "jab";
    d.instances[1].label = "block";
    const FrameDescription f = d.frame();
    const Image img = renderImage(f);
    expectMatchesGolden(img, "labels");
    const ImageDiff diff = compareImages(img, base, 8);
    EXPECT_GT(diff.differing, 150);
    // Labels sit above the heads.
    const float head = pixelOf(f, d.red.positions[static_cast<std::size_t>(jointIndex("Head"))]).y;
    EXPECT_LT(static_cast<float>(diff.maxY), head);
    // Turning labels off removes them.
    FrameDescription off = f;
    off.settings.labels = false;
    EXPECT_EQ(compareImages(renderImage(off), base, 8).differing, 0);
}

TEST_F(RenderGolden, RaisingAnArmChangesOnlyTheArmRegion) {
    const Character down = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f);
    const Character up = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f, {{"RightArm", aboutAxis(-60.0f, {0, 0, 1})}});
    FrameDescription f;
    f.camera = goldenCamera();
    f.camera.yaw = 0.0f;
    f.camera.distance = 4.0f;
    f.settings.shadows = false;  // the arm's shadow would (rightly) move too
    const std::vector<CharacterInstance> a{instanceOf(down, kRed)};
    const std::vector<CharacterInstance> b{instanceOf(up, kRed)};
    f.characters = a;
    const Image imgDown = renderImage(f);
    f.characters = b;
    const Image imgUp = renderImage(f);

    const ArmChange change = armChange(f, down, up, imgDown, imgUp);
    EXPECT_GT(change.inside, 150) << "raising the arm must change the picture around the arm";
    EXPECT_EQ(change.outside, 0) << "pixels changed away from the arm (box " << change.box << ")";
}

TEST_F(RenderGolden, SameInputSamePixels) {
    const Duel d;
    const Image first = renderImage(d.frame());
    FrameDescription other = d.frame();
    other.camera.yaw = -1.0f;
    (void)renderImage(other);
    const Image again = renderImage(d.frame());
    EXPECT_EQ(compareImages(first, again, 0).differing, 0);
    EXPECT_EQ(first.rgba, again.rgba);
}

using RenderEngine = GpuTest;

TEST_F(RenderEngine, BuffersGrowGeometricallyAndMeshesAreShared) {
    const Character c = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f);
    std::vector<CharacterInstance> crowd;
    FrameDescription f;
    f.camera = goldenCamera();
    f.camera.distance = 60.0f;
    f.settings.shadows = false;
    crowd.push_back(instanceOf(c, kRed));
    f.characters = crowd;
    ASSERT_TRUE(renderer->render(f).ok());
    const int growthsSmall = renderer->stats().bufferGrowths;
    // 600 characters (one shared skeleton object) need bigger buffers once.
    std::vector<Character> many;
    for (int i = 0; i < 600; ++i) many.push_back(posedCharacter({(i % 30) * 1.0f - 15.0f, 0.0f, (i / 30) * -1.0f}, 0.0f));
    crowd.clear();
    for (const Character& m : many) crowd.push_back(instanceOf(m, teamColor(static_cast<int>(crowd.size()))));
    f.characters = crowd;
    // Two frames are in flight, each with its own buffers: both grow once.
    ASSERT_TRUE(renderer->render(f).ok());
    ASSERT_TRUE(renderer->render(f).ok());
    const int growthsBig = renderer->stats().bufferGrowths;
    EXPECT_GT(growthsBig, growthsSmall);
    EXPECT_LE(growthsBig - growthsSmall, 8);  // per frame: instances + palette, at most twice each
    ASSERT_TRUE(renderer->render(f).ok());
    ASSERT_TRUE(renderer->render(f).ok());
    EXPECT_EQ(renderer->stats().bufferGrowths, growthsBig);
    EXPECT_EQ(renderer->stats().meshes, 1);
    EXPECT_EQ(renderer->stats().characters, 600);
    // 60 m away every character is a few pixels tall: all use the coarsest
    // body (4-sided capsules, 16 triangles per bone), none is culled.
    EXPECT_EQ(renderer->stats().triangles, 600u * 28u * 16u);
    EXPECT_EQ(renderer->stats().culled, 0);
    // A copy of the skeleton shares the mesh; a different skeleton adds one.
    Skeleton copy = demoSkeleton();
    Skeleton longer = demoSkeleton();
    longer.offsets[static_cast<std::size_t>(jointIndex("LeftLeg"))].y -= 0.1f;
    crowd.resize(3);
    crowd[1].skeleton = &copy;
    crowd[2].skeleton = &longer;
    f.characters = crowd;
    ASSERT_TRUE(renderer->render(f).ok());
    EXPECT_EQ(renderer->stats().meshes, 2);
}

TEST_F(RenderEngine, LevelOfDetailAndCulling) {
    const Character near = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f);
    const Character far = posedCharacter({0.0f, 0.0f, -80.0f}, 0.0f);
    const Character behind = posedCharacter({0.0f, 0.0f, 30.0f}, 0.0f);
    const Character aside = posedCharacter({40.0f, 0.0f, 0.0f}, 0.0f);
    FrameDescription f;
    f.camera = goldenCamera();
    f.camera.yaw = 0.0f;
    std::vector<CharacterInstance> v{instanceOf(near, kRed)};
    f.characters = v;
    ASSERT_TRUE(renderer->render(f).ok());
    EXPECT_EQ(renderer->stats().triangles, 28u * 64u);  // the full body: 8-sided capsules with two cap rings
    v.push_back(instanceOf(far, kBlue));
    f.characters = v;
    ASSERT_TRUE(renderer->render(f).ok());
    EXPECT_EQ(renderer->stats().triangles, 28u * 64u + 28u * 16u);  // the far one is coarsest (4-sided)
    const Character mid = posedCharacter({0.0f, 0.0f, -8.0f}, 0.0f);  // about 40 px tall
    std::vector<CharacterInstance> three{v[0], v[1], instanceOf(mid, kBlue)};
    f.characters = three;
    ASSERT_TRUE(renderer->render(f).ok());
    EXPECT_EQ(renderer->stats().triangles, 28u * 64u + 28u * 16u + 28u * 24u);  // 6-sided for the middle one
    v.push_back(instanceOf(behind, kBlue));
    v.push_back(instanceOf(aside, kBlue));
    f.characters = v;
    f.settings.shadows = false;  // (the shadow volume would grow to include them)
    Image withHidden;
    ASSERT_TRUE(renderer->render(f, &withHidden).ok());
    EXPECT_EQ(renderer->stats().culled, 2);
    EXPECT_EQ(renderer->stats().triangles, 28u * 64u + 28u * 16u);
    // Nothing of the culled characters was visible anyway.
    f.characters = std::span<const CharacterInstance>(v.data(), 2);
    Image without;
    ASSERT_TRUE(renderer->render(f, &without).ok());
    EXPECT_EQ(compareImages(withHidden, without, 0).differing, 0);
}

// Fast quality draws characters a few dozen pixels tall as camera-facing
// cards, four triangles per capsule: they cover the pixels the capsules cover
// and are shaded in the character's tint, from the side and from above (bones
// seen end-on), and the default thresholds pick them for small characters only.
TEST_F(RenderEngine, FastQualityDrawsSmallCharactersAsCards) {
    RendererOptions o;
    o.width = kWidth;
    o.height = kHeight;
    o.quality = Quality::Fast;
    o.lodPixels = 100000;  // everyone counts as small: cards
    auto cards = Renderer::create(GpuEnvironment::device(), o);
    o.lodPixels = 0;  // full-detail capsules
    auto capsules = Renderer::create(GpuEnvironment::device(), o);
    ASSERT_TRUE(cards.ok() && capsules.ok());
    const Character c = posedCharacter({0.0f, 0.0f, 0.0f}, 30.0f, {{"RightArm", aboutAxis(-60.0f, {0, 0, 1})}});
    const std::vector<CharacterInstance> one{instanceOf(c, kRed)};
    for (const float pitch : {0.32f, 1.5f}) {
        FrameDescription f;
        f.camera = goldenCamera();
        f.camera.pitch = pitch;
        f.settings.shadows = false;
        Image empty, withCards, withCapsules;
        ASSERT_TRUE((*cards)->render(f, &empty).ok());
        f.characters = one;
        ASSERT_TRUE((*cards)->render(f, &withCards).ok());
        EXPECT_EQ((*cards)->stats().triangles, 28u * 4u);
        ASSERT_TRUE((*capsules)->render(f, &withCapsules).ok());
        EXPECT_EQ((*capsules)->stats().triangles, 28u * 64u);
        // The body's pixels: those that differ from the empty floor.
        int both = 0, either = 0, reddish = 0, cardPixels = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                const bool a = differs(withCards, empty, x, y), b = differs(withCapsules, empty, x, y);
                both += a && b;
                either += a || b;
                cardPixels += a;
                const std::uint8_t* p = withCards.pixel(x, y);
                reddish += a && p[0] > p[2] + 40;
            }
        ASSERT_GT(either, 300) << "pitch " << pitch;
        const double iou = static_cast<double>(both) / static_cast<double>(either);
        EXPECT_GT(iou, 0.9) << "cards and capsules cover different pixels (pitch " << pitch << ")";
        EXPECT_GT(reddish, cardPixels * 8 / 10) << "cards are shaded in the tint (pitch " << pitch << ")";
    }
    // Default thresholds: the near character in full detail, one 8 m back
    // (about 40 px tall) as cards; High quality keeps 4-sided capsules for it.
    o.lodPixels = -1;
    auto fast = Renderer::create(GpuEnvironment::device(), o);
    ASSERT_TRUE(fast.ok());
    // Both characters outlive the frames (instances only point at their joints).
    const Character nearBody = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f);
    const Character mid = posedCharacter({0.0f, 0.0f, -8.0f}, 0.0f);
    FrameDescription f;
    f.camera = goldenCamera();
    f.camera.yaw = 0.0f;
    std::vector<CharacterInstance> v{instanceOf(nearBody, kRed)};
    f.characters = v;
    ASSERT_TRUE((*fast)->render(f).ok());
    const std::uint64_t near = (*fast)->stats().triangles;
    EXPECT_GE(near, 28u * 24u);
    v.push_back(instanceOf(mid, kBlue));
    f.characters = v;
    ASSERT_TRUE((*fast)->render(f).ok());
    EXPECT_EQ((*fast)->stats().triangles, near + 28u * 4u);
}

// Far cards (the far field's level of detail in Fast) against full-detail
// capsules, from near (a close-up, where the dropped small bones show most)
// and from far (where they are drawn): the same body pixels within the IoU
// thresholds, fewer triangles; the default thresholds use them only for
// characters under farPixels.
TEST_F(RenderEngine, FarCardsCoverFullDetailPixels) {
    RendererOptions o;
    o.width = kWidth;
    o.height = kHeight;
    o.quality = Quality::Fast;
    o.lodPixels = 100000;
    o.farPixels = 100000;  // everyone counts as far: far cards
    auto far = Renderer::create(GpuEnvironment::device(), o);
    o.lodPixels = 0;  // full-detail capsules
    o.farPixels = 0;
    auto full = Renderer::create(GpuEnvironment::device(), o);
    ASSERT_TRUE(far.ok() && full.ok());
    const Character c = posedCharacter({0.0f, 0.0f, 0.0f}, 30.0f, {{"RightArm", aboutAxis(-60.0f, {0, 0, 1})}});
    const std::vector<CharacterInstance> one{instanceOf(c, kRed)};
    struct View {
        float distance, pitch, minIou;
    };
    for (const View v : {View{6.0f, 0.32f, 0.85}, View{6.0f, 1.5f, 0.85}, View{30.0f, 0.32f, 0.75}}) {
        FrameDescription f;
        f.camera = goldenCamera();
        f.camera.distance = v.distance;
        f.camera.pitch = v.pitch;
        f.settings.shadows = false;
        Image empty, withFar, withFull;
        ASSERT_TRUE((*far)->render(f, &empty).ok());
        f.characters = one;
        ASSERT_TRUE((*far)->render(f, &withFar).ok());
        const std::uint64_t farTriangles = (*far)->stats().triangles;
        ASSERT_TRUE((*full)->render(f, &withFull).ok());
        EXPECT_EQ((*full)->stats().triangles, 28u * 64u);
        EXPECT_GT(farTriangles, 0u);
        EXPECT_LT(farTriangles, 28u * 4u) << "far cards are fewer than the cards";
        int both = 0, either = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                const bool a = differs(withFar, empty, x, y), b = differs(withFull, empty, x, y);
                both += a && b;
                either += a || b;
            }
        ASSERT_GT(either, 30) << "distance " << v.distance;
        const double iou = static_cast<double>(both) / static_cast<double>(either);
        std::printf("far cards: distance %.0f m, pitch %.2f: IoU %.3f over %d pixels, %llu triangles\n",
                    static_cast<double>(v.distance), static_cast<double>(v.pitch), iou, either,
                    static_cast<unsigned long long>(farTriangles));
        EXPECT_GT(iou, v.minIou) << "far cards and capsules cover different pixels (distance " << v.distance << ", pitch " << v.pitch << ")";
    }
    // Default thresholds: a character 8 m back stays in cards, one 40 m back is far.
    o.lodPixels = -1;
    o.farPixels = -1;
    auto fast = Renderer::create(GpuEnvironment::device(), o);
    ASSERT_TRUE(fast.ok());
    const Character mid = posedCharacter({0.0f, 0.0f, -8.0f}, 0.0f);
    const Character distant = posedCharacter({0.0f, 0.0f, -40.0f}, 0.0f);
    FrameDescription f;
    f.camera = goldenCamera();
    f.camera.yaw = 0.0f;
    std::vector<CharacterInstance> v{instanceOf(mid, kRed)};
    f.characters = v;
    ASSERT_TRUE((*fast)->render(f).ok());
    EXPECT_EQ((*fast)->stats().triangles, 28u * 4u);
    v = {instanceOf(distant, kBlue)};
    f.characters = v;
    ASSERT_TRUE((*fast)->render(f).ok());
    EXPECT_LT((*fast)->stats().triangles, 28u * 4u);
    EXPECT_GT((*fast)->stats().triangles, 0u);
}

// Every overlay kind and a crowd: once warmed up (meshes built, buffers grown
// to the crowd, pipeline variants and the bitmap uploaded), frames whose poses
// and camera change allocate nothing, in both qualities.
TEST_F(RenderEngine, SteadyStateFramesDoNotAllocate) {
    // The validation layer allocates for its own bookkeeping on every call,
    // so this test measures on a device without it (lavapipe is C, and our
    // code must not allocate once warmed up).
    DeviceOptions o;
    o.preference = DevicePreference::Cpu;
    auto plain = VulkanDevice::create(o);
    ASSERT_TRUE(plain.ok()) << plain.error().message;

    // The duel with a label, a selection, a flash, a trajectory with
    // checkpoints (two labelled) and a painted floor.
    Duel d;
    d.instances[0].label = "jab";
    d.instances[1].selected = true;
    const std::vector<Flash> flashes{{glm::vec3(0.0f, 1.45f, 0.0f), 0.2f, {1.0f, 0.4f, 0.1f, 0.9f}}};
    std::vector<glm::vec3> path;
    for (int i = 0; i <= 24; ++i) path.emplace_back(-2.0f + 0.16f * static_cast<float>(i), 0.0f, 1.0f + 0.3f * std::sin(0.5f * i));
    const std::vector<Polyline> lines{{path, {1.0f, 0.75f, 0.15f, 0.95f}, 0.07f}, {{path.data(), 12}, {0.3f, 0.6f, 1.0f, 0.9f}, 0.05f}};
    const std::vector<Checkpoint> marks{{path.front(), {0.2f, 0.9f, 0.4f, 1.0f}, 0.3f, "start"},
                                        {path[12], {1.0f, 0.75f, 0.15f, 1.0f}, 0.25f, {}},
                                        {path.back(), {0.95f, 0.3f, 0.3f, 1.0f}, 0.3f, "end"}};
    Image paint;
    paint.resize(64, 32);
    std::fill(paint.rgba.begin(), paint.rgba.end(), std::uint8_t(180));
    const FloorBitmap bmp = floorBitmapOf(paint);

    // A crowd of 1,024 on a 32 x 32 grid in two sets of poses (frames
    // alternate between them, as when playing), every tenth labelled, one
    // selected, with the same trajectories, checkpoints and floor.
    std::array<std::vector<Character>, 2> poses;
    std::array<std::vector<CharacterInstance>, 2> crowd;
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < 1024; ++i) {
            const glm::vec3 at((static_cast<float>(i % 32) - 16.0f) * 1.2f, 0.0f, (static_cast<float>(i / 32) - 16.0f) * 1.2f);
            poses[static_cast<std::size_t>(k)].push_back(
                posedCharacter(at, static_cast<float>((i * 37 + k * 90) % 360), {{"RightArm", aboutAxis(k ? -40.0f : 20.0f, {0, 0, 1})}}));
        }
    for (int k = 0; k < 2; ++k) {
        const auto ku = static_cast<std::size_t>(k);
        for (std::size_t i = 0; i < poses[ku].size(); ++i) {
            crowd[ku].push_back(instanceOf(poses[ku][i], teamColor(static_cast<int>(i % 4))));
            if (i % 10 == 0) crowd[ku].back().label = i % 20 == 0 ? "jab" : "block";
        }
        crowd[ku][517].selected = true;
    }

    for (Quality q : {Quality::High, Quality::Fast}) {
        SCOPED_TRACE(q == Quality::High ? "High" : "Fast");
        RendererOptions ro;
        ro.width = kWidth;
        ro.height = kHeight;
        ro.quality = q;
        auto r = Renderer::create(*plain, ro);
        ASSERT_TRUE(r.ok()) << r.error().message;

        FrameDescription f = d.frame();
        f.flashes = flashes;
        f.trajectories = lines;
        f.checkpoints = marks;
        f.floorBitmap = &bmp;
        Image img;
        ASSERT_TRUE((*r)->render(f, &img).ok());  // warm up: meshes, buffers, image storage, bitmap
        ASSERT_TRUE((*r)->render(f, &img).ok());
        long before = allocationCount();
        for (int i = 0; i < 3; ++i) {
            f.camera.yaw += 0.1f;
            ASSERT_TRUE((*r)->render(f, &img).ok());
        }
        EXPECT_EQ(allocationCount() - before, 0) << "C++ allocations during steady-state frames of the duel";

        Bounds area;
        area.add(glm::vec3(-20.0f, 0.0f, -20.0f));
        area.add(glm::vec3(20.0f, 1.8f, 20.0f));
        f.camera.frame(area, static_cast<float>(kWidth) / static_cast<float>(kHeight));
        for (int k = 0; k < 2; ++k) {  // warm up: buffers grow to the crowd
            f.characters = crowd[static_cast<std::size_t>(k)];
            ASSERT_TRUE((*r)->render(f, &img).ok());
        }
        EXPECT_EQ((*r)->stats().characters, 1024);
        EXPECT_EQ((*r)->stats().culled, 0);
        const int growths = (*r)->stats().bufferGrowths;
        before = allocationCount();
        for (int i = 0; i < 4; ++i) {
            f.characters = crowd[static_cast<std::size_t>(i % 2)];
            f.camera.yaw += 0.02f;
            ASSERT_TRUE((*r)->render(f, &img).ok());
        }
        EXPECT_EQ(allocationCount() - before, 0) << "C++ allocations during steady-state frames of a crowd";
        EXPECT_EQ((*r)->stats().bufferGrowths, growths);
        EXPECT_GT((*r)->stats().overlayVertices, 103 * 3 * 6) << "the crowd's labels are drawn";
    }
}

TEST_F(RenderEngine, BadInputIsAnErrorAndTheRendererStaysUsable) {
    const Character c = posedCharacter({0.0f, 0.0f, 0.0f}, 0.0f);
    CharacterInstance bad = instanceOf(c, kRed);
    bad.jointPositions = bad.jointPositions.subspan(0, 5);
    std::vector<CharacterInstance> v{bad};
    FrameDescription f;
    f.camera = goldenCamera();
    f.characters = v;
    const Status s = renderer->render(f);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("character 0"), std::string::npos) << s.error().message;
    v[0].skeleton = nullptr;
    EXPECT_FALSE(renderer->render(f).ok());
    v[0] = instanceOf(c, kRed);
    EXPECT_TRUE(renderer->render(f).ok());
    EXPECT_FALSE(renderer->resize(0, 10).ok());
    ASSERT_TRUE(renderer->resize(128, 96).ok());
    Image img;
    ASSERT_TRUE(renderer->render(f, &img).ok());
    EXPECT_EQ(img.width, 128);
    EXPECT_EQ(img.height, 96);
    Image again;
    ASSERT_TRUE(renderer->readback(again).ok());
    EXPECT_EQ(again.rgba, img.rgba);
}

// The messenger really counts: a deliberately invalid call on a separate
// validated device is reported (so the zero counts above mean something).
TEST(RenderValidation, InvalidCallsAreCounted) {
    DeviceOptions o;
    o.validation = true;
    o.preference = DevicePreference::Cpu;
    auto d = VulkanDevice::create(o);
    ASSERT_TRUE(d.ok()) << d.error().message;
    (*d)->validationLog()->setEcho(false);
    VkBufferCreateInfo bci{};
    bci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    bci.size = 64;
    bci.usage = 0;  // invalid: at least one usage bit is required
    VkBuffer buffer = VK_NULL_HANDLE;
    const VkResult r = vkCreateBuffer((*d)->device(), &bci, nullptr, &buffer);
    if (r == VK_SUCCESS && buffer) vkDestroyBuffer((*d)->device(), buffer, nullptr);
    EXPECT_GT((*d)->validationLog()->errors(), 0);
}

// No Vulkan driver at all (the loader finds no ICD): the error says what to install.
TEST(RenderDevice, NoDriverGivesTheInstallMessage) {
    const char* old = std::getenv("VK_ICD_FILENAMES");
    const std::string saved = old ? old : "";
    setenv("VK_ICD_FILENAMES", "/nonexistent/fray_icd.json", 1);
    auto d = VulkanDevice::create(DeviceOptions{});
    if (old) setenv("VK_ICD_FILENAMES", saved.c_str(), 1);
    else unsetenv("VK_ICD_FILENAMES");
    ASSERT_FALSE(d.ok());
    EXPECT_EQ(d.error().message, "no Vulkan device found; install mesa-vulkan-drivers (lavapipe) or a GPU driver");
}

}  // namespace
}  // namespace fray::render::test

#if defined(__SANITIZE_ADDRESS__)
// LeakSanitizer's built-in suppressions for this binary: the same single
// entry as tests/render/lsan.supp (the validation layer's own leaks).
extern "C" const char* __lsan_default_suppressions() { return "leak:libVkLayer_khronos_validation.so\n"; }
#endif

int main(int argc, char** argv) {
    // Synchronisation validation as well as the core checks (read when the
    // instance is created; an explicit setting in the environment wins).
    setenv("VK_LAYER_ENABLES", "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT", 0);
#if defined(__SANITIZE_ADDRESS__)
    // The Vulkan loader unloads the driver and the layer with the last
    // instance; lavapipe's global state (in use until exit) would then lie in
    // unmapped memory and LeakSanitizer would report it from "<unknown module>".
    // Kept mapped, lavapipe's memory is reachable and the layer's own leaks
    // can be matched by name (see __lsan_default_suppressions below).
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE);
    dlopen("libVkLayer_khronos_validation.so", RTLD_NOW | RTLD_NODELETE);
#endif
    ::testing::InitGoogleTest(&argc, argv);
    ::testing::AddGlobalTestEnvironment(new fray::render::test::GpuEnvironment);
    return RUN_ALL_TESTS();
}
