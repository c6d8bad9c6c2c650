#include "fbx_writer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <utility>
#include <vector>

#include <assimp/Exporter.hpp>

#include "assimp_scene.h"
#include "fray/core/rotation.h"

namespace fray::exporter {
namespace {

constexpr float kCentimetresPerMetre = 100.0f;
constexpr std::size_t kHeaderBytes = 27;  // "Kaydara FBX Binary  \0\x1a\0" + uint32 version

std::uint64_t readLe(std::string_view b, std::size_t at, std::size_t bytes) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(b[at + i])) << (8 * i);
    return v;
}

struct Record {
    std::size_t end = 0;         // offset just past the record
    std::size_t properties = 0;  // offset of the first property
    std::size_t children = 0;    // offset of the first nested record
    std::string_view name;
};

bool isBinaryFbx(std::string_view b) { return b.size() >= kHeaderBytes && b.substr(0, 18) == "Kaydara FBX Binary"; }
// FBX 7.5 and later use 64-bit record headers.
std::size_t wordBytes(std::string_view b) { return readLe(b, 23, 4) >= 7500 ? 8 : 4; }

// The record at `at`, or nothing for a null record (the end of a list) or one
// that does not fit in [at, limit).
std::optional<Record> recordAt(std::string_view b, std::size_t at, std::size_t limit) {
    const std::size_t w = wordBytes(b);
    if (at + 3 * w + 1 > limit) return std::nullopt;
    const std::uint64_t end = readLe(b, at, w);
    const std::uint64_t propertyBytes = readLe(b, at + 2 * w, w);
    const std::size_t nameLen = static_cast<unsigned char>(b[at + 3 * w]);
    const std::size_t properties = at + 3 * w + 1 + nameLen;
    if (end == 0 || end > limit || properties > end || propertyBytes > end - properties) return std::nullopt;
    return Record{static_cast<std::size_t>(end), properties, properties + static_cast<std::size_t>(propertyBytes),
                  b.substr(at + 3 * w + 1, nameLen)};
}

std::optional<Record> findRecord(std::string_view b, std::size_t from, std::size_t limit, std::string_view name) {
    for (auto r = recordAt(b, from, limit); r; r = recordAt(b, r->end, limit)) {
        if (r->name == name) return r;
    }
    return std::nullopt;
}

// ---- repairing Assimp 5.2's binary FBX -----------------------------------------
// Assimp 5.2.x writes its null records from a std::string built from a char
// array of zeros, i.e. as nothing (assimp/assimp#4686): no nested list ends
// with the null record FBX requires, nor does the top-level list. Assimp's own
// importer then fails ("FBX-Tokenize ... block offset is out of range"), and
// so does Blender's. The tree is parsed leniently and written again with
// every null record in place, which moves every record's end offset.

struct FbxNode {
    std::string_view name;
    std::uint64_t propertyCount = 0;
    std::string_view properties;  // raw, copied as they are
    std::vector<FbxNode> children;
};

// Parses the record at `at` (not a null record) with its children; a nested
// list may or may not end with a null record.
bool parseNode(std::string_view b, std::size_t at, std::size_t limit, FbxNode& out) {
    const auto r = recordAt(b, at, limit);
    if (!r) return false;
    out.name = r->name;
    out.propertyCount = readLe(b, at + wordBytes(b), wordBytes(b));
    out.properties = b.substr(r->properties, r->children - r->properties);
    for (std::size_t pos = r->children; pos < r->end;) {
        if (readLe(b, pos, std::min(wordBytes(b), r->end - pos)) == 0) break;  // the null record: the list ends
        const auto child = recordAt(b, pos, r->end);
        if (!child) return false;
        out.children.emplace_back();
        if (!parseNode(b, pos, r->end, out.children.back())) return false;
        pos = child->end;
    }
    return true;
}

void putLe(std::string& out, std::size_t at, std::uint64_t v, std::size_t bytes) {
    for (std::size_t i = 0; i < bytes; ++i) out[at + i] = static_cast<char>((v >> (8 * i)) & 0xffu);
}

// Whether a node ends with a null record: after a nested list, and, as the
// FBX SDK and Blender write them, after a node without properties and after
// AnimationStack and AnimationLayer objects (Assimp's reader wants a scope there).
bool endsWithNullRecord(const FbxNode& n) {
    return !n.children.empty() || n.propertyCount == 0 || n.name == "AnimationStack" || n.name == "AnimationLayer";
}

