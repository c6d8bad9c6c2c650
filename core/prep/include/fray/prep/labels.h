#pragma once
// User-labelled foot contacts: the training data of the SVM (SPEC 1.3). The
// animator marks, over a frame range of one motion, whether each foot is
// supporting the body. A labels file is CSV:
//
//   # comment
//   motion,first_frame,last_frame,left,right
//   walk_01,120,480,1,0
//
// "motion" is the motion's id in the project (or its file stem); frames are
// inclusive; left/right are 1 (supporting), 0 (not) or "-" (not labelled).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"

namespace fray::prep {

struct ContactLabel {
    int firstFrame = 0;  // inclusive
    int lastFrame = 0;   // inclusive
    std::optional<bool> left;
    std::optional<bool> right;
    int frameCount() const { return lastFrame - firstFrame + 1; }
    friend bool operator==(const ContactLabel&, const ContactLabel&) = default;
};

struct LabelRow {
    std::string motion;
    ContactLabel label;
    int line = 0;  // line in the labels file (0 when not read from one)
};

// Parses a labels file; errors name the file, the line and the field.
Result<std::vector<LabelRow>> parseLabelsCsv(std::string_view text, std::string_view fileName);
std::string labelsToCsv(const std::vector<LabelRow>& rows);

// Per-frame labels of one motion: -1 unlabelled, 0 free, 1 supporting.
struct FrameLabels {
    std::vector<std::int8_t> left;
    std::vector<std::int8_t> right;
};
// Expands ranges; fails naming the range when it is outside [0, frameCount).
Result<FrameLabels> expandLabels(const std::vector<ContactLabel>& labels, int frameCount);

}  // namespace fray::prep
