#include "fray/demo/demo_project.h"

#include <algorithm>

#include "fray/prep/contacts.h"

namespace fray::demo {

prep::Project makeDemoProject(const std::vector<ProjectTake>& takes) {
    prep::Project p = prep::makeProject("demo");
    // Five seconds labelled in four takes of different kinds: 20 s in all.
    const std::pair<const char*, double> labelled[] = {
        {"shadowbox_energetic", 20.0}, {"walking", 10.0}, {"running_around", 15.0}, {"falls", 5.0},
        // The football set: runs, cuts and a dive.
        {"football_1", 30.0}, {"football_2", 50.0}};
    for (const auto& t : takes) {
        prep::ProjectMotion m;
        m.id = t.truth.take;
        m.path = t.motionPath;
        m.actions = prep::MotionActions::whole(t.truth.frameCount);
        m.actions.actions.clear();
        for (std::size_t i = 0; i < t.truth.actions.size(); ++i) {
            const TruthAction& a = t.truth.actions[i];
            if (i > 0) m.actions.cuts.push_back(a.firstFrame);
            prep::ActionInfo info;
            info.name = a.name;
            info.annotations = a.annotations;
            info.joints = a.joints;
            info.attackDirection = a.attackDirection;
            info.defendedPart = a.defendedPart;
            m.actions.actions.push_back(std::move(info));
        }
        for (const auto& [take, start] : labelled) {
            if (t.truth.take == take) {
                const int first = static_cast<int>(start * t.truth.fps);
                m.contactLabels = prep::labelsFromContacts({t.truth.leftContact, t.truth.rightContact}, first,
                                                            first + static_cast<int>(5.0 * t.truth.fps) - 1);
            }
        }
        p.motions.push_back(std::move(m));
    }
    // The football set is runs, cuts and dives: at the default 0.2 clustering
    // splits the run cycle so finely that half the steps join only their own
    // continuation; 0.3 keeps the foot phases apart and joins the rest.
    const bool football = !takes.empty() && std::all_of(takes.begin(), takes.end(),
                                                         [](const ProjectTake& t) { return t.truth.kind == "football"; });
    if (football) p.settings.graphThreshold = 0.3;
    // A starter table (SPEC 1.6): avoid what is coming, do not attack into a fall.
    p.combos.set({"sway_back", "@punch", 1.0});
    p.combos.set({"sway_back", "uppercut_left", 2.0});
    p.combos.set({"sway_back", "uppercut_right", 2.0});
    p.combos.set({"duck", "hook_left", 2.0});
    p.combos.set({"duck", "hook_right", 2.0});
    p.combos.set({"slip_left", "jab", 1.5});
    p.combos.set({"slip_right", "cross", 1.5});
    p.combos.set({"block_high", "@punch", 1.0});
    p.combos.set({"block_low", "@kick", 1.0});
    p.combos.set({"@punch", "@falling", -1.0});
    p.combos.set({"@idle", "@punch", -1.0});
    return p;
}

}  // namespace fray::demo
