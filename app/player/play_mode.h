#pragma once
// A live mode of fray-play, played frame by frame on the Interaction Graph:
// the duel and team fight (duel.h) and the two carriers (carry_play.h).
// main.cpp drives whichever the command line chose through this interface.
#include <chrono>
#include <cstdint>
#include <span>

#include "fray/core/result.h"
#include "fray/render/camera.h"
#include "fray/render/frame.h"

struct GLFWwindow;

namespace fray::player {

class PlayMode {
public:
    virtual ~PlayMode() = default;

    // One frame: keyboard and gamepad (keyboard: the UI does not want it),
    // the script's due events, dt s of play, policy swaps, posing. Returns an
    // error when building the graph failed.
    virtual Status update(double dt, GLFWwindow* window, bool keyboard) = 0;
    // The panel's contents (inside the caller's ImGui window), and the label
    // of the button that frames the characters.
    virtual void overlay() = 0;
    virtual const char* frameButton() const = 0;
    // The characters as posed by the last update (empty until the graph is ready).
    virtual std::span<const render::CharacterInstance> shown() const = 0;
    // Lines to draw on the floor (paths, arrows).
    virtual std::span<const render::Polyline> lines() const { return {}; }
    // What to frame: the characters (a default box until they are there),
    // with the room around them the mode wants in view.
    virtual render::Bounds framing() const = 0;
    // How far the characters' centre moved in the last update (for a camera that follows).
    virtual glm::vec3 moved() const = 0;
    virtual bool ready() const = 0;
    // Play time (s), and a line for a counted run's report: "match at 9.983 s; ...".
    virtual double time() const = 0;
    virtual std::string summary() const = 0;
    // Writes the log (--log) of what happened.
    virtual Status writeLog() const = 0;
};

// Wall-clock seconds an update spends with the play (steps, policy swaps,
// posing): mean and worst a frame.
class UpdateClock {
public:
    void add(double seconds) {
        total_ += seconds;
        worst_ = seconds > worst_ ? seconds : worst_;
        ++count_;
    }
    double mean() const { return count_ > 0 ? total_ / static_cast<double>(count_) : 0.0; }
    double worst() const { return worst_; }

private:
    double total_ = 0, worst_ = 0;
    std::int64_t count_ = 0;
};

// The characters' centre on the floor from frame to frame, for a camera
// that follows them; reset() when a new match or run starts.
class FollowCentre {
public:
    void reset() { have_ = false; }
    void to(const render::Bounds& b) {
        const glm::vec3 now = b.empty() ? glm::vec3(0.0f) : glm::vec3(b.center().x, 0.0f, b.center().z);
        moved_ = have_ ? now - centre_ : glm::vec3(0.0f);
        centre_ = now;
        have_ = true;
    }
    glm::vec3 moved() const { return moved_; }

private:
    glm::vec3 centre_{0.0f}, moved_{0.0f};
    bool have_ = false;
};

// A box about the origin, 3 m across and 1.8 m tall: what to frame before
// the characters are there.
inline render::Bounds framingPlaceholder() {
    render::Bounds b;
    b.add(glm::vec3(-1.5f, 0.0f, -1.5f));
    b.add(glm::vec3(1.5f, 1.8f, 1.5f));
    return b;
}

}  // namespace fray::player