void writeNode(std::string& out, const FbxNode& n, std::size_t w) {
    const std::size_t start = out.size();
    out.append(3 * w, '\0');
    out.push_back(static_cast<char>(n.name.size()));
    out.append(n.name);
    out.append(n.properties);
    for (const FbxNode& c : n.children) writeNode(out, c, w);
    if (endsWithNullRecord(n)) out.append(3 * w + 1, '\0');
    putLe(out, start, out.size(), w);
    putLe(out, start + w, n.propertyCount, w);
    putLe(out, start + 2 * w, n.properties.size(), w);
}

constexpr std::string_view kFooterId{"\xfa\xbc\xab\x09\xd0\xc8\xd4\x66\xb1\x76\xfb\x83\x1c\xf7\x26\x7e", 16};
constexpr std::string_view kFooterMagic{"\xf8\x5a\x8c\x6a\xde\xf5\xd9\x7e\xec\xe9\x0c\xe3\x75\x8f\x29\x0b", 16};

// Assimp's footer layout, its alignment padding computed for the new length.
void writeFooter(std::string& out, std::uint32_t version) {
    out.append(kFooterId);
    const std::size_t pad = 16 - out.size() % 16;
    out.append(pad + 4, '\0');
    out.append(4, '\0');
    putLe(out, out.size() - 4, version, 4);
    out.append(120, '\0');
    out.append(kFooterMagic);
}

// The string value of a node's first property ("" when it is not a string).
std::string_view stringProperty(const FbxNode& n) {
    if (n.properties.size() < 5 || n.properties[0] != 'S') return {};
    return n.properties.substr(5, static_cast<std::size_t>(readLe(n.properties, 1, 4)));
}

// Assimp 5.2 lists LayerElementColor and LayerElementUV in every geometry's
// Layer whether or not it wrote them; readers then look for elements that are
// not there (Assimp logs "failed to resolve vertex layer element"). Such
// entries are dropped.
void dropDanglingLayerElements(FbxNode& geometry) {
    auto present = [&](std::string_view type) {
        return std::any_of(geometry.children.begin(), geometry.children.end(),
                           [&](const FbxNode& c) { return c.name == type; });
    };
    for (FbxNode& layer : geometry.children) {
        if (layer.name != "Layer") continue;
        std::erase_if(layer.children, [&](const FbxNode& e) {
            if (e.name != "LayerElement") return false;
            const auto type = std::find_if(e.children.begin(), e.children.end(), [](const FbxNode& c) { return c.name == "Type"; });
            return type != e.children.end() && !present(stringProperty(*type));
        });
    }
}

Result<std::string> repairAssimpFbx(std::string_view b) {
    if (!isBinaryFbx(b)) return makeError("Assimp's FBX output is not binary FBX");
    const std::size_t w = wordBytes(b);
    std::vector<FbxNode> top;
    std::size_t pos = kHeaderBytes;
    // The top-level list ends at a null record, or (Assimp 5.2) right at the footer id.
    while (pos < b.size() && readLe(b, pos, std::min(w, b.size() - pos)) != 0 && b.substr(pos, 16) != kFooterId) {
        top.emplace_back();
        const auto r = recordAt(b, pos, b.size());
        if (!r || !parseNode(b, pos, b.size(), top.back())) {
            return makeError("Assimp's FBX output has a malformed record at byte " + std::to_string(pos));
        }
        pos = r->end;
    }
    if (top.empty()) return makeError("Assimp's FBX output has no records");
    for (FbxNode& n : top) {
        if (n.name != "Objects") continue;
        for (FbxNode& o : n.children)
            if (o.name == "Geometry") dropDanglingLayerElements(o);
    }
    std::string out(b.substr(0, kHeaderBytes));
    for (const FbxNode& n : top) writeNode(out, n, w);
    out.append(3 * w + 1, '\0');
    writeFooter(out, static_cast<std::uint32_t>(readLe(b, 23, 4)));
    return out;
}

// ---- properties and lists of the written file ------------------------------------

