#pragma once
// fray-play --carry: two carriers of one long box following the user in real
// time on the Interaction Graph's collaborative policies (docs/IGRAPH.md,
// "fray-play --carry"). The user steers the desired direction of the box
// (keyboard, gamepad) or gives a path (--path circle:R | FILE); a changed
// reward weight or depth recomputes the eight direction policies in the
// background while the old ones keep playing. The carry graph is read from
// its file (PROJECT.carry.igraph), or built (in the background, with
// progress) when it is missing, stale or damaged, and kept there.
//
// --input FILE: timed events, one a line ("#" comments):
//   SECONDS forward | back | stop | turn-left | turn-right
//   SECONDS heading DEGREES        (the desired direction in the world, 0: +Z, 90: +X)
//   SECONDS set NAME=VALUE          (a reward weight: w_theta, w_d, w_v, speed, gamma)
//   SECONDS depth D                 (1-10)
// forward: go the desired direction; back: turn it round and go; stop: hold;
// turn-left / turn-right: turn it 45 degrees. Errors name the file and line.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"
#include "fray/render/camera.h"
#include "fray/render/frame.h"
#include "play_mode.h"

struct GLFWwindow;

namespace fray::player {

struct CarryPlayOptions {
    std::string project;            // *.frayproj (with the carry set's carry-end actions)
    std::string graph;              // the carry graph file ("": PROJECT.carry.igraph)
    std::string path;               // "": steered by the user; else circle:R or a path JSON file
    int depth = 3;                  // policy depth (1-10)
    std::string input, log;         // a script of timed events; where to write what happened (JSON)
    std::int64_t graphStates = 20000;  // size of a carry graph built here
    std::uint64_t seed = 1;
    bool foreground = false;        // build a missing graph before returning (scripted runs)
    bool quiet = false;
};

struct CarryEvent {
    enum class Kind { Forward, Back, Stop, TurnLeft, TurnRight, Heading, Set, Depth };
    double time = 0;
    int line = 0;
    Kind kind = Kind::Forward;
    double degrees = 0;  // Heading
    std::string edit;    // Set: NAME=VALUE
    int depth = 0;       // Depth
};
// Parses a carry script; fileName names it in errors ("FILE:LINE: ...").
Result<std::vector<CarryEvent>> parseCarryScript(std::string_view text, std::string_view fileName);

class CarryPlay final : public PlayMode {
public:
    static Result<std::unique_ptr<CarryPlay>> open(const CarryPlayOptions& options);
    ~CarryPlay() override;
    CarryPlay(const CarryPlay&) = delete;
    CarryPlay& operator=(const CarryPlay&) = delete;

    Status update(double dt, GLFWwindow* window, bool keyboard) override;
    void overlay() override;
    const char* frameButton() const override;
    std::span<const render::CharacterInstance> shown() const override;
    std::span<const render::Polyline> lines() const override;  // the path and the desired direction
    render::Bounds framing() const override;                   // with a metre to walk into
    glm::vec3 moved() const override;
    bool ready() const override;
    double time() const override;
    std::string summary() const override;
    Status writeLog() const override;

private:
    CarryPlay();
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace fray::player
