// Quality of the demo library against its own ground truth. A small library
// (about 2.5 minutes, every action kind at least once, and a minute of the
// football set and one of the carry set) is generated once and
// every threshold is checked on every action kind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "fray/core/kinematics.h"
#include "fray/demo/demo_actor.h"
#include "fray/demo/ground_truth.h"
#include "fray/demo/metrics.h"
#include "fray/io/bvh.h"

using namespace fray;
using namespace fray::demo;

namespace {

// Thresholds (see docs/DEMO_ACTOR.md).
constexpr double kMaxSkate = 0.005;            // m per frame during ground-truth contact
constexpr double kFloor = -0.01;               // lowest joint (m)
constexpr double kMaxAngularSpeed = 2500.0;    // deg/s, any joint's local rotation
constexpr double kMaxCutVelocityJumpRoot = 0.15;  // m/s: velocity jump of the root at an action cut
constexpr double kMaxCutVelocityJump = 0.8;      // m/s: of any joint (IK-driven knees and ankles)

struct Library {
    std::vector<Take> takes;
    std::vector<TakeMetrics> metrics;
    std::vector<std::vector<glm::vec3>> positions;
};

const Library& library() {
    static const Library lib = [] {
        Library l;
        LibraryOptions o;
        o.seed = 11;
        o.minutes = 2.5;
        std::vector<TakeSpec> plan = planLibrary(o);
        // The football set's cuts and tackles are held to the same thresholds.
        LibraryOptions football = o;
        football.set = "football";
        football.minutes = 1.0;
        for (const TakeSpec& spec : planLibrary(football)) plan.push_back(spec);
        // The carry set's box-end steps too.
        LibraryOptions carry = o;
        carry.set = "carry";
        carry.minutes = 1.0;
        for (const TakeSpec& spec : planLibrary(carry)) plan.push_back(spec);
        for (const TakeSpec& spec : plan) {
            l.takes.push_back(generateTake(spec, takeSeed(o.seed, spec.name)));
            const Take& t = l.takes.back();
            l.metrics.push_back(measureTake(t.motion, t.truth));
            l.positions.push_back(worldPositions(t.motion, 0, t.motion.frameCount() - 1));
        }
        return l;
    }();
    return lib;
}

glm::vec3 jointAt(std::size_t take, int frame, const char* joint) {
    const Take& t = library().takes[take];
    const auto jc = static_cast<std::size_t>(t.motion.jointCount());
    return library().positions[take][static_cast<std::size_t>(frame) * jc +
                                     static_cast<std::size_t>(t.motion.skeleton().find(joint))];
}

bool isPunch(const std::string& n) { return n == "jab" || n == "cross" || n.rfind("hook_", 0) == 0 || n.rfind("uppercut_", 0) == 0; }

}  // namespace

TEST(DemoLibrary, PlansTheDefaultTakesAndScalesWithMinutes) {
    const auto plan = planLibrary({});
    ASSERT_EQ(plan.size(), 6u);
    for (const auto& s : plan)
        if (s.kind == TakeKind::ShadowBoxing) {
            EXPECT_TRUE(s.seconds >= 60 && s.seconds <= 180) << s.name;
        }
    double total = 0;
    for (const auto& s : planLibrary({1, 10.0})) total += s.seconds;
    EXPECT_NEAR(total, 600.0, 1e-6);
    // The football set: its own takes, scaled the same way; unknown sets plan nothing.
    total = 0;
    for (const auto& s : planLibrary({1, 2.0, "football"})) {
        EXPECT_EQ(s.kind, TakeKind::Football);
        total += s.seconds;
    }
    EXPECT_NEAR(total, 120.0, 1e-6);
    EXPECT_TRUE(planLibrary({1, 0.0, "ballet"}).empty());
}