// Offset just past the property whose type code is at `at`, or nothing when
// the type is unknown or the property overruns `limit`.
std::optional<std::size_t> propertyEnd(std::string_view b, std::size_t at, std::size_t limit) {
    if (at >= limit) return std::nullopt;
    std::size_t size = 0;
    switch (b[at]) {
        case 'C': size = 1; break;
        case 'Y': size = 2; break;
        case 'I':
        case 'F': size = 4; break;
        case 'D':
        case 'L': size = 8; break;
        case 'S':
        case 'R':
            if (at + 5 > limit) return std::nullopt;
            size = 4 + static_cast<std::size_t>(readLe(b, at + 1, 4));
            break;
        case 'f':
        case 'd':
        case 'l':
        case 'i':
        case 'b':
            if (at + 13 > limit) return std::nullopt;
            size = 12 + static_cast<std::size_t>(readLe(b, at + 9, 4));
            break;
        default: return std::nullopt;
    }
    if (size > limit - at - 1) return std::nullopt;
    return at + 1 + size;
}

// Offsets of the type codes of a record's properties (as many as fit).
std::vector<std::size_t> propertiesOf(std::string_view b, const Record& r) {
    std::vector<std::size_t> out;
    for (std::size_t at = r.properties; at < r.children;) {
        const auto end = propertyEnd(b, at, r.children);
        if (!end) break;
        out.push_back(at);
        at = *end;
    }
    return out;
}

std::vector<Record> childrenOf(std::string_view b, const Record& r) {
    std::vector<Record> out;
    for (auto c = recordAt(b, r.children, r.end); c; c = recordAt(b, c->end, r.end)) out.push_back(*c);
    return out;
}

std::vector<Record> topLevel(std::string_view b) {
    std::vector<Record> out;
    for (auto r = recordAt(b, kHeaderBytes, b.size()); r; r = recordAt(b, r->end, b.size())) out.push_back(*r);
    return out;
}

std::optional<Record> child(std::string_view b, const Record& r, std::string_view name) {
    return findRecord(b, r.children, r.end, name);
}

std::string_view stringAt(std::string_view b, std::size_t at) {
    if (b[at] != 'S') return {};
    return b.substr(at + 5, static_cast<std::size_t>(readLe(b, at + 1, 4)));
}

// An uncompressed array property: where its elements start and how many.
struct ArrayRef {
    std::size_t data = 0;
    std::size_t count = 0;
};
std::optional<ArrayRef> arrayAt(std::string_view b, std::size_t at, char type, std::size_t elementBytes) {
    if (b[at] != type || readLe(b, at + 5, 4) != 0) return std::nullopt;  // encoding 0: not compressed
    const std::size_t count = static_cast<std::size_t>(readLe(b, at + 1, 4));
    if (readLe(b, at + 9, 4) != count * elementBytes) return std::nullopt;
    return ArrayRef{at + 13, count};
}

float floatAt(std::string_view b, std::size_t at) {
    const auto bits = static_cast<std::uint32_t>(readLe(b, at, 4));
    float v = 0.0f;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

void putFloat(std::string& b, std::size_t at, float v) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof v);
    putLe(b, at, bits, 4);
}

// The last property of the Properties70 entry ("P" record) named `name`
// under `owner`, when it has the given type.
std::optional<std::size_t> p70Value(std::string_view b, const Record& owner, std::string_view name, char type) {
    const auto props = child(b, owner, "Properties70");
    if (!props) return std::nullopt;
    for (const Record& p : childrenOf(b, *props)) {
        const auto values = propertiesOf(b, p);
        if (p.name != "P" || values.size() < 5 || stringAt(b, values.front()) != name) continue;
        if (b[values.back()] != type) return std::nullopt;
        return values.back() + 1;
    }
    return std::nullopt;
}

// FBX's TimeMode for a frame rate: the named rates, else 14 (custom, the
// rate in CustomFrameRate).
constexpr int kCustomTimeMode = 14;
int timeModeFor(double fps) {
    static constexpr std::array<std::pair<double, int>, 10> kModes = {
        {{120, 1}, {100, 2}, {60, 3}, {50, 4}, {48, 5}, {30, 6}, {25, 10}, {24, 11}, {96, 15}, {72, 16}}};
    for (const auto& [rate, mode] : kModes) {
        if (rate == fps) return mode;
    }
    return kCustomTimeMode;
}

}  // namespace

