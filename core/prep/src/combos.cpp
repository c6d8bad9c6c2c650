#include "fray/prep/combos.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "csv.h"

namespace fray::prep {

bool ComboTable::validKey(std::string_view s) {
    if (s.empty() || s.size() > 64) return false;
    const std::string_view body = s.front() == '@' ? s.substr(1) : s;
    return !body.empty() && std::all_of(body.begin(), body.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
               c == '.';
    });
}

std::optional<double> ComboTable::set(const ComboRecord& record) {
    for (auto& r : records_) {
        if (r.mine == record.mine && r.theirs == record.theirs) {
            const double old = r.suitability;
            r.suitability = record.suitability;
            return old;
        }
    }
    records_.push_back(record);
    return std::nullopt;
}

std::optional<ComboRecord> ComboTable::remove(std::string_view mine, std::string_view theirs) {
    for (auto it = records_.begin(); it != records_.end(); ++it) {
        if (it->mine == mine && it->theirs == theirs) {
            ComboRecord r = *it;
            records_.erase(it);
            return r;
        }
    }
    return std::nullopt;
}

std::optional<double> ComboTable::find(std::string_view mine, std::string_view theirs) const {
    for (const auto& r : records_) {
        if (r.mine == mine && r.theirs == theirs) return r.suitability;
    }
    return std::nullopt;
}

double ComboTable::query(std::string_view myName, const std::vector<std::string>& myAnnotations,
                         std::string_view theirName, const std::vector<std::string>& theirAnnotations) const {
    if (const auto exact = find(myName, theirName)) return *exact;
    auto matches = [](std::string_view key, std::string_view name, const std::vector<std::string>& annotations) {
        if (key.empty()) return false;
        if (key.front() != '@') return key == name;
        const std::string_view a = key.substr(1);
        return std::find(annotations.begin(), annotations.end(), a) != annotations.end();
    };
    double sum = 0.0;
    for (const auto& r : records_) {
        if (r.mine.front() != '@' && r.theirs.front() != '@') continue;  // exact pairs handled above
        if (matches(r.mine, myName, myAnnotations) && matches(r.theirs, theirName, theirAnnotations)) {
            sum += r.suitability;
        }
    }
    return sum;
}

std::string ComboTable::toCsv() const {
    std::ostringstream out;
    out.precision(17);
    out << "mine,theirs,suitability\n";
    for (const auto& r : records_) out << r.mine << ',' << r.theirs << ',' << r.suitability << '\n';
    return out.str();
}

Result<ComboTable> ComboTable::fromCsv(std::string_view text, std::string_view fileName) {
    ComboTable table;
    bool header = false;
    csv::Reader reader(text);
    while (reader.next()) {
        const std::string where = std::string(fileName) + ":" + std::to_string(reader.line()) + ": ";
        const auto& cells = reader.cells();
        if (!header) {
            header = true;
            if (cells.size() != 3 || cells[0] != "mine" || cells[1] != "theirs" || cells[2] != "suitability") {
                return makeError(where + "header: expected \"mine,theirs,suitability\"");
            }
            continue;
        }
        if (cells.size() != 3) {
            return makeError(where + "row: expected 3 comma-separated fields, found " + std::to_string(cells.size()));
        }
        for (int i = 0; i < 2; ++i) {
            if (!validKey(cells[static_cast<std::size_t>(i)])) {
                return makeError(where + (i == 0 ? "mine" : "theirs") + ": \"" +
                                 std::string(cells[static_cast<std::size_t>(i)].substr(0, 64)) +
                                 "\" is not an action name or @annotation");
            }
        }
        double v = 0.0;
        const auto c = cells[2];
        const auto [p, ec] = std::from_chars(c.data(), c.data() + c.size(), v);
        if (ec != std::errc() || p != c.data() + c.size() || !std::isfinite(v)) {
            return makeError(where + "suitability: \"" + std::string(c.substr(0, 32)) + "\" is not a number");
        }
        if (table.find(cells[0], cells[1])) {
            return makeError(where + "row: the pair " + std::string(cells[0]) + " / " + std::string(cells[1]) +
                             " appears twice");
        }
        table.records_.push_back({std::string(cells[0]), std::string(cells[1]), v});
    }
    if (!header) return makeError(std::string(fileName) + ": empty combination table (no header)");
    return table;
}

}  // namespace fray::prep