TEST(DemoLibrary, EveryActionKindIsPerformed) {
    std::set<std::string> seen;
    for (const Take& t : library().takes)
        for (const TruthAction& a : t.truth.actions) seen.insert(a.name);
    EXPECT_GE(actionKinds().size(), 45u);
    for (const std::string& k : actionKinds()) EXPECT_TRUE(seen.count(k)) << k << " never performed";
    for (const std::string& s : seen)
        EXPECT_NE(std::find(actionKinds().begin(), actionKinds().end(), s), actionKinds().end()) << s;
    // Each take performs the kinds its kind owns.
    for (const Take& t : library().takes) {
        std::set<std::string> inTake;
        for (const TruthAction& a : t.truth.actions) inTake.insert(a.name);
        for (const std::string& k : actionKindsOf(t.spec.kind)) EXPECT_TRUE(inTake.count(k)) << t.spec.name << ": " << k;
    }
}

TEST(DemoLibrary, GroundTruthIsConsistentAndRoundTripsThroughJson) {
    for (const Take& t : library().takes) {
        EXPECT_FALSE(validate(t.truth).has_value()) << t.spec.name << ": " << validate(t.truth).value_or("");
        EXPECT_EQ(t.truth.frameCount, t.motion.frameCount());
        EXPECT_DOUBLE_EQ(t.truth.fps, 60.0);
        const std::string json = toJson(t.truth);
        auto back = groundTruthFromJson(json, t.spec.name);
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_EQ(toJson(*back), json);
        for (const TruthAction& a : t.truth.actions) {
            if (a.has("punch") || a.has("kick")) {
                EXPECT_TRUE(a.attackDirection && a.targetPart && a.attackVector && a.peakSpeed) << a.name;
            }
            if (a.has("block") || a.has("avoid")) {
                EXPECT_TRUE(a.defendedPart.has_value()) << a.name;
            }
            EXPECT_FALSE(a.joints.empty() && !a.has("idle") && !a.has("transition")) << a.name;
        }
    }
}

TEST(DemoLibrary, RejectsBrokenGroundTruth) {
    GroundTruth t = library().takes.front().truth;
    t.actions[1].firstFrame += 1;  // a gap
    EXPECT_TRUE(validate(t).has_value());
    t = library().takes.front().truth;
    t.leftContact.pop_back();
    EXPECT_TRUE(validate(t).has_value());
    t = library().takes.front().truth;
    t.actions[0].annotations = {"dance"};
    EXPECT_TRUE(validate(t).has_value());
    EXPECT_FALSE(groundTruthFromJson("{", "x").ok());
    EXPECT_FALSE(groundTruthFromJson(R"({"format":"other"})", "x").ok());
}

TEST(DemoLibrary, FeetDoNotSkateDuringContact) {
    for (std::size_t i = 0; i < library().takes.size(); ++i) {
        const TakeMetrics& m = library().metrics[i];
        EXPECT_LT(m.maxSkate, kMaxSkate) << library().takes[i].spec.name;
        EXPECT_GT(m.contactFrames, 0);
    }
    // Every locomotion step has a supporting foot at some point; runs also have flight.
    for (const Take& t : library().takes)
        for (const TruthAction& a : t.truth.actions) {
            if (!a.has("walk") && !a.has("run")) continue;
            int contact = 0;
            for (int f = a.firstFrame; f <= a.lastFrame; ++f)
                contact += t.truth.leftContact[static_cast<std::size_t>(f)] | t.truth.rightContact[static_cast<std::size_t>(f)];
            EXPECT_GT(contact, 0) << t.spec.name << " " << a.name << " at " << a.firstFrame;
        }
}

TEST(DemoLibrary, NoJointGoesBelowTheFloor) {
    for (std::size_t i = 0; i < library().takes.size(); ++i)
        EXPECT_GT(library().metrics[i].minJointHeight, kFloor) << library().takes[i].spec.name;
}

TEST(DemoLibrary, JointAngularSpeedsStayWithinHumanLimits) {
    std::map<std::string, double> worst;
    for (const TakeMetrics& m : library().metrics)
        for (const ActionMetrics& a : m.actions) worst[a.name] = std::max(worst[a.name], a.maxAngularSpeed);
    EXPECT_EQ(worst.size(), actionKinds().size());
    for (const auto& [name, w] : worst) EXPECT_LT(w, kMaxAngularSpeed) << name;
}

