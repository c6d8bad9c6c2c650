// CPU parts of the renderer: the body mesh built from a skeleton, the font,
// PNG round trips and the image comparison used by the golden tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include <glm/geometric.hpp>

#include "fray/core/atomic_file.h"
#include "fray/demo/demo_actor.h"
#include "fray/render/body_mesh.h"
#include "fray/render/font.h"
#include "fray/render/image.h"
#include "overlay_builder.h"

namespace fray::render {
namespace {

TEST(BodyMesh, EveryBoneOfTheDemoSkeletonGetsAClosedCapsule) {
    const Skeleton sk = demo::makeDemoSkeleton();
    const BodyMeshOptions opt{8, 2};
    const BodyMesh mesh = buildBodyMesh(sk, opt);
    // 23 parent-child bones plus 5 end sites (head, hands, toes).
    EXPECT_EQ(mesh.bones, 28);
    const std::size_t perCapsule = static_cast<std::size_t>(opt.sides * 2 * opt.capRings + 2);
    EXPECT_EQ(mesh.vertices.size(), perCapsule * 28);
    EXPECT_EQ(mesh.indices.size() % 3, 0u);
    // A closed surface of V vertices has 2V - 4 triangles per capsule (Euler).
    EXPECT_EQ(mesh.indices.size() / 3, (2 * perCapsule - 4) * 28);
    std::set<std::uint32_t> joints;
    for (const BodyVertex& v : mesh.vertices) {
        ASSERT_LT(v.joint, static_cast<std::uint32_t>(sk.jointCount()));
        EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
        joints.insert(v.joint);
    }
    for (std::uint32_t i : mesh.indices) ASSERT_LT(i, mesh.vertices.size());
    // Every joint with a child or an end site carries geometry.
    EXPECT_EQ(joints.size(), static_cast<std::size_t>(sk.jointCount()));
}

// The capsule list (which the renderer's cards use) is what the mesh is
// built from: one capsule per bone, each vertex within its capsule's radius
// of the segment, on the capsule's joint.
TEST(BodyMesh, TheMeshTessellatesTheCapsuleList) {
    const Skeleton sk = demo::makeDemoSkeleton();
    const std::vector<BodyCapsule> capsules = bodyCapsules(sk);
    const BodyMeshOptions opt{8, 2};
    const BodyMesh mesh = buildBodyMesh(sk, opt);
    ASSERT_EQ(capsules.size(), static_cast<std::size_t>(mesh.bones));
    const std::size_t perCapsule = mesh.vertices.size() / capsules.size();
    for (std::size_t c = 0; c < capsules.size(); ++c) {
        const BodyCapsule& cap = capsules[c];
        ASSERT_LT(cap.joint, static_cast<std::uint32_t>(sk.jointCount()));
        EXPECT_GT(cap.radius, 0.01f);
        const glm::vec3 ab = cap.b - cap.a;
        for (std::size_t k = c * perCapsule; k < (c + 1) * perCapsule; ++k) {
            const BodyVertex& v = mesh.vertices[k];
            ASSERT_EQ(v.joint, cap.joint);
            const float len2 = glm::dot(ab, ab);
            const float t = len2 > 0.0f ? std::clamp(glm::dot(v.position - cap.a, ab) / len2, 0.0f, 1.0f) : 0.0f;
            EXPECT_NEAR(glm::length(v.position - (cap.a + t * ab)), cap.radius, 1e-4f) << "capsule " << c;
        }
    }
}

TEST(BodyMesh, TrianglesFaceOutwards) {
    const BodyMesh mesh = buildBodyMesh(demo::makeDemoSkeleton());
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        const BodyVertex& a = mesh.vertices[mesh.indices[t]];
        const BodyVertex& b = mesh.vertices[mesh.indices[t + 1]];
        const BodyVertex& c = mesh.vertices[mesh.indices[t + 2]];
        const glm::vec3 n = glm::cross(b.position - a.position, c.position - a.position);
        ASSERT_GE(glm::dot(n, a.normal + b.normal + c.normal), 0.0f) << "triangle " << t / 3;
    }
}

TEST(BodyMesh, TorsoIsThickerThanForearmsAndScalesWithTheSkeleton) {
    const Skeleton sk = demo::makeDemoSkeleton();
    // Largest distance of joint j's vertices from its bone (j to its first child).
    auto radiusAt = [](const BodyMesh& m, const Skeleton& s, int joint) {
        const glm::vec3 b = s.offsets[static_cast<std::size_t>(s.children(joint).front())];
        float r = 0.0f;
        for (const BodyVertex& v : m.vertices) {
            if (v.joint != static_cast<std::uint32_t>(joint)) continue;
            const float t = std::clamp(glm::dot(v.position, b) / glm::dot(b, b), 0.0f, 1.0f);
            r = std::max(r, glm::length(v.position - t * b));
        }
        return r;
    };
    const BodyMesh mesh = buildBodyMesh(sk);
    EXPECT_GT(radiusAt(mesh, sk, sk.find("Spine")), 2.0f * radiusAt(mesh, sk, sk.find("LeftForeArm")));
    Skeleton child = sk;
    for (glm::vec3& o : child.offsets) o *= 0.6f;
    for (auto& e : child.endSites)
        if (e) *e *= 0.6f;
    const BodyMesh small = buildBodyMesh(child);
    EXPECT_LT(radiusAt(small, child, sk.find("Spine")), 0.8f * radiusAt(mesh, sk, sk.find("Spine")));
}

TEST(BodyMesh, FingerprintFollowsContentNotIdentity) {
    const Skeleton a = demo::makeDemoSkeleton();
    Skeleton b = a;
    EXPECT_EQ(skeletonFingerprint(a), skeletonFingerprint(b));
    b.offsets[3].y += 0.01f;
    EXPECT_NE(skeletonFingerprint(a), skeletonFingerprint(b));
    EXPECT_TRUE(buildBodyMesh(Skeleton{}).vertices.empty());
}

TEST(Font, PrintableAsciiHasGlyphsAndUnknownCharactersFallBack) {
    for (int c = 33; c <= 126; ++c) {
        int set = 0;
        for (int y = 0; y < font::kGlyphHeight; ++y)
            for (int x = 0; x < font::kGlyphWidth; ++x) set += font::glyphPixel(static_cast<char>(c), x, y);
        EXPECT_GT(set, 0) << "glyph '" << static_cast<char>(c) << "' is empty";
    }
    for (int y = 0; y < font::kGlyphHeight; ++y)
        for (int x = 0; x < font::kGlyphWidth; ++x) {
            EXPECT_FALSE(font::glyphPixel(' ', x, y));
            EXPECT_EQ(font::glyphPixel('\x01', x, y), font::glyphPixel('?', x, y));
        }
    EXPECT_EQ(font::textWidth("jab", 2), (3 * 6 - 1) * 2);
    const auto atlas = font::buildAtlas();
    EXPECT_EQ(atlas.size(), static_cast<std::size_t>(font::kAtlasWidth * font::kAtlasHeight));
}

TEST(Image, PngRoundTripIsExact) {
    Image img;
    img.resize(37, 11);
    for (std::size_t i = 0; i < img.rgba.size(); ++i) img.rgba[i] = static_cast<std::uint8_t>(i * 7 + 3);
    const auto path = std::filesystem::path(testing::TempDir()) / "fray_png_roundtrip.png";
    ASSERT_TRUE(writePng(path, img).ok());
    auto back = readPng(path);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->width, 37);
    EXPECT_EQ(back->height, 11);
    EXPECT_EQ(back->rgba, img.rgba);
    std::filesystem::remove(path);
}

