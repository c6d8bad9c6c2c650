#pragma once
// Demo takes shared by the data-preparation tests: the default library plan,
// generated once per test binary (deterministic for its seed).
#include <map>
#include <string>

#include "fray/core/joint_guess.h"
#include "fray/demo/demo_actor.h"
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

}  // namespace fray::test
