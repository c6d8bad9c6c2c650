#pragma once
// What `export --rig` and `--root-motion` do to a sampled scene before the
// writers see it (docs/EXPORT.md).
#include <string>
#include <vector>

#include "fray/core/retarget.h"
#include "fray/export/export.h"
#include "sampled_scene.h"

namespace fray::exporter {

// Every character retargeted onto the rig's skeleton (feet held through the
// contacts found on the sampled motion). One note per character says what
// was mapped and dropped. A character without feet or legs (a rat) keeps its
// own skeleton, with a note naming what is missing; when no character can be
// retargeted, that is the error.
// `retargeted` (when given) gets 1 per character that was.
Status retargetCharacters(SampledScene& scene, const RetargetTarget& rig, std::vector<std::string>& notes,
                          std::vector<char>* retargeted = nullptr);

// Hits land on the bodies as in the scene: at each hit by a retargeted
// attacker's forearm, shin or foot, a two-bone IK on that limb (eased over
// 0.2 s either side) brings the striking tip (hand, ankle, toe) onto the
// nearest point of the defender's body (its capsules), where the new
// proportions left it short or past. Returns the hits moved.
int landHits(SampledScene& sampled, const sim::Scene& scene, const std::vector<char>& retargeted);

// Adds a root bone above the skeleton's root (see RootMotion). Its name is
// kRootBoneName, or "fray_root" when that is taken. The old root keeps its
// position channels; its rest offset is its height at the first frame (no
// capsule is drawn from the floor: fray::bodyCapsules skips bones above the pelvis).
void addRootBone(Motion& motion, RootMotion mode);

}  // namespace fray::exporter
