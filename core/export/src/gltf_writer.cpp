#include "gltf_writer.h"

#include <bit>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "rig.h"

namespace fray::exporter {
namespace {

using json = nlohmann::ordered_json;
static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian; so is this machine's memory");

constexpr int kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

json vec3Json(const glm::vec3& v) {
    return json::array({static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)});
}

// Buffer views and accessors over one binary buffer, built together.
class BufferBuilder {
public:
    // Appends the bytes as a new buffer view at a 4-byte boundary; target 0: none.
    int addView(const void* data, std::size_t bytes, int target) {
        bin_.resize((bin_.size() + 3) & ~std::size_t{3}, '\0');
        json v = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
        if (target != 0) v["target"] = target;
        bin_.append(static_cast<const char*>(data), bytes);
        views_.push_back(std::move(v));
        return static_cast<int>(views_.size()) - 1;
    }
    template <class T>
    int addView(const std::vector<T>& v, int target) {
        return addView(v.data(), v.size() * sizeof(T), target);
    }
    int addAccessor(int view, std::size_t byteOffset, int componentType, std::size_t count, const char* type) {
        json a = {{"bufferView", view}};
        if (byteOffset != 0) a["byteOffset"] = byteOffset;
        a["componentType"] = componentType;
        a["count"] = count;
        a["type"] = type;
        accessors_.push_back(std::move(a));
        return static_cast<int>(accessors_.size()) - 1;
    }
    // Exact per-component bounds of float data (the validator compares them with the data).
    void setBounds(int accessor, const std::vector<float>& data, std::size_t components) {
        json lo = json::array(), hi = json::array();
        for (std::size_t k = 0; k < components; ++k) {
            float mn = data[k], mx = data[k];
            for (std::size_t i = k; i < data.size(); i += components) mn = std::min(mn, data[i]), mx = std::max(mx, data[i]);
            lo.push_back(static_cast<double>(mn));
            hi.push_back(static_cast<double>(mx));
        }
        accessors_[static_cast<std::size_t>(accessor)]["min"] = std::move(lo);
        accessors_[static_cast<std::size_t>(accessor)]["max"] = std::move(hi);
    }
    // Adds buffers, bufferViews and accessors to the document; with embed,
    // the buffer is a base64 data URI, else it is the GLB's binary chunk.
    void finish(json& doc, bool embed) {
        bin_.resize((bin_.size() + 3) & ~std::size_t{3}, '\0');
        json buffer = {{"byteLength", bin_.size()}};
        if (embed) buffer["uri"] = "data:application/octet-stream;base64," + base64(bin_);
        doc["buffers"] = json::array({std::move(buffer)});
        doc["bufferViews"] = std::move(views_);
        doc["accessors"] = std::move(accessors_);
    }
    const std::string& bin() const { return bin_; }

private:
    std::string bin_;
    json views_ = json::array(), accessors_ = json::array();
};

std::vector<float> flatten(const std::vector<glm::vec3>& v) {
    std::vector<float> out;
    out.reserve(v.size() * 3);
    for (const auto& p : v) out.insert(out.end(), {p.x, p.y, p.z});
    return out;
}

// The body of one character (the rig's skin or the capsules) as a mesh;
// returns the mesh index.
int addBodyMesh(BufferBuilder& buf, json& meshes, const CharacterTake& c, const ExportBody& body, int material) {
    const std::size_t n = body.positions.size();
    const std::vector<float> positions = flatten(body.positions), normals = flatten(body.normals);
    std::vector<float> weights(n * 4, 0.0f);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < 4; ++k) weights[i * 4 + k] = body.weights[i][static_cast<glm::length_t>(k)];

