#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

#include "fray/core/kinematics.h"
#include "fray/core/normalize.h"
#include "fray/core/rotation.h"
#include "fray/io/bvh.h"
#include "test_util.h"

using namespace fray;
using fray::test::testData;

namespace {

std::string slurp(const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// Angle in radians of the rotation taking a to b (sign-insensitive, in double
// so float rounding of 1 - |dot| does not hide real differences).
float quatDistance(const glm::quat& a, const glm::quat& b) {
    const glm::dquat d = glm::inverse(glm::dquat(a)) * glm::dquat(b);
    return static_cast<float>(2.0 * std::atan2(glm::length(glm::dvec3(d.x, d.y, d.z)), std::abs(d.w)));
}

// Largest difference between two motions' local data (translations in file
// units, rotations as 1 - |dot|) and world positions.
struct Diff {
    float translation = 0, rotation = 0, world = 0;
};
Diff compare(const Motion& a, const Motion& b) {
    Diff d;
    EXPECT_EQ(a.frameCount(), b.frameCount());
    EXPECT_EQ(a.jointCount(), b.jointCount());
    if (a.frameCount() != b.frameCount() || a.jointCount() != b.jointCount()) return {1e9f, 1e9f, 1e9f};
    const auto& ta = a.allTranslations();
    const auto& tb = b.allTranslations();
    for (std::size_t i = 0; i < ta.size(); ++i) d.translation = std::max(d.translation, glm::length(ta[i] - tb[i]));
    const auto& ra = a.allRotations();
    const auto& rb = b.allRotations();
    for (std::size_t i = 0; i < ra.size(); ++i) d.rotation = std::max(d.rotation, quatDistance(ra[i], rb[i]));
    const auto wa = worldPositions(a, 0, a.frameCount() - 1);
    const auto wb = worldPositions(b, 0, b.frameCount() - 1);
    for (std::size_t i = 0; i < wa.size(); ++i) d.world = std::max(d.world, glm::length(wa[i] - wb[i]));
    return d;
}

}  // namespace

TEST(Bvh, ReadsTinyFileExactly) {
    auto m = readBvh(testData() / "bvh_valid/tiny.bvh");
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->jointCount(), 3);
    EXPECT_EQ(m->frameCount(), 3);
    EXPECT_NEAR(m->fps(), 30.0, 1e-3);
    EXPECT_EQ(m->skeleton().channelCount(), 12);
    EXPECT_EQ(m->skeleton().rotationOrders[0], RotationOrder::ZXY);
    ASSERT_TRUE(m->skeleton().endSites[1].has_value());
    EXPECT_FLOAT_EQ(m->skeleton().endSites[1]->y, 10.0f);
    // Frame 2: root at (2, 90, 0) turned 10 degrees about Z; Spine 10 up along the turned Y.
    std::vector<glm::vec3> p(3);
    worldPositions(*m, 2, p);
    const float a = glm::radians(10.0f);
    EXPECT_NEAR(p[0].x, 2.0f, 1e-5f);
    EXPECT_NEAR(p[1].x, 2.0f - 10.0f * std::sin(a), 1e-4f);
    EXPECT_NEAR(p[1].y, 90.0f + 10.0f * std::cos(a), 1e-4f);
}

TEST(Bvh, ToleratesCrlfTabsAndOddWhitespace) {
    const std::string base = slurp(testData() / "bvh_valid/tiny.bvh");
    auto ref = readBvhFromMemory(base, "tiny.bvh");
    ASSERT_TRUE(ref.ok());
    std::vector<std::string> variants;
    std::string crlf;
    for (char c : base) {
        if (c == '\n') crlf += "\r\n";
        else crlf += c;
    }
    variants.push_back(crlf);
    std::string spaced;
    for (char c : base) {
        if (c == ' ') spaced += " \t  ";
        else if (c == '\t') spaced += "   ";
        else spaced += c;
    }
    variants.push_back(spaced);
    std::string glued = base;
    glued.replace(glued.find("Frames: 3"), 9, "Frames:3");
    glued.replace(glued.find("ROOT Hips\n{"), 11, "ROOT Hips {");
    variants.push_back(glued);
    variants.push_back(base.substr(0, base.size() - 1));  // no final newline
    variants.push_back("\n\n" + base + "\n\n\n");
    for (const auto& v : variants) {
        auto m = readBvhFromMemory(v, "variant.bvh");
        ASSERT_TRUE(m.ok()) << m.error().message;
        const Diff d = compare(*ref, *m);
        EXPECT_EQ(d.translation, 0.0f);
        EXPECT_LT(d.rotation, 1e-7f);
    }
}

