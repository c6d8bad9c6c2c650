#pragma once
// Hand labels of shared real captures (tests/data/real_labels, README.md there)
// and the captures they label, loaded once per test binary.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fray/core/joint_guess.h"
#include "fray/io/import.h"
#include "fray/prep/contacts.h"
#include "fray/prep/labels.h"
#include "fray/prep/signals.h"
#include "test_util.h"

namespace fray::test {

struct LabelledAction {
    int first = 0, last = 0;
    std::string label;
};

inline std::filesystem::path realLabelsDir() { return std::filesystem::path(FRAY_REAL_LABELS); }

// Rows "take,first,last,label" of a labels CSV, grouped by take (the capture's
// path under the shared mocap folder). Lines starting with '#' are comments.
inline std::map<std::string, std::vector<LabelledAction>> readActionLabels(const std::string& file) {
    std::map<std::string, std::vector<LabelledAction>> out;
    std::ifstream in(realLabelsDir() / file);
    EXPECT_TRUE(in.good()) << "cannot open " << (realLabelsDir() / file);
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::stringstream ss(line);
        std::string take, a, b, label;
        std::getline(ss, take, ',');
        std::getline(ss, a, ',');
        std::getline(ss, b, ',');
        std::getline(ss, label, ',');
        out[take].push_back({std::stoi(a), std::stoi(b), label});
    }
    return out;
}

struct RealTake {
    Motion motion;
    StandardJoints joints;
    prep::MotionSignals signals;
};

// Loads (once) a capture under the shared mocap folder.
inline const RealTake* realTake(const std::string& relative) {
    static std::map<std::string, RealTake> cache;
    if (auto it = cache.find(relative); it != cache.end()) return &it->second;
    auto motion = loadMotion(sharedMocap() / relative);
    if (!motion.ok()) {
        ADD_FAILURE() << relative << ": " << motion.error().message;
        return nullptr;
    }
    RealTake t;
    t.joints = guessStandardJoints(motion->skeleton());
    auto s = prep::computeSignals(*motion, t.joints);
    if (!s.ok()) {
        ADD_FAILURE() << relative << ": " << s.error().message;
        return nullptr;
    }
    t.signals = std::move(*s);
    t.motion = std::move(*motion);
    return &cache.emplace(relative, std::move(t)).first->second;
}

// The true cuts of a fully labelled take: every labelled action starts an
// action, and when the next labelled action starts restSeconds or more after
// one ends, the rest between them is an idle action (the project rule: SegmentationParams::idleSeconds) of its own (its first
// frame is a cut too). Cuts closer than 0.25 s keep the earlier one.
inline std::vector<int> trueCuts(const std::vector<LabelledAction>& actions, int frames, double fps,
                                 double restSeconds = 0.75) {
    std::vector<int> cuts;
    for (std::size_t i = 0; i < actions.size(); ++i) {
        if (actions[i].first > 0) cuts.push_back(actions[i].first);
        const int next = i + 1 < actions.size() ? actions[i + 1].first : frames;
        if (actions[i].last + 1 < frames && next - actions[i].last - 1 >= restSeconds * fps) {
            cuts.push_back(actions[i].last + 1);
        }
    }
    std::sort(cuts.begin(), cuts.end());
    std::vector<int> out;
    for (int c : cuts) {
        if (out.empty() || c - out.back() >= 0.25 * fps) out.push_back(c);
    }
    return out;
}

}  // namespace fray::test
