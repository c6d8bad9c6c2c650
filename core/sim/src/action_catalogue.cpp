#include "fray/sim/action_catalogue.h"

namespace fray::sim {

std::uint32_t actionFlags(const std::vector<std::string>& annotations) {
    std::uint32_t f = 0;
    for (const auto& a : annotations) {
        if (a == "punch") f |= kPunch;
        else if (a == "kick") f |= kKick;
        else if (a == "block") f |= kBlock;
        else if (a == "avoid" || a == "dodge") f |= kAvoid;
        else if (a == "pushed") f |= kPushed;
        else if (a == "falling") f |= kFalling;
        else if (a == "step") f |= kStep;
        else if (a == "idle") f |= kIdle;
        else if (a == "walk") f |= kWalk;
        else if (a == "run") f |= kRun;
        else if (a == "turn") f |= kTurn;
        else if (a == "transition") f |= kTransition;
        else if (a == "tackle") f |= kTackle;
    }
    return f;
}

ActionLibrary projectCatalogue(const prep::Project& project) {
    std::vector<LibraryAction> actions;
    for (std::size_t m = 0; m < project.motions.size(); ++m) {
        const auto& motion = project.motions[m];
        for (const auto& info : motion.actions.actions) {
            LibraryAction a;
            a.motion = static_cast<int>(m);
            a.motionId = motion.id;
            a.name = info.name;
            a.annotations = info.annotations;
            a.flags = actionFlags(info.annotations);
            actions.push_back(std::move(a));
        }
    }
    return ActionLibrary::catalogue(std::move(actions), project.vocabulary);
}

}  // namespace fray::sim
