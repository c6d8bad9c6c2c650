#pragma once
// fray-play --duel / --teams: the user steers a boxer against characters
// driven by the Interaction Graph (docs/IGRAPH.md, "fray-play duel"). The
// graph is read from its file (built in the background, with progress, when
// it is missing or stale, and kept as the cache); the opponents' policy is
// recomputed in the background when its style or depth changes while the old
// one keeps playing. Keyboard, gamepad (GLFW's gamepad mapping) and a script
// of timed commands (duel_script.h) steer character 0.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fray/core/result.h"
#include "fray/render/camera.h"
#include "fray/render/frame.h"
#include "play_mode.h"

struct GLFWwindow;

namespace fray::player {

struct DuelOptions {
    std::string project;         // *.frayproj
    std::string graph;           // the graph file ("": PROJECT.igraph)
    int characters = 2;          // 2: a duel; more: two teams
    std::string style = "general";  // the opponents' style
    int depth = 3;               // the opponents' policy depth
    std::string input;           // a script of timed commands ("": none)
    std::string log;             // where to write what happened, as JSON ("": nowhere)
    std::int64_t graphStates = 80000;  // size of a graph built here
    std::uint64_t seed = 1;
    bool foreground = false;     // build a missing graph before returning (scripted runs)
    bool quiet = false;          // no progress on stderr
};

class Duel final : public PlayMode {
public:
    // Opens the project, checks the script and reads the graph (or starts
    // building it). Errors: the project, a project without attacks, a script
    // line, a file at the graph's place that is not a graph.
    static Result<std::unique_ptr<Duel>> open(const DuelOptions& options);
    ~Duel() override;
    Duel(const Duel&) = delete;
    Duel& operator=(const Duel&) = delete;

    Status update(double dt, GLFWwindow* window, bool keyboard) override;
    void overlay() override;
    const char* frameButton() const override;
    std::span<const render::CharacterInstance> shown() const override;
    render::Bounds framing() const override;
    glm::vec3 moved() const override;
    bool ready() const override;
    double time() const override;
    // "match at T s; match steps and posing M ms a frame (worst W ms)": wall
    // clock update() spent with the match (steps, policy swaps, posing).
    std::string summary() const override;
    // Writes the log (options.log) of actions, commands, hits and policies.
    Status writeLog() const override;

private:
    Duel();
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace fray::player
