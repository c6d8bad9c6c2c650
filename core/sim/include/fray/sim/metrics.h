#pragma once
// Quality and outcome metrics of a scene (`fray-cli metrics`): per character
// the hits given and received, time to catch, distance to the opponent,
// path-following error, body penetration outside intended hits and foot
// skate, measured on the played-back scene (ScenePoser, transitions included).
#include <optional>
#include <string>
#include <vector>

#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"

namespace fray::sim {

struct CharacterMetrics {
    std::string name;
    int actions = 0;
    int hitsGiven = 0, hitsReceived = 0;        // successful (not blocked)
    int blockedGiven = 0, blockedReceived = 0;  // landed on a block
    double damageGiven = 0, damageReceived = 0; // sum of effector speeds (m/s)
    std::optional<double> timeToCatch;          // first catch it took part in (s)
    std::optional<double> meanOpponentDistance; // m, pelvis to pelvis
    std::optional<double> pathErrorMean, pathErrorMax;  // m, pelvis to its path polyline
    int penetrationFrames = 0;                  // samples with its body inside another's, outside intended hits
    double footSkateMean = 0, footSkateMax = 0; // cm per 60 Hz frame, feet in contact
    int forcedReactions = 0;
    std::int64_t fallbacks = 0;                 // decisions with no legal action (idle/guard taken)
};

struct SceneMetrics {
    double duration = 0;
    double sampleRate = 30;
    std::vector<CharacterMetrics> characters;
    int penetrationFrames = 0;       // samples where any two bodies penetrate outside intended hits
    int crossGroupPenetrations = 0;  // of which between characters of different groups
    struct Penetration {
        double time = 0;
        int a = 0, b = 0;
    };
    std::vector<Penetration> penetrations;  // the first kMaxListed samples, to find them
    static constexpr std::size_t kMaxListed = 100;
    int hits = 0, blocked = 0, attacks = 0;
    double hitRate = 0;              // successful hits / attacks launched
};

struct MetricsOptions {
    double sampleRate = 30;     // body tests
    double skateRate = 60;      // foot skate
    double hitWindow = 0.3;     // s around a hit where the two bodies may touch
};

SceneMetrics computeMetrics(const Scene& scene, const ActionLibrary& lib, const MetricsOptions& options = {});

std::string metricsToJson(const SceneMetrics& m);
std::string metricsToText(const SceneMetrics& m);

}  // namespace fray::sim
