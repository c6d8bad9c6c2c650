#pragma once
// American football (SPEC 4.5): a carrier runs for the goal line past
// tacklers that dive at it from {run, TACKLE, avoid} patches. Its part of a
// compose spec (kind "football") and of the compose stats.
#include <vector>

namespace fray::sim {

// From `time` on the carrier runs toward this floor heading (rad, 0 = +Z,
// straight at the goal line; the arrow on the floor).
struct RunDirection {
    double time = 0;
    double heading = 0;
};

// Tacklers coming in turn, the goal line this far along +Z (m) from the
// carrier's start, and the running direction over time.
struct FootballSpec {
    static constexpr const char* kKind = "football";
    int tacklers = 5;
    double goal = 40;
    std::vector<RunDirection> directions;
    // Two tacklers at once where a second tackle patch connects spatially to
    // the chosen one (the carrier's very same run and cut, the two tacklers
    // never meeting).
    bool doubles = false;
    // Carriers running at once (issue 27: crowds), each with its own
    // `tacklers`, composed in parallel and laid out side by side on the
    // floor, clear of each other ("runs" in the spec; run k uses seed + k).
    int runs = 1;
    // With several runs, each carrier's arrows are the directions above each
    // turned by up to this much either way (rad; "spread_deg" in the spec),
    // drawn from the run's seed, so the carriers do not all run alike.
    double spread = 0;
};

struct FootballStats {
    int graphJoined = 0;      // joined where the carrier's run continues in the motion graph
    int secondTacklers = 0;   // second tacklers joined beside a patch by a spatial connection
    int tacklersPassed = 0;   // tackles the carrier got away from
    double goalReached = -1;  // when the carrier crossed the goal line (s), -1 never
};

}  // namespace fray::sim
