// Supporting-foot classification (SPEC 1.3): the heuristic fallback and the
// SVM, measured against the demo actor's exact contacts, plus the binary
// model format, errors, cancellation and a run over the shared real captures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <type_traits>

#include "fray/io/import.h"
#include "fray/prep/contacts.h"
#include "prep/prep_fixture.h"
#include "test_util.h"

using namespace fray;
using namespace fray::prep;

namespace {

// Accuracy of `c` against the truth, over the frames outside `skip` ([first, last]).
double accuracyOutside(const FootContacts& c, const FootContacts& truth, int first, int last) {
    long equal = 0;
    long total = 0;
    for (int f = 0; f < truth.frameCount(); ++f) {
        if (f >= first && f <= last) continue;
        for (const Foot foot : {Foot::Left, Foot::Right}) {
            const auto i = static_cast<std::size_t>(f);
            equal += (c.foot(foot)[i] != 0) == (truth.foot(foot)[i] != 0) ? 1 : 0;
            ++total;
        }
    }
    return total ? static_cast<double>(equal) / static_cast<double>(total) : 1.0;
}

MotionSignals flatSignals(int frames, double fps) {
    MotionSignals s;
    s.fps = fps;
    s.frameCount = frames;
    for (auto& v : s.footSpeed) v.assign(static_cast<std::size_t>(frames), 0.0f);
    for (auto& v : s.footHeight) v.assign(static_cast<std::size_t>(frames), 0.0f);
    return s;
}

}  // namespace

// ---- heuristic ------------------------------------------------------------

TEST(Contacts, HeuristicIsReasonableOnDemoTakes) {
    long equal = 0;
    long total = 0;
    for (const auto& [name, t] : test::demoTakes()) {
        ASSERT_GT(t.signals.frameCount, 0) << name;
        const FootContacts h = heuristicContacts(t.signals);
        ASSERT_EQ(h.frameCount(), t.signals.frameCount);
        const double a = contactAgreement(h, t.truthContacts);
        std::printf("[ heuristic ] %-20s accuracy %.4f\n", name.c_str(), a);
        EXPECT_GE(a, 0.90) << name;
        equal += std::lround(a * 2 * t.signals.frameCount);
        total += 2L * t.signals.frameCount;
    }
    const double all = static_cast<double>(equal) / static_cast<double>(total);
    std::printf("[ heuristic ] all takes            accuracy %.4f\n", all);
    RecordProperty("heuristic_accuracy", std::to_string(all));
    EXPECT_GE(all, 0.94);
}

TEST(Contacts, HeuristicThresholdsAndMedianFilter) {
    MotionSignals s = flatSignals(40, 60.0);
    // Left: supported except a high swing 10..24 and a one-frame spike at 30.
    for (int f = 10; f < 25; ++f) s.footHeight[0][static_cast<std::size_t>(f)] = 0.2f;
    s.footSpeed[0][30] = 3.0f;
    // Right: in the air except a one-frame dip at 5.
    for (auto& v : s.footHeight[1]) v = 0.3f;
    s.footHeight[1][5] = 0.0f;
    const FootContacts c = heuristicContacts(s);
    for (int f = 0; f < 40; ++f) {
        const auto i = static_cast<std::size_t>(f);
        EXPECT_EQ(c.left[i], (f >= 10 && f < 25) ? 0 : 1) << f;  // the spike at 30 is filtered out
        EXPECT_EQ(c.right[i], 0) << f;                         // so is the dip
    }
    HeuristicParams raw;
    raw.medianWindow = 1;
    const FootContacts unfiltered = heuristicContacts(s, raw);
    EXPECT_EQ(unfiltered.left[30], 0);
    EXPECT_EQ(unfiltered.right[5], 1);

    // The window is in 60 fps frames: at 120 fps a 2-frame flicker is also removed.
    MotionSignals fast = flatSignals(80, 120.0);
    fast.footSpeed[0][40] = fast.footSpeed[0][41] = 3.0f;
    const FootContacts c120 = heuristicContacts(fast);
    EXPECT_EQ(c120.left[40], 1);
    EXPECT_EQ(c120.left[41], 1);
    // NaN features read as "not supporting" (then the filter decides).
    fast.footHeight[1][10] = std::nanf("");
    EXPECT_EQ(heuristicContacts(fast, raw).right[10], 0);
}

// ---- samples, labels, agreement ---------------------------------------------

