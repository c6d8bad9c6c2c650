#pragma once
// Demo takes shared by the data-preparation tests: the default library plan,
// generated once per test binary (deterministic for its seed).
#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "fray/core/joint_guess.h"
#include "fray/demo/demo_actor.h"
#include "fray/prep/contacts.h"
#include "fray/prep/labels.h"
#include "fray/prep/signals.h"

namespace fray::test {

struct DemoTake {
    demo::Take take;
    StandardJoints joints;
    prep::MotionSignals signals;
    prep::FootContacts truthContacts;
};

// All takes of the default library (seed 1), by take name.
inline const std::map<std::string, DemoTake>& demoTakes() {
    static const std::map<std::string, DemoTake> takes = [] {
        std::map<std::string, DemoTake> out;
        demo::LibraryOptions options;
        options.seed = 1;
        for (const auto& spec : demo::planLibrary(options)) {
            DemoTake t;
            t.take = demo::generateTake(spec, demo::takeSeed(options.seed, spec.name));
            t.joints = guessStandardJoints(t.take.motion.skeleton());
            auto s = prep::computeSignals(t.take.motion, t.joints);
            if (s) t.signals = std::move(*s);
            t.truthContacts.left = t.take.truth.leftContact;
            t.truthContacts.right = t.take.truth.rightContact;
            out.emplace(spec.name, std::move(t));
        }
        return out;
    }();
    return takes;
}

// ~20 s of labels, as an animator would mark them: 4 x 5 s from different
// kinds of take (frames at 60 fps, inclusive).
struct LabelRange {
    const char* take;
    int first;
    int last;
};
inline constexpr LabelRange kTrainingRanges[] = {{"shadowbox_energetic", 1200, 1499},
                                          {"running_around", 900, 1199},
                                          {"falls", 1500, 1799},
                                          {"walking", 600, 899}};

inline std::vector<prep::TrainingSample> demoLabelSamples() {
    std::vector<prep::TrainingSample> out;
    for (const auto& range : kTrainingRanges) {
        const auto& t = demoTakes().at(range.take);
        const auto labels = prep::expandLabels(prep::labelsFromContacts(t.truthContacts, range.first, range.last),
                                         t.signals.frameCount);
        if (!labels.ok()) {
            ADD_FAILURE() << labels.error().message;
            continue;
        }
        const auto s = prep::collectSamples(t.signals, *labels);
        out.insert(out.end(), s.begin(), s.end());
    }
    return out;
}

// Trained once per test binary (default options).
inline const prep::ContactSvm& demoSvm() {
    static const std::optional<prep::ContactSvm> svm = [] {
        auto r = prep::ContactSvm::train(demoLabelSamples());
        EXPECT_TRUE(r.ok()) << r.error().message;
        return r.ok() ? std::optional<prep::ContactSvm>(std::move(*r)) : std::nullopt;
    }();
    if (!svm) throw std::runtime_error("the demo SVM did not train");
    return *svm;
}

}  // namespace fray::test