TEST(DemoLibrary, AttackSpeedsAreRealistic) {
    std::set<std::string> checked;
    for (const TakeMetrics& m : library().metrics)
        for (const ActionMetrics& a : m.actions) {
            if (isPunch(a.name)) {
                EXPECT_GE(a.peakEffectorSpeed, 5.0) << a.name;
                EXPECT_LE(a.peakEffectorSpeed, 10.0) << a.name;
            } else if (a.name == "front_kick" || a.name.rfind("roundhouse_", 0) == 0) {
                EXPECT_GE(a.peakEffectorSpeed, 7.0) << a.name;
                EXPECT_LE(a.peakEffectorSpeed, 16.0) << a.name;
            } else if (a.name == "knee_strike") {
                EXPECT_GE(a.peakEffectorSpeed, 4.0) << a.name;
                EXPECT_LE(a.peakEffectorSpeed, 10.0) << a.name;
            } else {
                continue;
            }
            checked.insert(a.name);
        }
    EXPECT_EQ(checked.size(), 10u);
}

TEST(DemoLibrary, AttackVectorsMatchTheirDirection) {
    // Heading frame: x left, y up, z forward. "from_left" travels to the right.
    int n = 0;
    for (const Take& t : library().takes)
        for (const TruthAction& a : t.truth.actions) {
            if (!a.attackVector || !a.attackDirection) continue;
            const auto& v = *a.attackVector;
            EXPECT_NEAR(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), 1.0, 1e-3);
            const std::string& d = *a.attackDirection;
            if (d == "straight") {
                EXPECT_GT(v[2], 0.8) << a.name;
            } else if (d == "from_left") {
                EXPECT_LT(v[0], -0.1) << a.name;
            } else if (d == "from_right") {
                EXPECT_GT(v[0], 0.1) << a.name;
            } else if (d == "upward") {
                EXPECT_GT(v[1], 0.2) << a.name;
            }
            EXPECT_GT(v[2], 0.3) << a.name << ": attacks go toward the opponent";
            ++n;
        }
    EXPECT_GT(n, 20);
}

TEST(DemoLibrary, DurationsAreRealistic) {
    int jabs = 0, kicks = 0, falls = 0;
    for (const Take& t : library().takes)
        for (const TruthAction& a : t.truth.actions) {
            const double s = a.frameCount() / t.truth.fps;
            if (a.name == "jab") {
                ++jabs;
                EXPECT_TRUE(s >= 0.35 && s <= 0.5) << "jab " << s;
            }
            if (a.name.rfind("roundhouse_", 0) == 0) {
                ++kicks;
                EXPECT_TRUE(s >= 0.8 && s <= 1.0) << a.name << " " << s;
            }
            if (a.name.rfind("fall_", 0) == 0) {
                ++falls;
                EXPECT_TRUE(s >= 1.0 && s <= 2.0) << a.name << " " << s;
            }
        }
    EXPECT_GT(jabs, 0);
    EXPECT_GT(kicks, 0);
    EXPECT_GT(falls, 0);
}

TEST(DemoLibrary, FallsEndLyingAndKnockdownsGetUp) {
    for (std::size_t i = 0; i < library().takes.size(); ++i)
        for (const TruthAction& a : library().takes[i].truth.actions) {
            if (a.name.rfind("fall_", 0) == 0) {
                EXPECT_LT(jointAt(i, a.lastFrame, "Hips").y, 0.25f) << a.name;
                EXPECT_LT(jointAt(i, a.lastFrame, "Head").y, 0.40f) << a.name;
            }
            if (a.name == "knocked_down" || a.name == "get_up") {
                float lowest = 10;
                for (int f = a.firstFrame; f <= a.lastFrame; ++f) lowest = std::min(lowest, jointAt(i, f, "Hips").y);
                EXPECT_LT(lowest, 0.25f) << a.name;
                EXPECT_GT(jointAt(i, a.lastFrame, "Hips").y, 0.85f) << a.name;
                EXPECT_GT(jointAt(i, a.lastFrame, "Head").y, 1.45f) << a.name;
            }
        }
}

