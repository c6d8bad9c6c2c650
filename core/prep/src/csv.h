#pragma once
// The small CSV dialect of the labels and combination-table files: one record
// per line, comma-separated cells with surrounding blanks trimmed, blank lines
// and lines starting with '#' skipped, CRLF accepted. No quoting (no cell
// needs a comma).
#include <string_view>
#include <vector>

namespace fray::prep::csv {

inline std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

// Walks the records of a text; line() is the 1-based line of the current one.
class Reader {
public:
    explicit Reader(std::string_view text) : text_(text) {}

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