std::vector<FbxRotationCurves> fbxRotationCurves(std::string_view b) {
    std::vector<FbxRotationCurves> out;
    if (!isBinaryFbx(b)) return out;
    std::map<std::int64_t, std::size_t> nodeOf;  // AnimationCurveNode "R" uid -> index in out
    std::map<std::int64_t, FbxCurve> curves;     // AnimationCurve uid -> its keys
    for (const Record& top : topLevel(b)) {
        if (top.name != "Objects") continue;
        for (const Record& o : childrenOf(b, top)) {
            const auto props = propertiesOf(b, o);
            if (props.size() < 2 || b[props[0]] != 'L') continue;
            const auto uid = static_cast<std::int64_t>(readLe(b, props[0] + 1, 8));
            if (o.name == "AnimationCurveNode" && stringAt(b, props[1]).substr(0, 1) == "R") {
                nodeOf[uid] = out.size();
                out.emplace_back();
            } else if (o.name == "AnimationCurve") {
                const auto times = child(b, o, "KeyTime");
                const auto values = child(b, o, "KeyValueFloat");
                if (!times || !values) continue;
                const auto t = arrayAt(b, times->properties, 'l', 8);
                const auto v = arrayAt(b, values->properties, 'f', 4);
                if (t && v && t->count == v->count) curves[uid] = FbxCurve{t->data, v->data, v->count};
            }
        }
    }
    for (const Record& top : topLevel(b)) {
        if (top.name != "Connections") continue;
        for (const Record& c : childrenOf(b, top)) {
            const auto props = propertiesOf(b, c);
            if (props.size() < 4 || stringAt(b, props[0]) != "OP" || b[props[1]] != 'L' || b[props[2]] != 'L') continue;
            const auto from = static_cast<std::int64_t>(readLe(b, props[1] + 1, 8));
            const auto to = static_cast<std::int64_t>(readLe(b, props[2] + 1, 8));
            const std::string_view axis = stringAt(b, props[3]);
            const auto node = nodeOf.find(to);
            const auto curve = curves.find(from);
            if (node == nodeOf.end() || curve == curves.end() || axis.size() != 3 || axis.substr(0, 2) != "d|") continue;
            const int k = axis[2] - 'X';
            if (k >= 0 && k < 3) out[node->second].axes[static_cast<std::size_t>(k)] = curve->second;
        }
    }
    std::erase_if(out, [](const FbxRotationCurves& r) {
        return std::any_of(r.axes.begin(), r.axes.end(), [&](const FbxCurve& c) { return c.count != r.axes[0].count || c.count == 0; });
    });
    return out;
}

std::array<float, 3> fbxRotationKey(std::string_view bytes, const FbxRotationCurves& curves, std::size_t key) {
    std::array<float, 3> out{};
    for (std::size_t k = 0; k < 3; ++k) out[k] = floatAt(bytes, curves.axes[k].values + 4 * key);
    return out;
}

void unwrapFbxRotationCurves(std::string& bytes) {
    for (const FbxRotationCurves& r : fbxRotationCurves(bytes)) {
        std::array<float, 3> prev = fbxRotationKey(bytes, r, 0);
        for (std::size_t key = 1; key < r.axes[0].count; ++key) {
            const auto e = fbxRotationKey(bytes, r, key);
            // FBX's default order XYZ (R = Rz Ry Rx) is RotationOrder::ZYX in Fray's naming.
            const glm::dvec3 v = nearestEquivalentEuler(glm::dvec3(e[0], e[1], e[2]), glm::dvec3(prev[0], prev[1], prev[2]),
                                                        RotationOrder::ZYX);
            for (std::size_t k = 0; k < 3; ++k) {
                prev[k] = static_cast<float>(v[static_cast<glm::length_t>(k)]);
                putFloat(bytes, r.axes[k].values + 4 * key, prev[k]);
            }
        }
    }
}