TEST(DemoLibrary, EnergeticIsFasterThanTired) {
    std::map<std::string, std::pair<double, int>> e, t;
    for (const Take& take : library().takes)
        for (const TruthAction& a : take.truth.actions) {
            if (a.style != "energetic" && a.style != "tired") continue;
            auto& m = a.style == "energetic" ? e : t;
            m[a.name].first += a.frameCount();
            m[a.name].second += 1;
        }
    double ratioSum = 0;
    int kinds = 0;
    for (const auto& [name, v] : e) {
        const auto it = t.find(name);
        if (it == t.end()) continue;
        ratioSum += (v.first / v.second) / (it->second.first / it->second.second);
        ++kinds;
    }
    ASSERT_GE(kinds, 25);
    EXPECT_LE(ratioSum / kinds, 0.8);
    // The tired guard is lower: wrists during guard_idle.
    double handY[2] = {0, 0};
    int n[2] = {0, 0};
    for (std::size_t i = 0; i < library().takes.size(); ++i)
        for (const TruthAction& a : library().takes[i].truth.actions) {
            if (a.name != "guard_idle" || (a.style != "energetic" && a.style != "tired")) continue;
            const int s = a.style == "tired";
            handY[s] += static_cast<double>(jointAt(i, a.firstFrame, "LeftHand").y - jointAt(i, a.firstFrame, "Head").y);
            ++n[s];
        }
    ASSERT_TRUE(n[0] > 0 && n[1] > 0);
    EXPECT_LT(handY[1] / n[1], handY[0] / n[0] - 0.04);
}

TEST(DemoLibrary, MotionIsContinuousAcrossActionCuts) {
    // A velocity jump J at frame b shows as a spike of J in the per-frame
    // velocity change dv(b) against the mean of its neighbours dv(b-1), dv(b+1).
    // The key curves are C2, so the root shows almost none; IK-driven joints
    // (a knee straightening at toe-off) show some curvature, never a jump.
    double worstRoot = 0, worstJoint = 0;
    std::string whereRoot, whereJoint;
    int cuts = 0;
    for (std::size_t i = 0; i < library().takes.size(); ++i) {
        const Take& t = library().takes[i];
        const auto jc = static_cast<std::size_t>(t.motion.jointCount());
        const auto& P = library().positions[i];
        auto vel = [&](int f, std::size_t j) {
            return (P[static_cast<std::size_t>(f) * jc + j] - P[static_cast<std::size_t>(f - 1) * jc + j]) * 60.0f;
        };
        for (const TruthAction& a : t.truth.actions) {
            const int b = a.firstFrame;
            if (b < 3 || b + 2 >= t.motion.frameCount()) continue;
            ++cuts;
            for (std::size_t j = 0; j < jc; ++j) {
                const glm::vec3 dvPrev = vel(b - 1, j) - vel(b - 2, j);
                const glm::vec3 dv = vel(b, j) - vel(b - 1, j);
                const glm::vec3 dvNext = vel(b + 1, j) - vel(b, j);
                const double spike = glm::length(dv - 0.5f * (dvPrev + dvNext));
                double& worst = j == 0 ? worstRoot : worstJoint;
                if (spike > worst) {
                    worst = spike;
                    (j == 0 ? whereRoot : whereJoint) = t.spec.name + " " + a.name + " at frame " + std::to_string(b) +
                                                        " joint " + t.motion.skeleton().names[j];
                }
            }
        }
    }
    EXPECT_GT(cuts, 150);
    EXPECT_LT(worstRoot, kMaxCutVelocityJumpRoot) << whereRoot;
    EXPECT_LT(worstJoint, kMaxCutVelocityJump) << whereJoint;
}

TEST(DemoLibrary, SameSeedGivesIdenticalFilesOtherSeedsDiffer) {
    const TakeSpec spec{"shadowbox_energetic", TakeKind::ShadowBoxing, Style::Energetic, 25.0};
    const Take a = generateTake(spec, 42), b = generateTake(spec, 42), c = generateTake(spec, 43);
    EXPECT_EQ(writeBvhToString(a.motion), writeBvhToString(b.motion));
    EXPECT_EQ(toJson(a.truth), toJson(b.truth));
    EXPECT_NE(writeBvhToString(a.motion), writeBvhToString(c.motion));
    EXPECT_NE(takeSeed(1, "walking"), takeSeed(1, "falls"));
    EXPECT_NE(takeSeed(1, "walking"), takeSeed(2, "walking"));
}
