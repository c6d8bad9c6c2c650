#include "fray/prep/json_reader.h"

#include <algorithm>

namespace fray::prep {

std::string lineColumn(std::string_view text, std::size_t offset) {
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i < std::min(offset, text.size()); ++i) {
        if (text[i] == '\n') ++line, col = 1;
        else ++col;
    }
    return std::to_string(line) + ":" + std::to_string(col);
}

namespace {

// Byte offset where the nesting first goes past maxDepth, or npos. Brackets
// inside strings do not count; a malformed document is left to the parser.
std::size_t tooDeepAt(std::string_view text, int maxDepth) {
    int depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i;
            else if (c == '"') inString = false;
            continue;
        }
        if (c == '"') inString = true;
        else if (c == '[' || c == '{') {
            if (++depth > maxDepth) return i;
        } else if (c == ']' || c == '}') {
            depth = std::max(0, depth - 1);
        }
    }
    return std::string_view::npos;
}

// nlohmann's message without its "[json.exception.parse_error.101] parse
// error at line 1, column 5: " prefix (the position is reported our way).
std::string shortMessage(const std::string& what) {
    std::string s = what;
    if (const auto close = s.find("] "); close != std::string::npos && s.front() == '[') s = s.substr(close + 2);
    if (s.rfind("parse error", 0) == 0) {
        if (const auto colon = s.find(": "); colon != std::string::npos) s = s.substr(colon + 2);
    }
    return s.substr(0, 160);
}

}  // namespace

Result<nlohmann::ordered_json> parseJson(std::string_view text, std::string_view fileName) {
    const std::string file(fileName);
    if (text.size() > kMaxJsonBytes) {
        return makeError(file + ": " + std::to_string(text.size()) + " bytes of JSON is more than the limit of " +
                         std::to_string(kMaxJsonBytes));
    }
    if (const auto at = tooDeepAt(text, kMaxJsonDepth); at != std::string_view::npos) {
        return makeError(file + ":" + lineColumn(text, at) + ": nested deeper than " + std::to_string(kMaxJsonDepth) +
                         " levels of [ ] and { }");
    }
    try {
        return nlohmann::ordered_json::parse(text.begin(), text.end());
    } catch (const nlohmann::ordered_json::parse_error& e) {
        return makeError(file + ":" + lineColumn(text, e.byte == 0 ? 0 : e.byte - 1) + ": not valid JSON (" +
                         shortMessage(e.what()) + ")");
    } catch (const nlohmann::ordered_json::exception& e) {  // e.g. a number too large for a double
        return makeError(file + ": not valid JSON (" + shortMessage(e.what()) + ")");
    }
}

std::string dumpJson(const nlohmann::ordered_json& j, int indent) {
    return j.dump(indent, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

bool isValidUtf8(std::string_view s) {
    std::size_t i = 0;
    while (i < s.size()) {
        const auto c = static_cast<unsigned char>(s[i]);
        int extra = 0;
        std::uint32_t cp = 0;
        if (c < 0x80) {
            ++i;
            continue;
        } else if ((c & 0xE0) == 0xC0) {
            extra = 1, cp = c & 0x1F;
        } else if ((c & 0xF0) == 0xE0) {
            extra = 2, cp = c & 0x0F;
        } else if ((c & 0xF8) == 0xF0) {
            extra = 3, cp = c & 0x07;
        } else {
            return false;
        }
        if (i + static_cast<std::size_t>(extra) >= s.size()) return false;
        for (int k = 1; k <= extra; ++k) {
            const auto d = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
            if ((d & 0xC0) != 0x80) return false;
            cp = (cp << 6) | (d & 0x3F);
        }
        static const std::uint32_t kMin[] = {0, 0x80, 0x800, 0x10000};
        if (cp < kMin[extra] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
        i += static_cast<std::size_t>(extra) + 1;
    }
    return true;
}

}  // namespace fray::prep