TEST(Image, ReadErrorsNameTheFile) {
    const auto missing = readPng("/nonexistent/fray.png");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("/nonexistent/fray.png"), std::string::npos);
    const auto path = std::filesystem::path(testing::TempDir()) / "fray_not_a_png.png";
    ASSERT_TRUE(writeFileAtomically(path, "hello, not a png").ok());
    const auto bad = readPng(path);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("not a PNG"), std::string::npos);
    // A truncated PNG: the first half of a valid one.
    Image img;
    img.resize(64, 64);
    std::fill(img.rgba.begin(), img.rgba.end(), std::uint8_t(128));
    ASSERT_TRUE(writePng(path, img).ok());
    auto bytes = readWholeFile(path);
    ASSERT_TRUE(bytes.ok());
    ASSERT_TRUE(writeFileAtomically(path, bytes->substr(0, bytes->size() / 2)).ok());
    const auto cut = readPng(path);
    ASSERT_FALSE(cut.ok());
    EXPECT_NE(cut.error().message.find("bad PNG"), std::string::npos);
    std::filesystem::remove(path);
}

TEST(Image, CompareCountsPixelsBeyondTheThresholdAndBoxesThem) {
    Image a, b;
    a.resize(10, 8);
    std::fill(a.rgba.begin(), a.rgba.end(), std::uint8_t(100));
    b = a;
    b.pixel(2, 3)[1] = 108;  // within 8 levels
    b.pixel(7, 5)[0] = 109;  // beyond
    b.pixel(4, 1)[2] = 50;   // beyond
    const ImageDiff d = compareImages(a, b, 8);
    EXPECT_EQ(d.differing, 2);
    EXPECT_EQ(d.maxDelta, 50);
    EXPECT_EQ(d.minX, 4);
    EXPECT_EQ(d.minY, 1);
    EXPECT_EQ(d.maxX, 7);
    EXPECT_EQ(d.maxY, 5);
    Image c;
    c.resize(10, 9);
    EXPECT_TRUE(compareImages(a, c, 8).sizeMismatch);
    EXPECT_EQ(imageStats(a).distinctColors, 1);
    EXPECT_EQ(imageStats(a).lumaStdDev, 0.0);
}

}  // namespace
}  // namespace fray::render