TEST(Contacts, CollectSamplesTakesLabelledFramesOfBothFeetInOrder) {
    MotionSignals s = flatSignals(6, 60.0);
    for (int f = 0; f < 6; ++f) {
        s.footSpeed[0][static_cast<std::size_t>(f)] = static_cast<float>(f);
        s.footSpeed[1][static_cast<std::size_t>(f)] = static_cast<float>(10 + f);
    }
    FrameLabels labels;
    labels.left = {-1, 1, 0, -1, 1, -1};
    labels.right = {0, -1, -1, 1};  // shorter than the motion: the rest is unlabelled
    const auto samples = collectSamples(s, labels);
    ASSERT_EQ(samples.size(), 5u);
    const float speeds[] = {1, 2, 4, 10, 13};
    const bool contact[] = {true, false, true, false, true};
    for (std::size_t i = 0; i < samples.size(); ++i) {
        EXPECT_EQ(samples[i].speed, speeds[i]) << i;
        EXPECT_EQ(samples[i].contact, contact[i]) << i;
    }
}

TEST(Contacts, LabelsFromContactsAreRunsThatExpandBack) {
    FootContacts c;
    c.left = {1, 1, 0, 0, 1, 1, 1};
    c.right = {0, 0, 0, 1, 1, 1, 0};
    const auto runs = labelsFromContacts(c, 1, 10);  // clamped to frame 6
    ASSERT_EQ(runs.size(), 5u);
    EXPECT_EQ(runs[0], (ContactLabel{1, 1, true, false}));
    EXPECT_EQ(runs[1], (ContactLabel{2, 2, false, false}));
    EXPECT_EQ(runs[4], (ContactLabel{6, 6, true, false}));
    const auto labels = expandLabels(runs, 7);
    ASSERT_TRUE(labels.ok());
    EXPECT_EQ(labels->left, (std::vector<std::int8_t>{-1, 1, 0, 0, 1, 1, 1}));
    EXPECT_EQ(labels->right, (std::vector<std::int8_t>{-1, 0, 0, 1, 1, 1, 0}));
}

TEST(Contacts, AgreementCountsEveryFrameOfBothFeet) {
    FootContacts a;
    a.left = {1, 0, 1, 1};
    a.right = {0, 0, 1, 1};
    FootContacts b = a;
    EXPECT_DOUBLE_EQ(contactAgreement(a, b), 1.0);
    b.right[0] = 1;
    EXPECT_DOUBLE_EQ(contactAgreement(a, b), 7.0 / 8.0);
    b.left.pop_back();  // a frame only one side has is a disagreement
    EXPECT_DOUBLE_EQ(contactAgreement(a, b), 6.0 / 8.0);
    EXPECT_DOUBLE_EQ(contactAgreement(FootContacts{}, FootContacts{}), 1.0);
}

// ---- SVM ----------------------------------------------------------------

TEST(ContactSvm, TwentySecondsOfLabelsClassifyEveryDemoTake) {
    const auto samples = test::demoLabelSamples();
    ASSERT_EQ(samples.size(), 2400u);  // 20 s at 60 fps, both feet
    const ContactSvm& svm = test::demoSvm();
    const SvmReport& rep = svm.report();
    std::printf("[ svm ] C %g gamma %g loo %.4f samples %d distinct %d support vectors %d loo retrains %lld "
                "train %.2f s\n",
                rep.C, rep.gamma, rep.looAccuracy, rep.samples, rep.distinctSamples, rep.supportVectors,
                rep.looRetrains, rep.seconds);
    EXPECT_EQ(rep.samples, 2400);
    EXPECT_EQ(rep.grid.size(), SvmTrainOptions{}.log2C.size() * SvmTrainOptions{}.log2Gamma.size());
    EXPECT_GE(rep.looAccuracy, 0.95);
    EXPECT_GT(rep.supportVectors, 0);
    for (const auto& cell : rep.grid) EXPECT_LE(cell.looAccuracy, rep.looAccuracy);

    long svmEqual = 0;
    long heurEqual = 0;
    long total = 0;
    double unseenSum = 0;
    int unseenTakes = 0;
    for (const auto& [name, t] : test::demoTakes()) {
        const FootContacts c = svm.classify(t.signals);
        ASSERT_EQ(c.frameCount(), t.signals.frameCount);
        const double a = contactAgreement(c, t.truthContacts);
        const double h = contactAgreement(heuristicContacts(t.signals), t.truthContacts);
        // Accuracy over the frames that were not labelled.
        int first = 1;
        int last = 0;
        for (const auto& r : test::kTrainingRanges) {
            if (name == r.take) {
                first = r.first;
                last = r.last;
            }
        }
        const double unseen = accuracyOutside(c, t.truthContacts, first, last);
        std::printf("[ svm ] %-20s accuracy %.4f (unlabelled frames %.4f), heuristic %.4f\n", name.c_str(), a,
                    unseen, h);
        EXPECT_GE(a, 0.95) << name;
        EXPECT_GE(unseen, 0.95) << name;
        EXPECT_GT(a, h) << name;
        svmEqual += std::lround(a * 2 * t.signals.frameCount);
        heurEqual += std::lround(h * 2 * t.signals.frameCount);
        total += 2L * t.signals.frameCount;
        unseenSum += unseen;
        ++unseenTakes;
    }
    const double svmAll = static_cast<double>(svmEqual) / static_cast<double>(total);
    const double heurAll = static_cast<double>(heurEqual) / static_cast<double>(total);
    std::printf("[ svm ] all takes            accuracy %.4f, heuristic %.4f\n", svmAll, heurAll);
    RecordProperty("svm_accuracy", std::to_string(svmAll));
    EXPECT_GE(svmAll, 0.95);
    EXPECT_GE(unseenSum / unseenTakes, 0.95);
    EXPECT_GT(svmAll, heurAll);
}