    const int pos = buf.addAccessor(buf.addView(positions, kArrayBuffer), 0, kFloat, n, "VEC3");
    buf.setBounds(pos, positions, 3);
    const int nrm = buf.addAccessor(buf.addView(normals, kArrayBuffer), 0, kFloat, n, "VEC3");
    int joints = 0;
    if (c.motion.jointCount() <= 256) {
        std::vector<std::uint8_t> j(n * 4, 0);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t k = 0; k < 4; ++k) j[i * 4 + k] = static_cast<std::uint8_t>(body.joints[i][k]);
        joints = buf.addAccessor(buf.addView(j, kArrayBuffer), 0, kUnsignedByte, n, "VEC4");
    } else {
        std::vector<std::uint16_t> j(n * 4, 0);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t k = 0; k < 4; ++k) j[i * 4 + k] = body.joints[i][k];
        joints = buf.addAccessor(buf.addView(j, kArrayBuffer), 0, kUnsignedShort, n, "VEC4");
    }
    const int wts = buf.addAccessor(buf.addView(weights, kArrayBuffer), 0, kFloat, n, "VEC4");
    int indices = 0;
    if (n < 65535) {  // 65535 is the primitive-restart value, never a valid index
        const std::vector<std::uint16_t> idx(body.indices.begin(), body.indices.end());
        indices = buf.addAccessor(buf.addView(idx, kElementArrayBuffer), 0, kUnsignedShort, idx.size(), "SCALAR");
    } else {
        indices = buf.addAccessor(buf.addView(body.indices, kElementArrayBuffer), 0, kUnsignedInt, body.indices.size(),
                                  "SCALAR");
    }
    json prim = {{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"JOINTS_0", joints}, {"WEIGHTS_0", wts}}},
                 {"indices", indices},
                 {"material", material},
                 {"mode", 4}};
    meshes.push_back({{"name", c.name + " body"}, {"primitives", json::array({std::move(prim)})}});
    return static_cast<int>(meshes.size()) - 1;
}

// Inverse bind matrices (column-major), one per joint (for the capsules a
// translation by minus the joint's bind position: that bind pose has no rotation).
int addInverseBindMatrices(BufferBuilder& buf, const ExportBody& body) {
    std::vector<float> m;
    for (const glm::mat4& b : body.inverseBind)
        for (glm::length_t col = 0; col < 4; ++col)
            for (glm::length_t row = 0; row < 4; ++row) m.push_back(b[col][row]);
    return buf.addAccessor(buf.addView(m, 0), 0, kFloat, body.inverseBind.size(), "MAT4");
}

// The character's group node, its joint nodes (rest pose) and skin; returns
// the index of the skin. Joint j of the skeleton is node firstJoint + j.
int addCharacterNodes(json& nodes, json& skins, json& sceneNodes, const CharacterTake& c, int ibm, int& firstJoint) {
    const Skeleton& sk = c.motion.skeleton();
    const int group = static_cast<int>(nodes.size());
    firstJoint = group + 1;
    nodes.push_back({{"name", c.name},
                     {"children", json::array({firstJoint})},
                     {"extras", {{"side", c.side}, {"group", c.group}}}});
    json joints = json::array();
    for (int j = 0; j < sk.jointCount(); ++j) {
        json node = {{"name", sk.names[static_cast<std::size_t>(j)]},
                     {"translation", vec3Json(sk.offsets[static_cast<std::size_t>(j)])}};
        const auto children = sk.children(j);
        if (!children.empty()) {
            json ch = json::array();
            for (int k : children) ch.push_back(firstJoint + k);
            node["children"] = std::move(ch);
        }
        nodes.push_back(std::move(node));
        joints.push_back(firstJoint + j);
    }
    sceneNodes.push_back(group);
    skins.push_back({{"name", c.name}, {"inverseBindMatrices", ibm}, {"skeleton", firstJoint}, {"joints", std::move(joints)}});
    return static_cast<int>(skins.size()) - 1;
}

// Per joint a translation and a rotation sampler and channel, all outputs of
// the character in one buffer view.
void addCharacterAnimation(BufferBuilder& buf, json& samplers, json& channels, const CharacterTake& c, int firstJoint,
                           int timeAccessor) {
    const Motion& m = c.motion;
    const auto frames = static_cast<std::size_t>(m.frameCount());
    const int jc = m.jointCount();
    std::vector<float> data;
    data.reserve(frames * static_cast<std::size_t>(jc) * 7);
    for (int j = 0; j < jc; ++j) {
        for (int f = 0; f < m.frameCount(); ++f) {
            const glm::vec3 t = m.translations(f)[static_cast<std::size_t>(j)];
            data.insert(data.end(), {t.x, t.y, t.z});
        }
        for (int f = 0; f < m.frameCount(); ++f) {
            const glm::quat q = m.rotations(f)[static_cast<std::size_t>(j)];
            data.insert(data.end(), {q.x, q.y, q.z, q.w});
        }
    }
    const int view = buf.addView(data, 0);
    std::size_t offset = 0;
    for (int j = 0; j < jc; ++j) {
        const int t = buf.addAccessor(view, offset, kFloat, frames, "VEC3");
        offset += frames * 3 * sizeof(float);
        const int r = buf.addAccessor(view, offset, kFloat, frames, "VEC4");
        offset += frames * 4 * sizeof(float);
        for (const auto& [output, path] : {std::pair{t, "translation"}, std::pair{r, "rotation"}}) {
            channels.push_back({{"sampler", samplers.size()}, {"target", {{"node", firstJoint + j}, {"path", path}}}});
            samplers.push_back({{"input", timeAccessor}, {"interpolation", "LINEAR"}, {"output", output}});
        }
    }
}