TEST(Bvh, EveryRotationOrderAndChannelLayoutRoundTrips) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-170.0f, 170.0f);
    const std::vector<std::vector<Channel>> layouts = {
        {Channel::Xrotation, Channel::Yrotation, Channel::Zrotation}, {Channel::Xrotation, Channel::Zrotation, Channel::Yrotation},
        {Channel::Yrotation, Channel::Xrotation, Channel::Zrotation}, {Channel::Yrotation, Channel::Zrotation, Channel::Xrotation},
        {Channel::Zrotation, Channel::Xrotation, Channel::Yrotation}, {Channel::Zrotation, Channel::Yrotation, Channel::Xrotation},
        {Channel::Xposition, Channel::Yposition, Channel::Zposition, Channel::Yrotation, Channel::Xrotation, Channel::Zrotation},
        {Channel::Zrotation, Channel::Xposition, Channel::Yrotation, Channel::Yposition, Channel::Xrotation, Channel::Zposition},
    };
    Skeleton sk;
    sk.addJoint("root", -1, {0, 0, 0},
                {Channel::Xposition, Channel::Yposition, Channel::Zposition, Channel::Zrotation, Channel::Xrotation, Channel::Yrotation},
                RotationOrder::ZXY);
    for (std::size_t i = 0; i < layouts.size(); ++i)
        sk.addJoint("j" + std::to_string(i), static_cast<int>(i), {0.1f, 1.0f, 0.2f}, layouts[i], rotationOrderFromChannels(layouts[i]));
    sk.addJoint("leaf", static_cast<int>(layouts.size()), {0, 0.5f, 0}, {}, RotationOrder::ZXY);
    Motion m(sk, 60.0, 0);
    std::vector<glm::vec3> t(static_cast<std::size_t>(sk.jointCount()));
    std::vector<glm::quat> r(t.size());
    for (int f = 0; f < 50; ++f) {
        for (std::size_t j = 0; j < t.size(); ++j) {
            t[j] = sk.offsets[j];
            if (sk.hasPositionChannels(static_cast<int>(j))) t[j] = {u(rng) * 0.01f, u(rng) * 0.01f, u(rng) * 0.01f};
            r[j] = sk.channels[j].empty() ? glm::quat(1, 0, 0, 0)
                                          : eulerToQuat({u(rng), u(rng) * 0.5f, u(rng)}, sk.rotationOrders[j]);
        }
        m.appendFrame(t, r);
    }
    const std::string text = writeBvhToString(m);
    auto back = readBvhFromMemory(text, "orders.bvh");
    ASSERT_TRUE(back.ok()) << back.error().message;
    const Diff d = compare(m, *back);
    EXPECT_LT(d.translation, 1e-5f);
    EXPECT_LT(d.rotation, 1e-6f);
    EXPECT_LT(d.world, 1e-5f);
    EXPECT_EQ(back->skeleton().channels, sk.channels);
}

TEST(Bvh, SharedFilesRoundTripWithin1e5) {
    const auto files = fray::test::sharedBvhFiles();
    ASSERT_GE(files.size(), 49u);
    for (const auto& f : files) {
        auto m = readBvh(f);
        ASSERT_TRUE(m.ok()) << m.error().message;
        const std::string text = writeBvhToString(*m);
        auto back = readBvhFromMemory(text, f.filename().string());
        ASSERT_TRUE(back.ok()) << back.error().message;
        const Diff d = compare(*m, *back);
        // File units (cm or inches): 1e-5 of a unit is tighter than 1e-5 m.
        EXPECT_LT(d.translation, 1e-5f) << f;
        EXPECT_LT(d.rotation, 1e-6f) << f;  // radians
        // World positions in metres (file units x detected unit scale).
        const double metres = guessUnits(*m).scale;
        EXPECT_LT(static_cast<double>(d.world) * metres, 1e-5) << f;
        EXPECT_EQ(back->skeleton().names, m->skeleton().names);
        EXPECT_EQ(back->skeleton().channels, m->skeleton().channels);
        EXPECT_NEAR(back->fps(), m->fps(), 1e-9) << f;
    }
}

