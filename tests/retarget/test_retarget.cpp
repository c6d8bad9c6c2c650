// Retargeting (fray/core/retarget.h) on the real captures of three sources
// (CMU karate, LAFAN1, Bandai): every pair, foot skate on contacts, bone
// directions kept; bad skeletons as clear errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "fray/core/kinematics.h"
#include "fray/core/retarget.h"
#include "fray/io/import.h"
#include "fray/pipeline/prep_session.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/segmentation.h"
#include "temp_dir.h"
#include "test_util.h"

namespace fray::test {
namespace {

namespace fs = std::filesystem;

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

// A project mixing the three sources: `project new` would refuse nothing,
// and the session puts every take on the first one's skeleton, so one motion
// graph connects them; the heuristic contacts the project finds on the
// retargeted takes show no foot skate.
TEST(Retarget, MixedProjectBuildsOneMotionGraph) {
    if (!requireSharedMocap()) return;
    TempDir dir;
    const fs::path file = dir / "mixed.frayproj";
    prep::Project p = prep::makeProject("mixed");
    std::vector<std::string> takes;
    for (const char* t : {"oiduki001", "frontkick001", "gedanbarai", "mawashigeri", "heiansyodan"})
        takes.push_back(std::string("cmu135_karate/") + t + ".bvh");
    takes.insert(takes.end(), {"lafan1/push1_subject2.bvh", "lafan1/walk4_subject1.bvh"});
    for (const char* t : {"walk-back_normal", "walk-back_tired", "walk-left_normal", "walk-left_tired", "walk-right_normal",
                          "walk-right_tired", "walk_active", "walk_normal", "walk_tired", "run_active", "run_normal", "run_tired"})
        takes.push_back(std::string("bandai/dataset-1_") + t + "_001.bvh");
    constexpr std::size_t kCmu = 5, kLafan = 2;
    for (const std::string& take : takes) {
        auto m = loadMotion(sharedMocap() / take);
        ASSERT_TRUE(m) << m.error().message;
        prep::ProjectMotion entry;
        entry.id = fs::path(take).stem().string();
        entry.path = (sharedMocap() / take).string();
        entry.actions = prep::MotionActions::whole(m->frameCount());
        p.motions.push_back(std::move(entry));
    }
    ASSERT_TRUE(prep::saveProject(p, file));
    std::vector<RetargetReport> reports;
    auto loaded = pipeline::loadSessionMotions(p, file, {}, &reports);
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(reports.size(), takes.size() - kCmu);  // LAFAN1 and Bandai onto CMU's skeleton
    for (const auto& r : reports) {
        EXPECT_GE(r.mapped.size(), 17u) << r.text();
        EXPECT_NE(r.text().find("lfemur"), std::string::npos);
    }

    // Cancelling in the retargeting pass is a cancellation, not a failure.
    int calls = 0;
    auto cancelled = pipeline::loadSessionMotions(p, file, [&](double, std::string_view) { return ++calls <= static_cast<int>(takes.size()) + 3; });
    ASSERT_FALSE(cancelled);
    EXPECT_TRUE(cancelled.error().isCancelled()) << cancelled.error().message;

    auto s = pipeline::openSession(file, true, {}, {});
    ASSERT_TRUE(s) << s.error().message;
    for (const auto& m : s->motions) EXPECT_TRUE(sameSkeleton(m.motion.skeleton(), s->motions[0].motion.skeleton())) << m.id;
    ASSERT_TRUE(pipeline::computeContacts(*s, true, {}));
    const auto params = prep::segmentationParams(s->project.settings);
    for (std::size_t i = 0; i < s->motions.size(); ++i) {
        const auto r = prep::segment(s->motions[i].signals, s->motions[i].contacts, params);
        s->project.motions[i].actions = prep::recut(s->project.motions[i].actions, r.cuts);
    }
    // Foot skate on the retargeted takes, on the contacts the project found.
    for (std::size_t i = kCmu; i < s->motions.size(); ++i) {
        const auto& m = s->motions[i];
        const FootSkate skate = measureFootSkate(m.motion, m.joints, {m.contacts.left, m.contacts.right});
        std::printf("%s: foot skate %.3f cm per contact frame (max %.2f cm) over %d frames\n", m.id.c_str(),
                    skate.mean * 100, skate.max * 100, skate.frames);
        if (m.motion.frameCount() > 60) {
            EXPECT_GT(skate.frames, 10) << m.id;
        }
        EXPECT_LT(skate.mean, 0.005) << m.id;
    }
    // The default threshold (0.2, set on the synthetic demo) joins few real
    // poses, from one source or several (CMU or Bandai alone: 40-52 %). With
    // no threshold set, the project's graph takes the threshold its data's
    // transition gaps ask for, and connects the real takes without tuning.
    auto tight = pipeline::projectGraph(*s, "", 0.2, {});
    ASSERT_TRUE(tight) << tight.error().message;
    std::printf("threshold 0.2: %d nodes, largest SCC %.1f %%\n", tight->graph.nodeCount, tight->graph.stats.sccShare * 100);
    auto wide = pipeline::projectGraph(*s, "", 0.0, {});
    ASSERT_TRUE(wide) << wide.error().message;
    std::printf("threshold from the data %.3f: %d nodes, largest SCC %.1f %%\n", wide->options.threshold, wide->graph.nodeCount,
                wide->graph.stats.sccShare * 100);
    EXPECT_TRUE(wide->thresholdFromData);
    EXPECT_GT(wide->options.threshold, 0.2);
    EXPECT_GE(wide->graph.stats.sccShare, 0.8);
    // Some node joins poses of different sources.
    std::vector<int> firstAction;
    int a = 0;
    for (const auto& entry : s->project.motions) {
        firstAction.push_back(a);
        a += entry.actions.actionCount();
    }
    firstAction.push_back(a);
    auto sourceOf = [&](int action) {
        const int motion = static_cast<int>(std::upper_bound(firstAction.begin(), firstAction.end(), action) - firstAction.begin()) - 1;
        return motion < static_cast<int>(kCmu) ? 0 : motion < static_cast<int>(kCmu + kLafan) ? 1 : 2;
    };
    std::vector<int> sourcesAt(static_cast<std::size_t>(wide->graph.nodeCount), 0);
    for (int k = 0; k < a; ++k) {
        sourcesAt[static_cast<std::size_t>(wide->graph.startNode[static_cast<std::size_t>(k)])] |= 1 << sourceOf(k);
        sourcesAt[static_cast<std::size_t>(wide->graph.endNode[static_cast<std::size_t>(k)])] |= 1 << sourceOf(k);
    }
    const auto mixedNodes = std::count_if(sourcesAt.begin(), sourcesAt.end(), [](int m) { return m != 0 && (m & (m - 1)) != 0; });
    std::printf("nodes joining poses of two or three sources: %td\n", mixedNodes);
    EXPECT_GT(mixedNodes, 0);
}

}  // namespace
}  // namespace fray::test
