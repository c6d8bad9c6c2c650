#include "fray/prep/combos.h"

#include <algorithm>
#include <charconv>
#include <utility>
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

Status ComboTable::checkRecord(const ComboRecord& r, const std::vector<std::string>& vocabulary) {
    using Field = std::pair<const char*, const std::string*>;
    for (const auto& [field, key] : {Field{"mine", &r.mine}, Field{"theirs", &r.theirs}}) {
        if (!validKey(*key)) {
            return makeError(std::string(field) + ": \"" + csv::printable(*key) + "\" is not an action name or @annotation");
        }
        if (key->front() == '@' && std::find(vocabulary.begin(), vocabulary.end(), key->substr(1)) == vocabulary.end()) {
            std::string words;
            for (const auto& w : vocabulary) words += (words.empty() ? "" : ", ") + w;
            return makeError(std::string(field) + ": " + *key + " is not in the project vocabulary (" + words + ")");
        }
    }
    if (!std::isfinite(r.suitability) || std::abs(r.suitability) > kMaxSuitability) {
        return makeError("suitability: must be a finite number between -1e6 and 1e6");
    }
    return {};
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

Result<ComboTable> ComboTable::fromCsv(std::string_view text, std::string_view fileName,
                                       const std::vector<std::string>* vocabulary) {
    ComboTable table;
    if (const auto why = csv::notText(text); !why.empty()) return makeError(std::string(fileName) + ": " + why);
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
                                 csv::printable(cells[static_cast<std::size_t>(i)]) +
                                 "\" is not an action name or @annotation");
            }
        }
        double v = 0.0;
        const auto c = cells[2];
        const auto [p, ec] = std::from_chars(c.data(), c.data() + c.size(), v);
        if (ec != std::errc() || p != c.data() + c.size() || !std::isfinite(v)) {
            return makeError(where + "suitability: \"" + csv::printable(c, 32) + "\" is not a number");
        }
        const ComboRecord record{std::string(cells[0]), std::string(cells[1]), v};
        if (std::abs(v) > kMaxSuitability) return makeError(where + "suitability: must be between -1e6 and 1e6");
        if (vocabulary) {
            if (auto st = checkRecord(record, *vocabulary); !st) return makeError(where + st.error().message);
        }
        if (table.find(cells[0], cells[1])) {
            return makeError(where + "row: the pair " + std::string(cells[0]) + " / " + std::string(cells[1]) +
                             " appears twice");
        }
        table.records_.push_back(record);
    }
    if (!header) return makeError(std::string(fileName) + ": empty combination table (no header)");
    return table;
}

}  // namespace fray::prep
