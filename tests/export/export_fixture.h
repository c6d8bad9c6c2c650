#pragma once
// A short planned duel on the demo project, temporary folders, and a small
// glTF reader (JSON + buffer, accessors decoded as the spec says) so the tests
// check the files themselves, not the writer's intentions.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "fray/export/export.h"
#include "fray/sim/scene.h"
#include "sim/sim_fixture.h"
#include "temp_dir.h"

namespace fray::test {

namespace fs = std::filesystem;
using json = nlohmann::json;

// Two boxers, 6 s, depth 2: hits happen (the summary test needs some).
inline const sim::Scene& exportDuel() {
    static const sim::Scene scene = [] {
        auto s = runSpec(duelSpec(2, 2, 3, 6.0));
        if (!s) throw std::runtime_error(s.error().message);
        return std::move(*s);
    }();
    return scene;
}
inline const sim::ActionLibrary& exportLibrary() { return demoWorld().library; }

// A fresh folder for a test's exports.
struct TempFolder : TempDir {
    TempFolder() : TempDir("fray_export_test_") {}
};

inline std::string readBytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

inline exporter::ExportOptions optionsFor(exporter::Format format, const fs::path& dir, const std::string& name = "duel") {
    exporter::ExportOptions o;
    o.format = format;
    o.outDir = dir;
    o.name = name;
    o.source = "duel.frayscene";
    return o;
}

inline std::string decodeBase64(std::string_view text) {
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        if (c == '+') return 62;
        if (c == '/') return 63;
        return -1;
    };
    std::string out;
    std::uint32_t bits = 0;
    int n = 0;
    for (char c : text) {
        const int v = value(c);
        if (v < 0) break;  // '=' padding
        bits = (bits << 6) | static_cast<std::uint32_t>(v);
        n += 6;
        if (n >= 8) {
            n -= 8;
            out.push_back(static_cast<char>((bits >> n) & 0xffu));
        }
    }
    return out;
}

inline std::uint32_t le32(std::string_view b, std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(b[at + i])) << (8 * i);
    return v;
}

// A parsed glTF file: its JSON and its (single) buffer.
struct Gltf {
    json doc;
    std::string bin;

    static Gltf fromGltf(const std::string& text) {
        Gltf g;
        g.doc = json::parse(text);
        const std::string uri = g.doc["buffers"][0]["uri"];
        const std::string prefix = "data:application/octet-stream;base64,";
        if (uri.rfind(prefix, 0) != 0) throw std::runtime_error("buffer is not an embedded data URI");
        g.bin = decodeBase64(std::string_view(uri).substr(prefix.size()));
        return g;
    }
    static Gltf fromGlb(const std::string& bytes) {
        Gltf g;
        const std::uint32_t jsonLength = le32(bytes, 12);
        g.doc = json::parse(bytes.substr(20, jsonLength));
        const std::size_t binAt = 20 + jsonLength;
        g.bin = bytes.substr(binAt + 8, le32(bytes, binAt));
        return g;
    }

    static std::size_t components(const std::string& type) {
        if (type == "SCALAR") return 1;
        if (type == "VEC2") return 2;
        if (type == "VEC3") return 3;
        if (type == "VEC4") return 4;
        if (type == "MAT4") return 16;
        throw std::runtime_error("unexpected accessor type " + type);
    }
    static std::size_t componentBytes(int componentType) {
        switch (componentType) {
            case 5121: return 1;
            case 5123: return 2;
            case 5125:
            case 5126: return 4;
            default: throw std::runtime_error("unexpected component type");
        }
    }
    // Byte offset of element 0 and the element stride (tightly packed: no byteStride is written).
    std::size_t start(int accessor) const {
        const json& a = doc["accessors"][accessor];
        const json& v = doc["bufferViews"][a["bufferView"].get<int>()];
        return v.value("byteOffset", std::size_t{0}) + a.value("byteOffset", std::size_t{0});
    }
    std::size_t count(int accessor) const { return doc["accessors"][accessor]["count"]; }
    std::vector<float> floats(int accessor) const {
        const json& a = doc["accessors"][accessor];
        EXPECT_EQ(a["componentType"], 5126);
        std::vector<float> out(count(accessor) * components(a["type"]));
        std::memcpy(out.data(), bin.data() + start(accessor), out.size() * sizeof(float));
        return out;
    }
    std::vector<std::uint32_t> uints(int accessor) const {
        const json& a = doc["accessors"][accessor];
        const std::size_t bytes = componentBytes(a["componentType"]);
        std::vector<std::uint32_t> out(count(accessor) * components(a["type"]));
        for (std::size_t i = 0; i < out.size(); ++i) {
            std::uint32_t v = 0;
            std::memcpy(&v, bin.data() + start(accessor) + i * bytes, bytes);
            out[i] = v;
        }
        return out;
    }
};

inline Gltf exportGltf(exporter::Format format, const TempFolder& dir) {
    auto report = exporter::exportScene(exportDuel(), exportLibrary(), optionsFor(format, dir.path()));
    if (!report) throw std::runtime_error(report.error().message);
    const std::string bytes = readBytes(report->files.front());
    return format == exporter::Format::Glb ? Gltf::fromGlb(bytes) : Gltf::fromGltf(bytes);
}

}  // namespace fray::test
