#include "fray/prep/labels.h"

#include <charconv>
#include <sstream>

#include "csv.h"

namespace fray::prep {

Result<std::vector<LabelRow>> parseLabelsCsv(std::string_view text, std::string_view fileName) {
    static const char* const kFields[] = {"motion", "first_frame", "last_frame", "left", "right"};
    std::vector<LabelRow> rows;
    if (const auto why = csv::notText(text); !why.empty()) return makeError(std::string(fileName) + ": " + why);
    bool header = false;
    csv::Reader reader(text);
    while (reader.next()) {
        const int lineNo = reader.line();
        const std::string_view line = reader.text();
        const auto& cells = reader.cells();
        const auto where = [&](std::string_view field) {
            return std::string(fileName) + ":" + std::to_string(lineNo) + ": " + std::string(field);
        };
        if (!header) {
            header = true;
            if (cells.size() != 5 || cells[0] != "motion") {
                return makeError(where("header") +
                                 ": expected \"motion,first_frame,last_frame,left,right\", found \"" +
                                 csv::printable(line, 80) + "\"");
            }
            for (std::size_t i = 0; i < 5; ++i) {
                if (cells[i] != kFields[i]) {
                    return makeError(where("header") + ": column " + std::to_string(i + 1) + " must be \"" +
                                     kFields[i] + "\", found \"" + csv::printable(cells[i]) + "\"");
                }
            }
            continue;
        }
        if (cells.size() != 5) {
            return makeError(where("row") + ": expected 5 comma-separated fields, found " +
                             std::to_string(cells.size()));
        }
        LabelRow row;
        row.line = lineNo;
        row.motion = std::string(cells[0]);
        if (row.motion.empty()) return makeError(where("motion") + ": empty motion name");
        if (csv::printable(row.motion, row.motion.size()) != row.motion) {
            return makeError(where("motion") + ": \"" + csv::printable(row.motion) +
                             "\" is not a motion id (control characters or bytes that are not UTF-8)");
        }
        for (int i = 1; i <= 2; ++i) {
            const auto c = cells[static_cast<std::size_t>(i)];
            int v = 0;
            const auto [p, ec] = std::from_chars(c.data(), c.data() + c.size(), v);
            if (ec != std::errc() || p != c.data() + c.size()) {
                return makeError(where(kFields[i]) + ": \"" + csv::printable(c) + "\" is not a frame number");
            }
            if (v < 0) return makeError(where(kFields[i]) + ": frame " + std::to_string(v) + " is negative");
            (i == 1 ? row.label.firstFrame : row.label.lastFrame) = v;
        }
        if (row.label.lastFrame < row.label.firstFrame) {
            return makeError(where("last_frame") + ": " + std::to_string(row.label.lastFrame) +
                             " is before first_frame " + std::to_string(row.label.firstFrame));
        }
        for (int i = 3; i <= 4; ++i) {
            const auto c = cells[static_cast<std::size_t>(i)];
            std::optional<bool> v;
            if (c == "1") v = true;
            else if (c == "0") v = false;
            else if (c != "-" && !c.empty()) {
                return makeError(where(kFields[i]) + ": \"" + csv::printable(c) + "\" must be 1, 0 or -");
            }
            (i == 3 ? row.label.left : row.label.right) = v;
        }
        if (!row.label.left && !row.label.right) {
            return makeError(where("left") + ": the row labels neither foot");
        }
        rows.push_back(std::move(row));
    }
    if (!header) return makeError(std::string(fileName) + ": empty labels file (no header)");
    return rows;
}

std::string labelsToCsv(const std::vector<LabelRow>& rows) {
    std::ostringstream out;
    out << "motion,first_frame,last_frame,left,right\n";
    auto cell = [](const std::optional<bool>& v) { return v ? (*v ? "1" : "0") : "-"; };
    for (const auto& r : rows) {
        out << r.motion << ',' << r.label.firstFrame << ',' << r.label.lastFrame << ',' << cell(r.label.left) << ','
            << cell(r.label.right) << '\n';
    }
    return out.str();
}

Result<FrameLabels> expandLabels(const std::vector<ContactLabel>& labels, int frameCount) {
    FrameLabels out;
    out.left.assign(static_cast<std::size_t>(std::max(0, frameCount)), -1);
    out.right = out.left;
    for (std::size_t i = 0; i < labels.size(); ++i) {
        const auto& l = labels[i];
        if (l.firstFrame < 0 || l.lastFrame >= frameCount || l.lastFrame < l.firstFrame) {
            return makeError("label " + std::to_string(i + 1) + " covers frames " + std::to_string(l.firstFrame) +
                             ".." + std::to_string(l.lastFrame) + " but the motion has frames 0.." +
                             std::to_string(frameCount - 1));
        }
        for (int f = l.firstFrame; f <= l.lastFrame; ++f) {
            if (l.left) out.left[static_cast<std::size_t>(f)] = *l.left ? 1 : 0;
            if (l.right) out.right[static_cast<std::size_t>(f)] = *l.right ? 1 : 0;
        }
    }
    return out;
}

}  // namespace fray::prep
