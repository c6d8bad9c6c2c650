#pragma once
// Shared by the GPU tests: one lavapipe device per test process with the
// Khronos validation layer on (any warning or error fails the test), poses of
// the demo skeleton, and golden-image comparison.
//
// Golden images live in tests/render/golden/. To regenerate them after an
// intended change of the picture, run the tests with FRAY_UPDATE_GOLDENS=1
// (e.g. `FRAY_UPDATE_GOLDENS=1 ctest --test-dir build -R render`), look at
// the new PNGs, and commit them. A failing comparison writes the rendered
// image and a difference image next to the test binary (golden-out/).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "fray/core/kinematics.h"
#include "fray/demo/demo_actor.h"
#include "fray/render/image.h"
#include "fray/render/renderer.h"

namespace fray::render::test {

inline constexpr int kWidth = 256;
inline constexpr int kHeight = 192;

// The device and its validation log for the whole test process.
class GpuEnvironment : public ::testing::Environment {
public:
    static std::shared_ptr<VulkanDevice>& device() {
        static std::shared_ptr<VulkanDevice> d;
        return d;
    }
    static std::shared_ptr<ValidationLog>& log() {
        static std::shared_ptr<ValidationLog> l;
        return l;
    }
    static std::string& error() {
        static std::string e;
        return e;
    }

    void SetUp() override {
        DeviceOptions o;
        o.applicationName = "fray render tests";
        o.validation = true;
        o.preference = DevicePreference::Cpu;  // goldens are lavapipe pictures
        auto d = VulkanDevice::create(o);
        if (!d) {
            error() = d.error().message;
            return;
        }
        device() = *d;
        log() = device()->validationLog();
    }

    // Destroying the device reports leaked objects through the validation
    // layer, so the count is checked after it is gone.
    void TearDown() override {
        device().reset();
        if (log()) {
            EXPECT_EQ(log()->errors(), 0) << "Vulkan validation errors at device teardown";
            EXPECT_EQ(log()->warnings(), 0) << "Vulkan validation warnings at device teardown";
        }
    }
};

class GpuTest : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_TRUE(GpuEnvironment::device()) << GpuEnvironment::error();
        RendererOptions o;
        o.width = kWidth;
        o.height = kHeight;
        o.quality = Quality::High;
        o.shadowMapSize = 1024;
        auto r = Renderer::create(GpuEnvironment::device(), o);
        ASSERT_TRUE(r.ok()) << r.error().message;
        renderer = std::move(*r);
    }
    void TearDown() override {
        renderer.reset();
        if (auto log = GpuEnvironment::log()) {
            EXPECT_EQ(log->errors(), 0) << "Vulkan validation errors (printed above)";
            EXPECT_EQ(log->warnings(), 0) << "Vulkan validation warnings (printed above)";
        }
    }

    Image renderImage(const FrameDescription& frame) {
        Image img;
        const Status s = renderer->render(frame, &img);
        EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
        return img;
    }

    std::unique_ptr<Renderer> renderer;
};

// A posed demo character: world joint transforms computed by FK from the
// rest pose, with some local rotations replaced, standing on the floor at
// `at`, turned by yaw about +Y (0 faces +Z, towards the default camera).
struct Character {
    std::vector<glm::vec3> positions;
    std::vector<glm::quat> rotations;
};

inline const Skeleton& demoSkeleton() {
    static const Skeleton sk = demo::makeDemoSkeleton();
    return sk;
}

inline glm::quat aboutAxis(float degrees, glm::vec3 axis) { return glm::angleAxis(glm::radians(degrees), axis); }

using JointRotations = std::initializer_list<std::pair<const char*, glm::quat>>;