TEST(ContactSvm, ShortcutLeaveOneOutEqualsBruteForce) {
    // 5 s of walking and 5 s of falls: small enough to retrain every row.
    std::vector<TrainingSample> samples;
    for (const auto& range : {test::kTrainingRanges[3], test::kTrainingRanges[2]}) {
        const auto& t = test::demoTakes().at(range.take);
        const auto labels = expandLabels(labelsFromContacts(t.truthContacts, range.first, range.last),
                                         t.signals.frameCount);
        ASSERT_TRUE(labels.ok());
        const auto s = collectSamples(t.signals, *labels);
        samples.insert(samples.end(), s.begin(), s.end());
    }
    for (const double log2C : {-1.0, 3.0, 9.0}) {
        for (const double log2Gamma : {-1.0, 3.0, 7.0}) {
            const auto fast = evaluateSvmCell(samples, log2C, log2Gamma, LooMethod::Shortcut);
            const auto slow = evaluateSvmCell(samples, log2C, log2Gamma, LooMethod::BruteForce);
            ASSERT_TRUE(fast.ok() && slow.ok());
            EXPECT_DOUBLE_EQ(fast->looAccuracy, slow->looAccuracy) << "C 2^" << log2C << " gamma 2^" << log2Gamma;
        }
    }
}

TEST(ContactSvm, SameInputSameModel) {
    auto samples = test::demoLabelSamples();
    SvmTrainOptions small;  // a smaller grid keeps the sanitizer build quick
    small.log2C = {1, 5};
    small.log2Gamma = {1, 5};
    const auto a = ContactSvm::train(samples, small);
    const auto b = ContactSvm::train(samples, small);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->serialize(), b->serialize());
    ASSERT_EQ(a->report().grid.size(), b->report().grid.size());
    for (std::size_t i = 0; i < a->report().grid.size(); ++i)
        EXPECT_EQ(a->report().grid[i].looAccuracy, b->report().grid[i].looAccuracy);
    // Training rows are sorted, so the order of the samples does not matter.
    std::reverse(samples.begin(), samples.end());
    const auto c = ContactSvm::train(samples, small);
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(a->serialize(), c->serialize());
    const auto& walk = test::demoTakes().at("walking").signals;
    EXPECT_EQ(a->classify(walk).left, c->classify(walk).left);
}

TEST(ContactSvm, SubsamplesDeterministicallyAboveMaxSamples) {
    SvmTrainOptions opt;
    opt.log2C = {3};
    opt.log2Gamma = {3};
    opt.maxSamples = 1000;
    const auto a = ContactSvm::train(test::demoLabelSamples(), opt);
    const auto b = ContactSvm::train(test::demoLabelSamples(), opt);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->report().samples, 1000);
    EXPECT_EQ(a->serialize(), b->serialize());
}