int addTimeAccessor(BufferBuilder& buf, const SampledScene& scene) {
    std::vector<float> times(static_cast<std::size_t>(scene.frames));
    for (int f = 0; f < scene.frames; ++f) times[static_cast<std::size_t>(f)] = static_cast<float>(scene.time(f));
    const int a = buf.addAccessor(buf.addView(times, 0), 0, kFloat, times.size(), "SCALAR");
    buf.setBounds(a, times, 1);
    return a;
}

json materialsBySide(const SampledScene& scene, std::map<int, int>& index) {
    std::set<int> sides;
    for (const auto& c : scene.characters) sides.insert(c.side);
    json materials = json::array();
    for (int s : sides) {
        const glm::vec3 col = sideColour(s);
        index[s] = static_cast<int>(materials.size());
        materials.push_back({{"name", "side " + std::to_string(s)},
                             {"pbrMetallicRoughness",
                              {{"baseColorFactor", {static_cast<double>(col.x), static_cast<double>(col.y),
                                                    static_cast<double>(col.z), 1.0}},
                               {"metallicFactor", 0.0},
                               {"roughnessFactor", 0.8}}}});
    }
    return materials;
}

std::string glbContainer(std::string jsonText, std::string bin) {
    jsonText.resize((jsonText.size() + 3) & ~std::size_t{3}, ' ');
    bin.resize((bin.size() + 3) & ~std::size_t{3}, '\0');
    std::string out;
    auto u32 = [&](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
    };
    u32(0x46546C67u);  // "glTF"
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + jsonText.size() + 8 + bin.size()));
    u32(static_cast<std::uint32_t>(jsonText.size()));
    u32(0x4E4F534Au);  // "JSON"
    out += jsonText;
    u32(static_cast<std::uint32_t>(bin.size()));
    u32(0x004E4942u);  // "BIN\0"
    out += bin;
    return out;
}

}  // namespace

std::string base64(std::string_view bytes) {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
        std::uint32_t v = 0;
        for (std::size_t k = 0; k < 3; ++k)
            v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
        for (std::size_t k = 0; k < 4; ++k) out.push_back(k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63u] : '=');
    }
    return out;
}

std::string writeGltf(const SampledScene& scene, std::string_view name, GltfContainer container) {
    json doc;
    doc["asset"] = {{"version", "2.0"}, {"generator", "Fray scene export (fray_export)"}};
    doc["scene"] = 0;
    BufferBuilder buf;
    std::map<int, int> materialOfSide;
    json materials = materialsBySide(scene, materialOfSide);
    json nodes = json::array(), meshes = json::array(), skins = json::array(), sceneNodes = json::array();
    json samplers = json::array(), channels = json::array();
    const int time = addTimeAccessor(buf, scene);
    for (const auto& c : scene.characters) {
        int firstJoint = 0;
        const ExportBody body = exportBody(c.motion.skeleton(), c.skin.get());
        const int skin = addCharacterNodes(nodes, skins, sceneNodes, c, addInverseBindMatrices(buf, body), firstJoint);
        const int mesh = addBodyMesh(buf, meshes, c, body, materialOfSide.at(c.side));
        sceneNodes.push_back(static_cast<int>(nodes.size()));
        nodes.push_back({{"name", c.name + " body"}, {"mesh", mesh}, {"skin", skin}});
        addCharacterAnimation(buf, samplers, channels, c, firstJoint, time);
    }
    doc["scenes"] = json::array({{{"name", name}, {"nodes", std::move(sceneNodes)}}});
    doc["nodes"] = std::move(nodes);
    doc["meshes"] = std::move(meshes);
    doc["materials"] = std::move(materials);
    doc["skins"] = std::move(skins);
    doc["animations"] = json::array({{{"name", name}, {"channels", std::move(channels)}, {"samplers", std::move(samplers)}}});
    buf.finish(doc, container == GltfContainer::Embedded);
    if (container == GltfContainer::Binary) return glbContainer(doc.dump(1), buf.bin());
    return doc.dump(1) + "\n";
}

}  // namespace fray::exporter