// Arms down by 70 degrees from the T-pose, plus the given rotations.
inline Character posedCharacter(glm::vec3 at, float yawDegrees, JointRotations extra = {}) {
    const Skeleton& sk = demoSkeleton();
    const auto n = static_cast<std::size_t>(sk.jointCount());
    std::vector<glm::vec3> t(sk.offsets.begin(), sk.offsets.end());
    std::vector<glm::quat> r(n, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
    auto set = [&](const char* name, glm::quat q) {
        const int j = sk.find(name);
        EXPECT_GE(j, 0) << name;
        if (j >= 0) r[static_cast<std::size_t>(j)] = q;
    };
    set("LeftArm", aboutAxis(-70.0f, {0, 0, 1}));
    set("RightArm", aboutAxis(70.0f, {0, 0, 1}));
    for (const auto& [name, q] : extra) set(name, q);
    // Feet on the floor: lift the root by the rest pose's lowest joint.
    Character c;
    c.positions.resize(n);
    c.rotations.resize(n);
    forwardKinematics(sk, t, std::vector<glm::quat>(n, glm::quat(1, 0, 0, 0)), c.positions, c.rotations);
    float lowest = 0.0f;
    for (const glm::vec3& p : c.positions) lowest = std::min(lowest, p.y);
    t[0] = at + glm::vec3(0.0f, -lowest + 0.04f, 0.0f);
    r[0] = aboutAxis(yawDegrees, {0, 1, 0}) * r[0];
    forwardKinematics(sk, t, r, c.positions, c.rotations);
    return c;
}

inline CharacterInstance instanceOf(const Character& c, glm::vec3 tint) {
    CharacterInstance i;
    i.skeleton = &demoSkeleton();
    i.jointPositions = c.positions;
    i.jointRotations = c.rotations;
    i.tint = tint;
    return i;
}

// Pixels that differ between two renderings of one character, inside and
// outside the screen box of its right arm (shoulder to fingertip, both poses,
// grown by `radius` metres and 2 pixels).
struct ArmChange {
    int inside = 0, outside = 0;
    std::string box;  // for messages
};
inline ArmChange armChange(const FrameDescription& f, const Character& a, const Character& b, const Image& imgA, const Image& imgB,
                           float radius = 0.07f) {
    const glm::mat4 vp = f.camera.viewProjection(static_cast<float>(imgA.width) / static_cast<float>(imgA.height));
    const glm::vec2 size(imgA.width, imgA.height);
    auto pixel = [&](glm::vec3 p) { return projectToPixel(vp, p, size).value_or(glm::vec3(0.0f)); };
    float minX = 1e9f, minY = 1e9f, maxX = -1e9f, maxY = -1e9f;
    for (const Character* c : {&a, &b})
        for (const char* name : {"RightArm", "RightForeArm", "RightHand", "RightHandIndex1"}) {
            const auto j = static_cast<std::size_t>(demoSkeleton().find(name));
            for (glm::vec3 p : {c->positions[j], c->positions[j] + c->rotations[j] * glm::vec3(-0.03f, 0.0f, 0.0f)}) {
                const glm::vec3 px = pixel(p);
                minX = std::min(minX, px.x);
                minY = std::min(minY, px.y);
                maxX = std::max(maxX, px.x);
                maxY = std::max(maxY, px.y);
            }
        }
    const float metre = std::abs(pixel({1.0f, 1.0f, 0.0f}).x - pixel({0.0f, 1.0f, 0.0f}).x);
    const float margin = radius * metre + 2.0f;
    ArmChange out;
    for (int y = 0; y < imgA.height; ++y)
        for (int x = 0; x < imgA.width; ++x) {
            const std::uint8_t* p = imgA.pixel(x, y);
            const std::uint8_t* q = imgB.pixel(x, y);
            bool differs = false;
            for (int k = 0; k < 3; ++k) differs = differs || std::abs(int(p[k]) - int(q[k])) > 8;
            if (!differs) continue;
            const bool in = static_cast<float>(x) >= minX - margin && static_cast<float>(x) <= maxX + margin &&
                            static_cast<float>(y) >= minY - margin && static_cast<float>(y) <= maxY + margin;
            (in ? out.inside : out.outside)++;
        }
    out.box = std::to_string(minX) + "," + std::to_string(minY) + " - " + std::to_string(maxX) + "," + std::to_string(maxY) +
              " +- " + std::to_string(margin);
    return out;
}

// A fixed three-quarter view of the area around the origin.
// `paint` laid on the floor from x -2 to 2 and z 0.4 to 2.4, in front of the
// golden camera (it must outlive the frames that use it).
inline FloorBitmap floorBitmapOf(const Image& paint) {
    FloorBitmap bmp;
    bmp.rgba = paint.rgba.data();
    bmp.width = paint.width;
    bmp.height = paint.height;
    bmp.min = {-2.0f, 0.4f};
    bmp.max = {2.0f, 2.4f};
    return bmp;
}

inline OrbitCamera goldenCamera() {
    OrbitCamera cam;
    cam.target = glm::vec3(0.0f, 0.9f, 0.0f);
    cam.yaw = 0.45f;
    cam.pitch = 0.32f;
    cam.distance = 5.2f;
    return cam;
}

inline std::filesystem::path goldenDir() { return FRAY_GOLDEN_DIR; }
inline std::filesystem::path goldenOutDir() { return FRAY_GOLDEN_OUT_DIR; }

// <= 1 % of the pixels may differ by more than 8 levels in some channel.
inline void expectMatchesGolden(const Image& image, const std::string& name) {
    const auto golden = goldenDir() / (name + ".png");
    const char* update = std::getenv("FRAY_UPDATE_GOLDENS");
    if (update && std::string(update) == "1") {
        ASSERT_TRUE(writePng(golden, image).ok());
        std::printf("updated %s\n", golden.string().c_str());
        return;
    }
    auto ref = readPng(golden);
    ASSERT_TRUE(ref.ok()) << ref.error().message << " (regenerate with FRAY_UPDATE_GOLDENS=1)";
    const ImageDiff d = compareImages(image, *ref, 8);
    if (d.sizeMismatch || d.fraction() > 0.01) {
        std::filesystem::create_directories(goldenOutDir());
        const auto actual = goldenOutDir() / (name + ".actual.png");
        const auto diff = goldenOutDir() / (name + ".diff.png");
        (void)writePng(actual, image);
        (void)writePng(diff, diffImage(image, *ref, 8));
        ADD_FAILURE() << name << ": " << d.differing << " of " << d.total << " pixels (" << 100.0 * d.fraction()
                      << " %) differ by more than 8 levels (max " << d.maxDelta << "); rendered: " << actual
                      << ", difference: " << diff;
    }
}

}  // namespace fray::render::test
