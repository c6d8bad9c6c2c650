#pragma once
// Little helpers for Fray's binary files (the patch library, the Interaction
// Graph): values written as their bytes, LEB128 counts, and a reader that
// never reads past its input: any short or malformed read sets `bad` and
// returns zeros, so a loader checks `bad` once per section.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace fray {

struct ByteWriter {
    std::string out;
    template <class T>
    void put(T v) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        out.append(b, sizeof(T));
    }
    // LEB128.
    void var(std::uint64_t v) {
        while (v >= 0x80) {
            out.push_back(static_cast<char>(0x80 | (v & 0x7f)));
            v >>= 7;
        }
        out.push_back(static_cast<char>(v));
    }
    void str(const std::string& s) {
        put(static_cast<std::uint32_t>(s.size()));
        out += s;
    }
};

struct ByteReader {
    std::string_view in;
    std::size_t at = 0;
    bool bad = false;

    template <class T>
    T get() {
        T v{};
        if (bad || in.size() - at < sizeof(T)) {
            bad = true;
            return v;
        }
        std::memcpy(&v, in.data() + at, sizeof(T));
        at += sizeof(T);
        return v;
    }
    // LEB128, at most 64 bits, in its shortest form (so what loads saves the same).
    std::uint64_t var() {
        std::uint64_t v = 0;
        for (int shift = 0; shift < 64 && !bad; shift += 7) {
            const auto byte = get<std::uint8_t>();
            if (bad) break;
            v |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
            if ((byte & 0x80) == 0) {
                if (byte == 0 && shift > 0) bad = true;  // padded
                if (shift == 63 && byte > 1) bad = true;  // beyond 64 bits
                return v;
            }
        }
        bad = true;
        return 0;
    }
    bool fits(std::uint64_t n, std::size_t minBytes) {
        if (bad || n > (in.size() - at) / std::max<std::size_t>(minBytes, 1)) bad = true;
        return !bad;
    }
    // A count of items that each take at least minBytes: refuses counts the input cannot hold.
    std::size_t count(std::size_t minBytes) {
        const auto n = get<std::uint32_t>();
        return fits(n, minBytes) ? n : 0;
    }
    std::size_t varCount(std::size_t minBytes) {
        const auto n = var();
        return fits(n, minBytes) ? static_cast<std::size_t>(n) : 0;
    }
    std::string str() {
        const std::size_t n = count(1);
        if (bad) return {};
        std::string s(in.substr(at, n));
        at += n;
        return s;
    }
};

}  // namespace fray
