#pragma once
// The small CSV dialect of the labels and combination-table files: one record
// per line, comma-separated cells with surrounding blanks trimmed, blank lines
// and lines starting with '#' skipped, CRLF accepted. No quoting (no cell
// needs a comma). A UTF-8 byte-order mark at the start is skipped (some
// spreadsheets write one). Cell text quoted in an error goes through
// printable() so binary content never reaches the terminal raw.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "fray/prep/json_reader.h"

namespace fray::prep::csv {

inline std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

// At most maxBytes of s for an error message: control characters (and, when s
// is not UTF-8, every byte above 0x7F) become '?'.
inline std::string printable(std::string_view s, std::size_t maxBytes = 64) {
    s = s.substr(0, maxBytes);
    const bool utf8 = isValidUtf8(s);
    std::string out;
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        out += (c < 0x20 || c == 0x7F || (!utf8 && c >= 0x80)) ? '?' : ch;
    }
    return out;
}

// "" when text can be a CSV file; else why not (binary data).
inline std::string notText(std::string_view text) {
    if (text.find('\0') != std::string_view::npos) return "is not a text file (it contains NUL bytes)";
    return "";
}

// Walks the records of a text; line() is the 1-based line of the current one.
class Reader {
public:
    explicit Reader(std::string_view text) : text_(text) {
        if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
    }

    // Moves to the next record; false at the end.
    bool next() {
        while (pos_ < text_.size()) {
            const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
            line_ = trim(text_.substr(pos_, end - pos_));
            pos_ = end + 1;
            ++lineNo_;
            if (line_.empty() || line_.front() == '#') continue;
            cells_.clear();
            std::size_t start = 0;
            for (std::size_t i = 0; i <= line_.size(); ++i) {
                if (i == line_.size() || line_[i] == ',') {
                    cells_.push_back(trim(line_.substr(start, i - start)));
                    start = i + 1;
                }
            }
            return true;
        }
        return false;
    }
    int line() const { return lineNo_; }
    std::string_view text() const { return line_; }
    const std::vector<std::string_view>& cells() const { return cells_; }

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    int lineNo_ = 0;
    std::string_view line_;
    std::vector<std::string_view> cells_;
};

}  // namespace fray::prep::csv
