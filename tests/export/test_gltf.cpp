// glTF 2.0 and GLB export: structure (counts, skins, channels, bounds, buffer
// lengths) read back from the files, the animation against the scene poser,
// and the skinned body against forward kinematics.
#include <map>
#include <set>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/quaternion.hpp>

#include "export_fixture.h"
#include "fray/core/kinematics.h"

namespace fray::test {
namespace {

using exporter::Format;

int findNode(const json& doc, const std::string& name) {
    for (std::size_t i = 0; i < doc["nodes"].size(); ++i) {
        if (doc["nodes"][i].value("name", "") == name) return static_cast<int>(i);
    }
    return -1;
}

TEST(ExportGltf, OneSkinnedAnimatedCharacterPerSceneCharacter) {
    TempFolder dir;
    const Gltf g = exportGltf(Format::Gltf, dir);
    const auto& scene = exportDuel();
    const sim::ScenePoser poser(scene, exportLibrary());
    const std::size_t n = scene.characters.size();
    ASSERT_EQ(n, 2u);
    const json& doc = g.doc;
    EXPECT_EQ(doc["asset"]["version"], "2.0");
    ASSERT_EQ(doc["skins"].size(), n);
    ASSERT_EQ(doc["meshes"].size(), n);
    EXPECT_EQ(doc["materials"].size(), 2u);  // sides 0 and 1
    std::size_t joints = 0;
    for (std::size_t c = 0; c < n; ++c) {
        const Skeleton& sk = poser.skeleton(static_cast<int>(c));
        const json& skin = doc["skins"][c];
        ASSERT_EQ(skin["joints"].size(), static_cast<std::size_t>(sk.jointCount()));
        EXPECT_EQ(g.count(skin["inverseBindMatrices"]), static_cast<std::size_t>(sk.jointCount()));
        for (int j = 0; j < sk.jointCount(); ++j) {
            EXPECT_EQ(doc["nodes"][skin["joints"][j].get<int>()]["name"], sk.names[static_cast<std::size_t>(j)]);
        }
        const int group = findNode(doc, scene.characters[c].name);
        ASSERT_GE(group, 0);
        EXPECT_EQ(doc["nodes"][group]["children"][0], skin["joints"][0]);
        EXPECT_EQ(doc["nodes"][group]["extras"]["side"], scene.characters[c].side);
        // The skinned mesh node sits at the scene root (glTF ignores its parents' transforms).
        const int body = findNode(doc, scene.characters[c].name + " body");
        ASSERT_GE(body, 0);
        EXPECT_EQ(doc["nodes"][body]["skin"], c);
        const auto& roots = doc["scenes"][0]["nodes"];
        EXPECT_NE(std::find(roots.begin(), roots.end(), body), roots.end());
        EXPECT_NE(std::find(roots.begin(), roots.end(), group), roots.end());
        joints += static_cast<std::size_t>(sk.jointCount());
    }
    ASSERT_EQ(doc["animations"].size(), 1u);
    const json& anim = doc["animations"][0];
    EXPECT_EQ(anim["name"], "duel");
    EXPECT_EQ(anim["channels"].size(), joints * 2);  // characters x joints x (translation, rotation)
    EXPECT_EQ(anim["samplers"].size(), joints * 2);
    const int frames = exporter::exportFrameCount(scene.duration, 30.0);
    EXPECT_EQ(frames, 181);  // 6 s at 30 fps, both ends included
    std::set<std::pair<int, std::string>> targets;
    for (const json& ch : anim["channels"]) {
        targets.insert({ch["target"]["node"].get<int>(), ch["target"]["path"].get<std::string>()});
        const json& s = anim["samplers"][ch["sampler"].get<int>()];
        EXPECT_EQ(s["interpolation"], "LINEAR");
        EXPECT_EQ(g.count(s["input"]), static_cast<std::size_t>(frames));
        EXPECT_EQ(g.count(s["output"]), static_cast<std::size_t>(frames));
        EXPECT_EQ(doc["accessors"][s["output"].get<int>()]["type"], ch["target"]["path"] == "rotation" ? "VEC4" : "VEC3");
    }
    EXPECT_EQ(targets.size(), joints * 2) << "every joint animated once per path";
    const int input = anim["samplers"][0]["input"];
    const auto times = g.floats(input);
    EXPECT_FLOAT_EQ(times.front(), 0.0f);
    EXPECT_NEAR(times.back(), scene.duration, 1e-5);
    EXPECT_EQ(doc["accessors"][input]["max"][0].get<double>(), static_cast<double>(times.back()));
}

TEST(ExportGltf, BuffersAccessorsAndBoundsAgreeWithTheData) {
    TempFolder dir;
    const Gltf g = exportGltf(Format::Gltf, dir);
    const json& doc = g.doc;
    ASSERT_EQ(doc["buffers"].size(), 1u);
    EXPECT_EQ(doc["buffers"][0]["byteLength"].get<std::size_t>(), g.bin.size());
    for (const json& v : doc["bufferViews"]) {
        EXPECT_LE(v.value("byteOffset", std::size_t{0}) + v["byteLength"].get<std::size_t>(), g.bin.size());
        EXPECT_EQ(v.value("byteOffset", std::size_t{0}) % 4, 0u);
    }
    for (std::size_t a = 0; a < doc["accessors"].size(); ++a) {
        const json& acc = doc["accessors"][a];
        const json& v = doc["bufferViews"][acc["bufferView"].get<int>()];
        const std::size_t bytes = g.count(static_cast<int>(a)) * Gltf::components(acc["type"]) *
                                  Gltf::componentBytes(acc["componentType"]);
        EXPECT_LE(acc.value("byteOffset", std::size_t{0}) + bytes, v["byteLength"].get<std::size_t>()) << "accessor " << a;
    }
    for (std::size_t m = 0; m < doc["meshes"].size(); ++m) {
        const json& prim = doc["meshes"][m]["primitives"][0];
        const json& attr = prim["attributes"];
        const int pos = attr["POSITION"];
        const std::size_t n = g.count(pos);
        ASSERT_GT(n, 0u);
        for (const char* name : {"NORMAL", "JOINTS_0", "WEIGHTS_0"}) EXPECT_EQ(g.count(attr[name]), n) << name;
        // min/max are required on POSITION and must be the data's exact bounds.
        const auto p = g.floats(pos);
        for (std::size_t k = 0; k < 3; ++k) {
            float lo = p[k], hi = p[k];
            for (std::size_t i = k; i < p.size(); i += 3) lo = std::min(lo, p[i]), hi = std::max(hi, p[i]);
            EXPECT_EQ(doc["accessors"][pos]["min"][k].get<double>(), static_cast<double>(lo));
            EXPECT_EQ(doc["accessors"][pos]["max"][k].get<double>(), static_cast<double>(hi));
        }
        const auto normals = g.floats(attr["NORMAL"]);
        for (std::size_t i = 0; i < normals.size(); i += 3) {
            ASSERT_NEAR(glm::length(glm::vec3(normals[i], normals[i + 1], normals[i + 2])), 1.0f, 1e-5f);
        }
        const std::size_t skinJoints = doc["skins"][m]["joints"].size();
        const auto joints = g.uints(attr["JOINTS_0"]);
        const auto weights = g.floats(attr["WEIGHTS_0"]);
        for (std::size_t i = 0; i < n; ++i) {
            ASSERT_LT(joints[i * 4], skinJoints);
            EXPECT_EQ(weights[i * 4] + weights[i * 4 + 1] + weights[i * 4 + 2] + weights[i * 4 + 3], 1.0f);
        }
        const auto indices = g.uints(prim["indices"]);
        EXPECT_EQ(indices.size() % 3, 0u);
        for (auto i : indices) ASSERT_LT(i, n);
    }
}

// Local translation and rotation of every node at one frame, from the animation.
std::map<int, std::pair<glm::vec3, glm::quat>> animatedPose(const Gltf& g, int frame) {
    std::map<int, std::pair<glm::vec3, glm::quat>> out;
    const json& anim = g.doc["animations"][0];
    for (const json& ch : anim["channels"]) {
        const int node = ch["target"]["node"];
        const auto data = g.floats(anim["samplers"][ch["sampler"].get<int>()]["output"]);
        auto& [t, r] = out[node];
        const auto f = static_cast<std::size_t>(frame);
        if (ch["target"]["path"] == "translation") {
            t = glm::vec3(data[f * 3], data[f * 3 + 1], data[f * 3 + 2]);
        } else {
            r = glm::quat(data[f * 4 + 3], data[f * 4], data[f * 4 + 1], data[f * 4 + 2]);  // glTF stores x, y, z, w
        }
    }
    return out;
}

TEST(ExportGltf, AnimationReproducesTheScenePoser) {
    TempFolder dir;
    const Gltf g = exportGltf(Format::Gltf, dir);
    const auto& scene = exportDuel();
    const sim::ScenePoser poser(scene, exportLibrary());
    const int frames = exporter::exportFrameCount(scene.duration, 30.0);
    for (int frame : {0, 1, frames / 2, frames - 1}) {
        const auto pose = animatedPose(g, frame);
        for (std::size_t c = 0; c < scene.characters.size(); ++c) {
            Pose expected;
            poser.pose(static_cast<int>(c), frame / 30.0, expected);
            const json& joints = g.doc["skins"][c]["joints"];
            for (std::size_t j = 0; j < joints.size(); ++j) {
                const auto& [t, r] = pose.at(joints[j].get<int>());
                EXPECT_LT(glm::length(t - expected.translations[j]), 1e-5f) << "character " << c << " joint " << j;
                EXPECT_GT(std::abs(glm::dot(r, glm::normalize(expected.rotations[j]))), 1.0f - 1e-6f);
            }
        }
    }
}

// The body's vertices, skinned the way a glTF viewer does (joint world matrix
// times inverse bind matrix), land where forward kinematics of the scene pose
// puts the bone they belong to.
TEST(ExportGltf, SkinnedBodyFollowsTheBones) {
    TempFolder dir;
    const Gltf g = exportGltf(Format::Gltf, dir);
    const auto& scene = exportDuel();
    const sim::ScenePoser poser(scene, exportLibrary());
    const int frame = 97;
    const auto pose = animatedPose(g, frame);
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        const Skeleton& sk = poser.skeleton(static_cast<int>(c));
        const auto jc = static_cast<std::size_t>(sk.jointCount());
        const json& skin = g.doc["skins"][c];
        // Joint world matrices through the node hierarchy (the group node has no transform).
        const int group = findNode(g.doc, scene.characters[c].name);
        EXPECT_FALSE(g.doc["nodes"][group].contains("translation") || g.doc["nodes"][group].contains("matrix"));
        std::vector<glm::mat4> world(jc);
        for (std::size_t j = 0; j < jc; ++j) {
            const auto& [t, r] = pose.at(skin["joints"][j].get<int>());
            const glm::mat4 local = glm::translate(glm::mat4(1.0f), t) * glm::toMat4(r);
            const int p = sk.parents[j];
            world[j] = p < 0 ? local : world[static_cast<std::size_t>(p)] * local;
        }
        const auto ibm = g.floats(skin["inverseBindMatrices"]);
        // Expected: forward kinematics of the poser's pose, bind offsets from the skeleton.
        Pose expected;
        poser.pose(static_cast<int>(c), frame / 30.0, expected);
        std::vector<glm::vec3> wp(jc), bind(jc);
        std::vector<glm::quat> wr(jc);
        forwardKinematics(sk, expected.translations, expected.rotations, wp, wr);
        for (std::size_t j = 0; j < jc; ++j) {
            bind[j] = (sk.parents[j] < 0 ? glm::vec3(0.0f) : bind[static_cast<std::size_t>(sk.parents[j])]) + sk.offsets[j];
        }
        const json& attr = g.doc["meshes"][c]["primitives"][0]["attributes"];
        const auto positions = g.floats(attr["POSITION"]);
        const auto joints = g.uints(attr["JOINTS_0"]);
        std::set<std::uint32_t> seen;
        for (std::size_t v = 0; v < positions.size() / 3; ++v) {
            const std::uint32_t j = joints[v * 4];
            const glm::vec3 p(positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2]);
            glm::mat4 inv;
            std::memcpy(&inv[0][0], &ibm[j * 16], sizeof(float) * 16);  // column-major, as GLM stores it
            const glm::vec3 skinned = glm::vec3(world[j] * inv * glm::vec4(p, 1.0f));
            const glm::vec3 want = wp[j] + wr[j] * (p - bind[j]);
            ASSERT_LT(glm::length(skinned - want), 1e-4f) << "character " << c << " vertex " << v << " joint " << j;
            seen.insert(j);
        }
        EXPECT_GE(seen.size(), jc - 2) << "almost every joint carries part of the body";
    }
}