TEST(Bvh, WriteIsAtomicAndRereads) {
    auto m = readBvh(testData() / "bvh_valid/tiny.bvh");
    ASSERT_TRUE(m.ok());
    const auto out = std::filesystem::temp_directory_path() / "fray_test_write.bvh";
    ASSERT_TRUE(writeBvh(*m, out).ok());
    EXPECT_FALSE(std::filesystem::exists(out.string() + ".tmp"));
    auto back = readBvh(out);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_LT(compare(*m, *back).world, 1e-5f);
    std::filesystem::remove(out);
    // An unwritable destination is an error value, not a crash.
    EXPECT_FALSE(writeBvh(*m, "/nonexistent-dir/x.bvh").ok());
}

TEST(Bvh, MalformedCorpusGivesSpecificErrors) {
    const auto dir = testData() / "bvh_malformed";
    std::ifstream manifest(dir / "EXPECTED.tsv");
    ASSERT_TRUE(manifest.good());
    std::string line;
    int cases = 0;
    while (std::getline(manifest, line)) {
        if (line.empty() || line[0] == '#') continue;
        const auto tab = line.find('\t');
        ASSERT_NE(tab, std::string::npos) << line;
        const std::string file = line.substr(0, tab), expected = line.substr(tab + 1);
        auto m = readBvh(dir / file);
        ASSERT_FALSE(m.ok()) << file << " should fail";
        const std::string& msg = m.error().message;
        EXPECT_EQ(msg.rfind(file + ":", 0), 0u) << "message must start with the file name: " << msg;
        EXPECT_NE(msg.find(expected), std::string::npos) << file << ": got '" << msg << "', want '" << expected << "'";
        // The in-memory path gives the same message.
        auto mem = readBvhFromMemory(slurp(dir / file), file);
        ASSERT_FALSE(mem.ok());
        EXPECT_EQ(mem.error().message, msg);
        ++cases;
    }
    EXPECT_GE(cases, 25);
}

TEST(Bvh, MemoryCapRefusesBeforeAllocating) {
    BvhReadOptions opt;
    opt.maxMotionBytes = 100;  // three joints x three frames x 28 bytes = 252 bytes
    auto m = readBvh(testData() / "bvh_valid/tiny.bvh", opt);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().message.find("over the limit"), std::string::npos) << m.error().message;
    opt = {};
    opt.maxJoints = 2;
    m = readBvh(testData() / "bvh_valid/tiny.bvh", opt);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().message.find("more than 2 joints"), std::string::npos) << m.error().message;
}

TEST(Bvh, MissingFileAndDirectoryAreErrors) {
    auto m = readBvh("/nonexistent/file.bvh");
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().message.find("cannot open"), std::string::npos);
    m = readBvh(testData());
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().message.find("directory"), std::string::npos);
}

TEST(Bvh, WorldPositionChannelsOfInnerJointsAreIgnoredWithWarning) {
    // CMU-135 conversion: 'thorax' and 'head' carry world positions in their position channels.
    auto m = readBvh(fray::test::sharedMocap() / "cmu135_karate/motorcycle.bvh");
    ASSERT_TRUE(m.ok()) << m.error().message;
    ASSERT_EQ(m->source().warnings.size(), 2u);
    EXPECT_NE(m->source().warnings[0].find("thorax"), std::string::npos);
    const int thorax = m->skeleton().find("thorax");
    EXPECT_EQ(m->translations(10)[static_cast<std::size_t>(thorax)], m->skeleton().offsets[static_cast<std::size_t>(thorax)]);
    // Bandai's moving Hips (child of a static root) keeps its channels.
    auto b = readBvh(fray::test::sharedMocap() / "bandai/dataset-1_walk_normal_001.bvh");
    ASSERT_TRUE(b.ok());
    EXPECT_TRUE(b->source().warnings.empty());
    const auto hips = static_cast<std::size_t>(b->skeleton().find("Hips"));
    EXPECT_GT(glm::length(b->translations(b->frameCount() - 1)[hips] - b->translations(0)[hips]), 50.0f);
}
