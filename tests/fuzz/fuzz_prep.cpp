// libFuzzer target for the data-preparation parsers: the project file, the
// contact-labels CSV, the combination-table CSV and the binary cache. The
// first input byte picks the parser. They must return an error, never crash,
// hang or leak.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "fray/prep/combos.h"
#include "fray/prep/labels.h"
#include "fray/prep/pipeline.h"
#include "fray/prep/project.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    switch (data[0] % 4) {
        case 0: {
            auto p = fray::prep::projectFromJson(text, "fuzz.frayproj");
            if (p) {  // what loads must save, and load again unchanged
                auto again = fray::prep::projectFromJson(fray::prep::projectToJson(*p), "again.frayproj");
                if (!again || !(*again == *p)) __builtin_trap();
            }
            break;
        }
        case 1: {
            auto rows = fray::prep::parseLabelsCsv(text, "fuzz.csv");
            if (rows) {
                std::vector<fray::prep::ContactLabel> labels;
                for (const auto& r : *rows) labels.push_back(r.label);
                (void)fray::prep::expandLabels(labels, 5000);
            }
            break;
        }
        case 2:
            (void)fray::prep::ComboTable::fromCsv(text, "fuzz.csv");
            break;
        default:
            (void)fray::prep::deserializeCache(std::vector<std::uint8_t>(data + 1, data + size));
            break;
    }
    return 0;
}