TEST(ExportGlb, SameDocumentAndBufferAsTheGltfFileInABinaryContainer) {
    TempFolder a, b;
    const Gltf gltf = exportGltf(Format::Gltf, a);
    (void)exportGltf(Format::Glb, b);
    const std::string glb = readBytes(b / "duel.glb");
    ASSERT_GE(glb.size(), 28u);
    EXPECT_EQ(glb.substr(0, 4), "glTF");
    EXPECT_EQ(le32(glb, 4), 2u);
    EXPECT_EQ(le32(glb, 8), glb.size());
    const std::uint32_t jsonLength = le32(glb, 12);
    EXPECT_EQ(jsonLength % 4, 0u);
    EXPECT_EQ(glb.substr(16, 4), "JSON");
    const std::size_t binAt = 20 + jsonLength;
    EXPECT_EQ(glb.substr(binAt + 4, 4), std::string("BIN\0", 4));
    EXPECT_EQ(binAt + 8 + le32(glb, binAt), glb.size());
    const Gltf g = Gltf::fromGlb(glb);
    EXPECT_FALSE(g.doc["buffers"][0].contains("uri"));
    EXPECT_EQ(g.doc["buffers"][0]["byteLength"].get<std::size_t>(), g.bin.size());
    EXPECT_EQ(g.bin, gltf.bin);
    json withoutUri = gltf.doc;
    withoutUri["buffers"][0].erase("uri");
    EXPECT_EQ(g.doc, withoutUri);
}

}  // namespace
}  // namespace fray::test