TEST(ContactSvm, SerializeRoundTripClassifiesIdentically) {
    const ContactSvm& svm = test::demoSvm();
    const auto bytes = svm.serialize();
    ASSERT_FALSE(bytes.empty());
    const auto back = ContactSvm::deserialize(bytes);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->serialize(), bytes);
    EXPECT_EQ(back->report().C, svm.report().C);
    EXPECT_EQ(back->report().gamma, svm.report().gamma);
    EXPECT_EQ(back->report().looAccuracy, svm.report().looAccuracy);
    EXPECT_EQ(back->report().supportVectors, svm.report().supportVectors);
    for (const auto& [name, t] : test::demoTakes()) {
        const FootContacts a = svm.classify(t.signals);
        const FootContacts b = back->classify(t.signals);
        EXPECT_EQ(a.left, b.left) << name;
        EXPECT_EQ(a.right, b.right) << name;
    }
    for (const float speed : {0.0f, 0.01f, 0.1f, 1.0f, 10.0f})
        for (const float height : {-0.01f, 0.0f, 0.001f, 0.05f, 1.0f})
            EXPECT_EQ(svm.decision(speed, height), back->decision(speed, height));
}

TEST(ContactSvm, DeserializeRejectsTruncatedAndGarbageBytes) {
    const auto bytes = test::demoSvm().serialize();
    for (std::size_t n = 0; n < bytes.size(); ++n) {
        const auto r = ContactSvm::deserialize(std::span(bytes.data(), n));
        EXPECT_FALSE(r.ok()) << n << " bytes";
    }
    auto longer = bytes;
    longer.push_back(0);
    EXPECT_FALSE(ContactSvm::deserialize(longer).ok());

    std::mt19937 rng(7);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<std::uint8_t> junk(static_cast<std::size_t>(trial * 7 % 600));
        for (auto& b : junk) b = static_cast<std::uint8_t>(byte(rng));
        if (trial % 2 == 0 && junk.size() >= 8) {  // a valid magic and version reach the deeper checks
            std::copy(bytes.begin(), bytes.begin() + 8, junk.begin());
        }
        EXPECT_FALSE(ContactSvm::deserialize(junk).ok()) << "trial " << trial;
    }
    // Single-byte corruptions either fail validation or give a usable model.
    const auto& walk = test::demoTakes().at("walking").signals;
    for (std::size_t i = 0; i < bytes.size(); i += 5) {
        auto bad = bytes;
        bad[i] ^= static_cast<std::uint8_t>(1 + byte(rng) % 255);
        const auto r = ContactSvm::deserialize(bad);
        if (r.ok()) {
            EXPECT_EQ(r->classify(walk).frameCount(), walk.frameCount);
        }
    }
}

TEST(ContactSvm, RejectsUnusableLabelsWithReasons) {
    const auto message = [](const std::vector<TrainingSample>& s, const SvmTrainOptions& o = {}) {
        const auto r = ContactSvm::train(s, o);
        return r.ok() ? std::string("(trained)") : r.error().message;
    };
    EXPECT_NE(message({}).find("no labelled frames"), std::string::npos);
    const std::vector<TrainingSample> planted(50, TrainingSample{0.0f, 0.0f, true});
    EXPECT_NE(message(planted).find("label some frames where the foot is in the air too"), std::string::npos);
    const std::vector<TrainingSample> flying(50, TrainingSample{2.0f, 0.3f, false});
    EXPECT_NE(message(flying).find("label some supporting frames too"), std::string::npos);
    auto mixed = planted;
    mixed.insert(mixed.end(), flying.begin(), flying.end());
    auto withNan = mixed;
    withNan[3].height = std::nanf("");
    EXPECT_NE(message(withNan).find("sample 3"), std::string::npos);
    SvmTrainOptions noGrid;
    noGrid.log2C.clear();
    EXPECT_NE(message(mixed, noGrid).find("grid"), std::string::npos);
    SvmTrainOptions hugeGamma;
    hugeGamma.log2Gamma = {64};
    EXPECT_NE(message(mixed, hugeGamma).find("outside"), std::string::npos);
    // Subsampling that leaves one class: samples 0 and 50 of 100, both planted.
    auto rare = std::vector<TrainingSample>(99, TrainingSample{0.0f, 0.0f, true});
    rare.push_back({2.0f, 0.3f, false});
    SvmTrainOptions tiny;
    tiny.maxSamples = 2;
    EXPECT_NE(message(rare, tiny).find("only one class"), std::string::npos);
    // The smallest usable problem trains.
    const auto two = ContactSvm::train({{0.0f, 0.0f, true}, {2.0f, 0.3f, false}});
    ASSERT_TRUE(two.ok()) << two.error().message;
    EXPECT_TRUE(two->predict(0.0f, 0.0f));
    EXPECT_FALSE(two->predict(2.0f, 0.3f));
}