Status setFbxTiming(std::string& bytes, double fps) {
    if (!isBinaryFbx(bytes)) return makeError("not a binary FBX file");
    // The key range: every curve's first and last key time.
    std::optional<std::int64_t> first, last;
    for (const Record& top : topLevel(bytes)) {
        if (top.name != "Objects") continue;
        for (const Record& o : childrenOf(bytes, top)) {
            if (o.name != "AnimationCurve") continue;
            const auto times = child(bytes, o, "KeyTime");
            const auto t = times ? arrayAt(bytes, times->properties, 'l', 8) : std::nullopt;
            if (!t) return makeError("Assimp's FBX output has an AnimationCurve without plain 64-bit KeyTime keys");
            if (t->count == 0) continue;
            const auto a = static_cast<std::int64_t>(readLe(bytes, t->data, 8));
            const auto z = static_cast<std::int64_t>(readLe(bytes, t->data + 8 * (t->count - 1), 8));
            first = first ? std::min(*first, a) : a;
            last = last ? std::max(*last, z) : z;
        }
    }
    if (!first) return makeError("Assimp's FBX output has no animation keys");
    std::optional<Record> settings;
    for (const Record& top : topLevel(bytes))
        if (top.name == "GlobalSettings") settings = top;
    if (!settings) return makeError("Assimp's FBX output has no GlobalSettings");
    const auto mode = p70Value(bytes, *settings, "TimeMode", 'I');
    const auto rate = p70Value(bytes, *settings, "CustomFrameRate", 'D');
    const auto spanStart = p70Value(bytes, *settings, "TimeSpanStart", 'L');
    const auto spanStop = p70Value(bytes, *settings, "TimeSpanStop", 'L');
    if (!mode || !rate || !spanStart || !spanStop) {
        return makeError("Assimp's FBX output lacks GlobalSettings TimeMode, CustomFrameRate or TimeSpanStart/Stop");
    }
    putLe(bytes, *mode, static_cast<std::uint32_t>(timeModeFor(fps)), 4);
    std::uint64_t rateBits = 0;
    std::memcpy(&rateBits, &fps, sizeof fps);
    putLe(bytes, *rate, rateBits, 8);
    putLe(bytes, *spanStart, static_cast<std::uint64_t>(*first), 8);
    putLe(bytes, *spanStop, static_cast<std::uint64_t>(*last), 8);
    int stacks = 0;
    for (const Record& top : topLevel(bytes)) {
        if (top.name != "Objects") continue;
        for (const Record& o : childrenOf(bytes, top)) {
            if (o.name != "AnimationStack") continue;
            for (const auto& [name, value] : {std::pair{"LocalStart", *first}, {"LocalStop", *last},
                                              {"ReferenceStart", *first}, {"ReferenceStop", *last}}) {
                const auto at = p70Value(bytes, o, name, 'L');
                if (!at) return makeError(std::string("Assimp's FBX output has an AnimationStack without ") + name);
                putLe(bytes, *at, static_cast<std::uint64_t>(value), 8);
            }
            ++stacks;
        }
    }
    if (stacks == 0) return makeError("Assimp's FBX output has no AnimationStack");
    return {};
}

std::optional<std::size_t> fbxPropertyOffset(std::string_view bytes, std::initializer_list<std::string_view> path) {
    if (!isBinaryFbx(bytes) || path.size() == 0) return std::nullopt;
    std::size_t from = kHeaderBytes, limit = bytes.size();
    std::optional<Record> r;
    for (std::string_view name : path) {
        r = findRecord(bytes, from, limit, name);
        if (!r) return std::nullopt;
        from = r->children;
        limit = r->end;
    }
    return r->properties;
}

Status fixFbxCreationTime(std::string& bytes) {
    if (!fbxPropertyOffset(bytes, {"FBXHeaderExtension", "CreationTimeStamp"})) return {};
    static constexpr std::array<std::pair<std::string_view, std::int32_t>, 7> kFixed = {
        {{"Year", 1970}, {"Month", 1}, {"Day", 1}, {"Hour", 10}, {"Minute", 0}, {"Second", 0}, {"Millisecond", 0}}};
    for (const auto& [field, value] : kFixed) {
        const auto at = fbxPropertyOffset(bytes, {"FBXHeaderExtension", "CreationTimeStamp", field});
        if (!at || *at + 5 > bytes.size() || bytes[*at] != 'I') {
            return makeError("Assimp's FBX output has no 32-bit CreationTimeStamp/" + std::string(field) +
                             "; cannot make the file reproducible");
        }
        putLe(bytes, *at + 1, static_cast<std::uint32_t>(value), 4);
    }
    return {};
}

Result<std::string> writeFbx(const SampledScene& scene, std::string_view name) {
    const auto ai = buildAssimpScene(scene, name, kCentimetresPerMetre);
    Assimp::Exporter exporter;
    const aiExportDataBlob* blob = exporter.ExportToBlob(ai.get(), "fbx", 0);
    if (!blob) return makeError(std::string("Assimp's FBX exporter failed: ") + exporter.GetErrorString());
    auto bytes = repairAssimpFbx(std::string_view(static_cast<const char*>(blob->data), blob->size));
    if (!bytes) return bytes.error();
    if (auto st = fixFbxCreationTime(*bytes); !st) return st.error();
    unwrapFbxRotationCurves(*bytes);
    if (auto st = setFbxTiming(*bytes, scene.fps); !st) return st.error();
    return std::move(*bytes);
}

}  // namespace fray::exporter
