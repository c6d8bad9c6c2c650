// Retargeting (fray/core/retarget.h) on the real captures of three sources
// (CMU karate, LAFAN1, Bandai): every pair, foot skate on contacts, bone
// directions kept; bad skeletons as clear errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "fray/core/kinematics.h"
#include "fray/core/retarget.h"
#include "fray/io/import.h"
#include "test_util.h"

namespace fray::test {
namespace {

struct Take {
    const char* file;
    int first, last;  // frames kept
};
// Short pieces of one take per source (each a few seconds, stepping included).
constexpr Take kTakes[] = {{"cmu135_karate/oiduki001.bvh", 200, 800},
                           {"lafan1/walk4_subject1.bvh", 100, 400},
                           {"bandai/dataset-1_walk_normal_001.bvh", 0, 194}};

Motion loadTake(const Take& t) {
    auto m = loadMotion(sharedMocap() / t.file);
    EXPECT_TRUE(m) << (m ? "" : m.error().message);
    if (!m) return {};
    auto cut = trim(*m, t.first, std::min(t.last, m->frameCount() - 1));
    EXPECT_TRUE(cut);
    return cut ? std::move(*cut) : Motion{};
}

// Angle (degrees) between the source's and the target's upper-arm and
// forearm directions, worst over the take (legs are left out: the foot IK
// bends them where the proportions differ).
double worstLimbAngle(const Motion& src, const Motion& dst) {
    const StandardJoints a = guessStandardJoints(src.skeleton()), b = guessStandardJoints(dst.skeleton());
    std::vector<glm::vec3> pa(static_cast<std::size_t>(src.jointCount())), pb(static_cast<std::size_t>(dst.jointCount()));
    double worst = 0.0;
    auto dir = [](const std::vector<glm::vec3>& p, int from, int to) {
        return glm::normalize(p[static_cast<std::size_t>(to)] - p[static_cast<std::size_t>(from)]);
    };
    for (int f = 0; f < src.frameCount(); f += 7) {
        worldPositions(src, f, pa);
        worldPositions(dst, f, pb);
        const std::pair<int, int> limbsA[] = {{a.leftShoulder, a.leftElbow}, {a.rightElbow, a.rightHand}, {a.rightShoulder, a.rightElbow}};
        const std::pair<int, int> limbsB[] = {{b.leftShoulder, b.leftElbow}, {b.rightElbow, b.rightHand}, {b.rightShoulder, b.rightElbow}};
        for (std::size_t k = 0; k < 3; ++k) {
            const float c = glm::dot(dir(pa, limbsA[k].first, limbsA[k].second), dir(pb, limbsB[k].first, limbsB[k].second));
            worst = std::max(worst, std::acos(std::clamp(static_cast<double>(c), -1.0, 1.0)) * 180.0 / M_PI);
        }
    }
    return worst;
}

TEST(Retarget, EveryPairOfSourcesKeepsFeetPlantedAndLimbsAligned) {
    if (!requireSharedMocap()) return;
    std::vector<Motion> takes;
    for (const Take& t : kTakes) takes.push_back(loadTake(t));
    for (std::size_t s = 0; s < takes.size(); ++s) {
        for (std::size_t t = 0; t < takes.size(); ++t) {
            if (s == t) continue;
            const RetargetTarget target = retargetTargetFromMotion(takes[t], 0, kTakes[t].file);
            RetargetReport report;
            const StandardJoints ssj = guessStandardJoints(takes[s].skeleton());
            const FootContactTrack contacts = detectFootContacts(takes[s], ssj);
            RetargetOptions options;
            options.contacts = &contacts;
            auto out = retarget(takes[s], target, options, &report);
            ASSERT_TRUE(out) << out.error().message;
            EXPECT_EQ(out->frameCount(), takes[s].frameCount());
            EXPECT_TRUE(sameSkeleton(out->skeleton(), takes[t].skeleton()));
            const FootSkate before = measureFootSkate(takes[s], ssj, contacts);
            const FootSkate after = measureFootSkate(*out, guessStandardJoints(out->skeleton()), contacts);
            // Measured again with contacts found on the result itself.
            const StandardJoints tsj = guessStandardJoints(out->skeleton());
            const FootSkate own = measureFootSkate(*out, tsj, detectFootContacts(*out, tsj));
            const double angle = worstLimbAngle(takes[s], *out);
            std::printf("%s -> %s: scale %.3f, %zu mapped, skate %.2f cm (source %.2f cm) max %.2f cm over %d, "
                        "planted %d unreached %d, worst limb angle %.2f deg, skate on its own contacts %.2f cm over %d\n",
                        kTakes[s].file, kTakes[t].file, report.scale, report.mapped.size(), after.mean * 100, before.mean * 100,
                        after.max * 100, after.frames, report.plantedFrames, report.unreachedFrames, angle, own.mean * 100, own.frames);
            EXPECT_GT(own.frames, 20);
            EXPECT_LT(own.mean, 0.005);
            EXPECT_GT(after.frames, 20);
            EXPECT_LT(after.mean, 0.005) << "mean foot skate per contact frame";
            EXPECT_LT(angle, 0.5);
        }
    }
}

}  // namespace
}  // namespace fray::test