// Labels of characters standing close together are stacked instead of
// printed over each other: the selected one keeps its place, a label that
// covers none stays, the others move up above what they would cover.
TEST(Overlay, CloseLabelsAreStackedNotOverlapped) {
    using fray::render::PendingLabel;
    auto make = [](float x, float y, bool selected, int index) {
        PendingLabel l;
        l.x = x, l.y = l.anchorY = y, l.halfWidth = 60, l.height = 20, l.selected = selected, l.index = index;
        return l;
    };
    std::vector<PendingLabel> labels{make(100, 200, false, 0), make(110, 205, false, 1), make(130, 195, true, 2),
                                     make(500, 200, false, 3)};
    fray::render::stackLabels(labels);
    auto find = [&](int index) {
        return *std::find_if(labels.begin(), labels.end(), [&](const PendingLabel& l) { return l.index == index; });
    };
    EXPECT_EQ(find(2).y, 195.0f);  // selected: unmoved
    EXPECT_EQ(find(3).y, 200.0f);  // far from the others: unmoved
    EXPECT_LT(find(0).y, 195.0f - 20.0f);
    EXPECT_LT(find(1).y, 195.0f - 20.0f);
    for (std::size_t i = 0; i < labels.size(); ++i)
        for (std::size_t k = i + 1; k < labels.size(); ++k) {
            const PendingLabel& a = labels[i];
            const PendingLabel& b = labels[k];
            const bool apart = std::abs(a.x - b.x) >= a.halfWidth + b.halfWidth || a.y <= b.y - b.height || b.y <= a.y - a.height;
            EXPECT_TRUE(apart) << a.index << " covers " << b.index;
        }
    // The same input in another order gives the same places.
    std::vector<PendingLabel> again{make(500, 200, false, 3), make(130, 195, true, 2), make(110, 205, false, 1),
                                    make(100, 200, false, 0)};
    fray::render::stackLabels(again);
    for (const PendingLabel& l : labels) {
        const auto it = std::find_if(again.begin(), again.end(), [&](const PendingLabel& o) { return o.index == l.index; });
        EXPECT_EQ(it->y, l.y) << l.index;
    }
}

// A crowd's blob shadows are written in parallel (one slot per character):
// the same vertices, in the same order, as building each character's shadow
// on its own, whether the renderer passes its culling bounds or not.
TEST(Overlay, CrowdBlobShadowsMatchOneByOne) {
    using namespace fray::render;
    const fray::Skeleton sk = fray::demo::makeDemoSkeleton();
    const auto jc = static_cast<std::size_t>(sk.jointCount());
    std::vector<std::vector<glm::vec3>> joints(6000, std::vector<glm::vec3>(jc));
    std::vector<glm::quat> rotations(jc, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
    std::vector<CharacterInstance> crowd(joints.size());
    std::vector<Bounds> bounds(joints.size());
    for (std::size_t i = 0; i < joints.size(); ++i) {
        for (std::size_t j = 0; j < jc; ++j)
            joints[i][j] = glm::vec3(static_cast<float>(i % 80) * 1.3f + 0.01f * static_cast<float>(j),
                                     0.05f * static_cast<float>(j) + 0.001f * static_cast<float>(i % 7),
                                     static_cast<float>(i / 80) * 1.3f - 0.02f * static_cast<float>(j % 5));
        crowd[i].skeleton = &sk;
        crowd[i].jointPositions = joints[i];
        crowd[i].jointRotations = rotations;
        for (const glm::vec3& p : joints[i]) bounds[i].add(p);
    }
    FrameDescription f;
    f.characters = crowd;
    f.settings.labels = false;
    const glm::mat4 vp = f.camera.viewProjection(16.0f / 9.0f);
    OverlayBuilder all, withBounds, one;
    buildOverlays(f, vp, {1280.0f, 720.0f}, true, all);
    buildOverlays(f, vp, {1280.0f, 720.0f}, true, withBounds, bounds);
    const auto& a = all.group(OverlayGroup::Depth);
    const auto& b = withBounds.group(OverlayGroup::Depth);
    ASSERT_EQ(a.size(), 6 * crowd.size());
    ASSERT_EQ(b.size(), a.size());
    for (std::size_t i = 0; i < crowd.size(); i += 37) {
        FrameDescription single;
        single.characters = std::span<const CharacterInstance>(&crowd[i], 1);
        single.settings.labels = false;
        buildOverlays(single, vp, {1280.0f, 720.0f}, true, one);
        const auto& s = one.group(OverlayGroup::Depth);
        ASSERT_EQ(s.size(), 6u);
        for (std::size_t k = 0; k < 6; ++k) {
            const OverlayVertex& x = a[6 * i + k];
            const OverlayVertex& y = b[6 * i + k];
            EXPECT_EQ(x.position, s[k].position) << "character " << i << " vertex " << k;
            EXPECT_EQ(x.uv, s[k].uv);
            EXPECT_EQ(x.color, s[k].color);
            EXPECT_EQ(x.mode, s[k].mode);
            EXPECT_EQ(y.position, x.position);
            EXPECT_EQ(y.color, x.color);
        }
    }
}
