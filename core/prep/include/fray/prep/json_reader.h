#pragma once
// Reading JSON documents with errors that name the file and the JSON pointer
// of the bad field ("demo.frayproj: /motions/2/cuts/5: must be an integer").
// Shared by the project file, scene specs and scene files. Consumers link
// nlohmann_json themselves.
//
// parseJson is the one way in: it bounds the size and the nesting depth of a
// document (so no later recursive copy, dump or destruction can exhaust the
// stack) and reports syntax errors with line and column.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "fray/core/result.h"

namespace fray::prep {

// Limits of every JSON document Fray reads (docs/FILES.md).
inline constexpr int kMaxJsonDepth = 64;
inline constexpr std::size_t kMaxJsonBytes = std::size_t{256} << 20;  // 256 MiB

// "line:column" (1-based) of a byte offset in text.
std::string lineColumn(std::string_view text, std::size_t offset);

// Parses a whole document. Errors: "FILE:LINE:COL: not valid JSON (...)",
// "FILE:LINE:COL: nested deeper than 64 levels", "FILE: ... larger than ...".
Result<nlohmann::ordered_json> parseJson(std::string_view text, std::string_view fileName);

// Serialises without throwing: bytes that are not UTF-8 (a joint name from a
// Latin-1 capture) become U+FFFD instead of an exception.
std::string dumpJson(const nlohmann::ordered_json& j, int indent = -1);

// True when s is well-formed UTF-8.
bool isValidUtf8(std::string_view s);

// Reading with JSON-pointer error paths. Every accessor checks the type and
// returns an Error naming the path.
class JsonReader {
public:
    using json = nlohmann::ordered_json;

    explicit JsonReader(std::string_view file) : file_(file) {}

    Error error(const std::string& path, const std::string& problem) const {
        return makeError(file_ + ": " + (path.empty() ? "/" : path) + ": " + problem);
    }
    Result<const json*> field(const json& obj, const std::string& path, const char* key, bool required = true) const {
        const auto it = obj.find(key);
        if (it == obj.end()) {
            if (!required) return static_cast<const json*>(nullptr);
            return error(path + "/" + key, "missing");
        }
        return &*it;
    }
    Result<std::string> string(const json& v, const std::string& path) const {
        if (!v.is_string()) return error(path, "must be a string");
        return v.get<std::string>();
    }
    Result<int> integer(const json& v, const std::string& path) const {
        if (!v.is_number_integer()) return error(path, "must be an integer");
        const auto x = v.get<std::int64_t>();
        if (x < -(1LL << 31) || x >= (1LL << 31)) return error(path, "is out of range");
        return static_cast<int>(x);
    }
    Result<double> number(const json& v, const std::string& path) const {
        if (!v.is_number()) return error(path, "must be a number");
        const double x = v.get<double>();
        if (!std::isfinite(x)) return error(path, "must be a finite number");
        return x;
    }
    // A number within [lo, hi]; the error names both bounds.
    Result<double> numberIn(const json& v, const std::string& path, double lo, double hi) const {
        auto x = number(v, path);
        if (!x) return x;
        if (*x < lo || *x > hi) return error(path, "must be between " + fmt(lo) + " and " + fmt(hi) + " (is " + fmt(*x) + ")");
        return x;
    }
    Result<bool> boolean(const json& v, const std::string& path) const {
        if (!v.is_boolean()) return error(path, "must be true or false");
        return v.get<bool>();
    }
    // A required member read as one type: obj[key] at path/key.
    Result<std::string> stringAt(const json& obj, const std::string& path, const char* key) const {
        return member(obj, path, key, &JsonReader::string);
    }
    Result<int> integerAt(const json& obj, const std::string& path, const char* key) const {
        return member(obj, path, key, &JsonReader::integer);
    }
    Result<double> numberAt(const json& obj, const std::string& path, const char* key) const {
        return member(obj, path, key, &JsonReader::number);
    }
    Result<bool> booleanAt(const json& obj, const std::string& path, const char* key) const {
        return member(obj, path, key, &JsonReader::boolean);
    }
    Result<std::vector<std::string>> strings(const json& v, const std::string& path) const {
        if (!v.is_array()) return error(path, "must be an array of strings");
        std::vector<std::string> out;
        for (std::size_t i = 0; i < v.size(); ++i) {
            auto s = string(v[i], path + "/" + std::to_string(i));
            if (!s) return s.error();
            out.push_back(std::move(*s));
        }
        return out;
    }

    static std::string fmt(double x) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", x);
        return buf;
    }

private:
    template <class T>
    Result<T> member(const json& obj, const std::string& path, const char* key,
                     Result<T> (JsonReader::*read)(const json&, const std::string&) const) const {
        auto f = field(obj, path, key);
        if (!f) return f.error();
        return (this->*read)(**f, path + "/" + key);
    }

    std::string file_;
};

#define FRAY_TRY(var, expr)              \
    auto var##_r = (expr);               \
    if (!var##_r) return var##_r.error(); \
    auto var = std::move(*var##_r)

}  // namespace fray::prep
