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
Status retargetCharacters(SampledScene& scene, const RetargetTarget& rig, std::vector<std::string>& notes);

// Adds a root bone above the skeleton's root (see RootMotion). Its name is
// kRootBoneName, or "fray_root" when that is taken. The old root keeps its
// position channels and gets a zero rest offset (no capsule from the floor).
void addRootBone(Motion& motion, RootMotion mode);

}  // namespace fray::exporter
