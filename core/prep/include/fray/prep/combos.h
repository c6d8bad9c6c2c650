#pragma once
// Action combination table (SPEC 1.6): how suitable my action is while the
// opponent performs theirs. Either side names an action ("jab") or an
// annotation ("@punch"). Positive values encourage, negative discourage.
// CSV form: "mine,theirs,suitability" with a header line.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"

namespace fray::prep {

// Suitabilities are finite and within +-kMaxSuitability.
inline constexpr double kMaxSuitability = 1e6;

struct ComboRecord {
    std::string mine;    // action name, or "@annotation"
    std::string theirs;  // action name, or "@annotation"
    double suitability = 0.0;
    friend bool operator==(const ComboRecord&, const ComboRecord&) = default;
};

class ComboTable {
public:
    const std::vector<ComboRecord>& records() const { return records_; }
    // Adds or replaces the record of (mine, theirs). Returns the previous value.
    std::optional<double> set(const ComboRecord& record);
    // Removes (mine, theirs); returns the removed record.
    std::optional<ComboRecord> remove(std::string_view mine, std::string_view theirs);
    std::optional<double> find(std::string_view mine, std::string_view theirs) const;

    // Suitability of performing an action (name + annotations) against an
    // opponent action: the exact pair wins, else the sum over the matching
    // annotation-level records (name-vs-annotation and annotation pairs).
    double query(std::string_view myName, const std::vector<std::string>& myAnnotations, std::string_view theirName,
                 const std::vector<std::string>& theirAnnotations) const;

    // An action name or "@annotation": letters, digits, '_', '-', '.'; 1..64 characters.
    static bool validKey(std::string_view key);

    // A record about to enter a project: both keys valid, every @annotation
    // in the vocabulary, the suitability finite and within +-kMaxSuitability.
    // The error names the field ("theirs: @pnuch is not in the project
    // vocabulary (...)") for the caller to prefix with its file or command.
    static Status checkRecord(const ComboRecord& record, const std::vector<std::string>& vocabulary);

    std::string toCsv() const;
    // Errors name the file, the line and the field. With a vocabulary, every
    // record is also checked as checkRecord does.
    static Result<ComboTable> fromCsv(std::string_view text, std::string_view fileName,
                                      const std::vector<std::string>* vocabulary = nullptr);
    friend bool operator==(const ComboTable&, const ComboTable&) = default;

private:
    std::vector<ComboRecord> records_;
};

}  // namespace fray::prep