TEST(ContactSvm, ProgressReportsCellsAndCancels) {
    const auto samples = test::demoLabelSamples();
    SvmTrainOptions opt;
    opt.log2C = {1, 3, 5};
    opt.log2Gamma = {1, 3};
    std::vector<double> fractions;
    const auto ok = ContactSvm::train(samples, opt, [&](double f, std::string_view stage) {
        EXPECT_FALSE(stage.empty());
        fractions.push_back(f);
        return true;
    });
    ASSERT_TRUE(ok.ok());
    ASSERT_EQ(fractions.size(), 7u);  // start + one per cell
    EXPECT_EQ(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0);
    EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));

    for (const int stopAfter : {0, 1, 3}) {
        int calls = 0;
        const auto r = ContactSvm::train(samples, opt, [&](double, std::string_view) { return calls++ < stopAfter; });
        ASSERT_FALSE(r.ok()) << "stop after " << stopAfter;
        EXPECT_TRUE(r.error().isCancelled()) << r.error().message;
    }
}

TEST(ContactSvm, IsMoveOnly) {
    static_assert(!std::is_copy_constructible_v<ContactSvm>);
    static_assert(!std::is_copy_assignable_v<ContactSvm>);
    static_assert(std::is_nothrow_move_constructible_v<ContactSvm>);
    auto a = ContactSvm::train({{0.0f, 0.0f, true}, {2.0f, 0.3f, false}});
    auto b = ContactSvm::train({{0.0f, 0.0f, true}, {0.5f, 0.1f, false}});
    ASSERT_TRUE(a.ok() && b.ok());
    ContactSvm moved = std::move(*a);
    EXPECT_TRUE(moved.predict(0.0f, 0.0f));
    moved = std::move(*b);  // frees the first model
    EXPECT_TRUE(moved.predict(0.0f, 0.0f));
    EXPECT_TRUE(a->serialize().empty());  // NOLINT(bugprone-use-after-move): moved-from is empty, not broken
    EXPECT_FALSE(a->predict(0.0f, 0.0f));
}

// ---- real captures ------------------------------------------------------

TEST(ContactsReal, HeuristicAndDemoSvmOnSharedCaptures) {
    const char* const files[] = {"cmu135_karate/bassai.bvh", "cmu135_karate/mawashigeri.bvh",
                                 "lafan1/walk4_subject1.bvh", "lafan1/pushAndFall1_subject1.bvh",
                                 "bandai/dataset-2_walk_normal_001.bvh", "bandai/dataset-1_run_active_001.bvh"};
    if (!test::requireSharedMocap()) return;
    const ContactSvm& svm = test::demoSvm();
    for (const char* file : files) {
        const auto path = test::sharedMocap() / file;
        const auto motion = loadMotion(path);
        ASSERT_TRUE(motion.ok()) << file << ": " << motion.error().message;
        const auto signals = computeSignals(*motion, guessStandardJoints(motion->skeleton()));
        ASSERT_TRUE(signals.ok()) << file << ": " << signals.error().message;
        const FootContacts h = heuristicContacts(*signals);
        const FootContacts s = svm.classify(*signals);
        ASSERT_EQ(h.frameCount(), signals->frameCount);
        int anyDown = 0;
        int svmAnyDown = 0;
        for (int f = 0; f < signals->frameCount; ++f) {
            anyDown += supportAt(h, f) != Support::None ? 1 : 0;
            svmAnyDown += supportAt(s, f) != Support::None ? 1 : 0;
        }
        const double share = static_cast<double>(anyDown) / signals->frameCount;
        const double svmShare = static_cast<double>(svmAnyDown) / signals->frameCount;
        std::printf("[ real ] %-38s %5d frames %5.1f fps: a foot down %.3f (heuristic) %.3f (demo SVM), "
                    "SVM/heuristic agreement %.4f\n",
                    file, signals->frameCount, signals->fps, share, svmShare, contactAgreement(s, h));
        EXPECT_GE(share, 0.20) << file;
        EXPECT_LE(share, 1.00) << file;
    }
}
