#pragma once
// Rigs for the tests: a skeleton written as a skinned GLB or FBX by Fray's own
// exporter (one character in its rest pose), a small hand-made glTF whose
// bind frames, names and weights a test can bend, and CPU skinning to check a
// fray::SkinnedMesh against what the capsules would do.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "fray/core/skinned_mesh.h"
#include "fbx_writer.h"    // core/export/src
#include "gltf_writer.h"   // core/export/src

namespace fray::test {

inline void writeBytes(const std::filesystem::path& file, const std::string& bytes) {
    std::ofstream f(file, std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!f) throw std::runtime_error("cannot write " + file.string());
}

// The skeleton as Fray exports a character: its capsule body skinned to its
// joints in the rest pose (glb: joint names as they are; fbx: centimetres,
// joints named "<name>_<joint>").
inline void writeExportedRig(const Skeleton& skeleton, const std::filesystem::path& file, bool fbx, const std::string& name = "rig") {
    exporter::SampledScene scene;
    exporter::CharacterTake take;
    take.name = name;
    take.fileName = name;
    take.motion = Motion(skeleton, 30.0, 2);
    scene.characters.push_back(std::move(take));
    scene.fps = 30.0;
    scene.frames = 2;
    if (!fbx) return writeBytes(file, exporter::writeGltf(scene, "rig", exporter::GltfContainer::Binary));
    auto bytes = exporter::writeFbx(scene, "rig");
    if (!bytes) throw std::runtime_error(bytes.error().message);
    writeBytes(file, *bytes);
}

// Where each vertex of `mesh` lands for the given world joint transforms:
// sum_k w_k * (world_k * inverseBind_k)(v), written out independently of the
// renderer's shader.
inline std::vector<glm::vec3> skinOnCpu(const SkinnedMesh& mesh, const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::quat>& rotations) {
    std::vector<glm::vec3> out;
    for (const SkinnedVertex& v : mesh.vertices) {
        glm::vec3 p(0.0f);
        for (int k = 0; k < 4; ++k) {
            const std::size_t j = v.joints[static_cast<std::size_t>(k)];
            const RigidTransform world{positions[j], rotations[j]};
            const RigidTransform m = world * mesh.inverseBind[j];
            p += v.weights[k] * (m.translation + m.rotation * v.position);
        }
        out.push_back(p);
    }
    return out;
}

// A small skinned glTF written by hand: a chain of joints along +Y with a
// side branch, a tetrahedron around each joint bound to it, and one vertex
// shared half and half between the first two joints. Tests change the names,
// the bind pose, the bind frames (per bone, or of the whole model), the
// weights or the skin.
struct MiniRig {
    std::vector<std::string> names{"Hips", "Spine", "Chest", "Head", "Arm"};
    std::vector<int> parents{-1, 0, 1, 2, 2};
    std::vector<glm::vec3> offsets{{0, 1, 0}, {0, 0.3f, 0}, {0, 0.3f, 0}, {0, 0.3f, 0}, {0.2f, 0.1f, 0}};
    std::vector<glm::quat> bindPose;       // local joint rotations the mesh is modelled in (empty: the rest pose)
    std::vector<glm::quat> boneTurn;       // per joint, a turn of its bind frame about its own origin (empty: none)
    glm::mat4 model{1.0f};                 // applied to the whole file (vertices and bind frames)
    bool skinned = true;                   // false: no skin, no JOINTS_0 / WEIGHTS_0
    int unweightedVertex = -1;             // this vertex gets no weights

    Skeleton skeleton() const {
        Skeleton sk;
        for (std::size_t j = 0; j < names.size(); ++j)
            sk.addJoint(names[j], parents[j], offsets[j], {Channel::Zrotation, Channel::Xrotation, Channel::Yrotation}, RotationOrder::ZXY);
        return sk;
    }
    std::vector<glm::vec3> restPositions() const {
        std::vector<glm::vec3> p(names.size());
        for (std::size_t j = 0; j < names.size(); ++j) p[j] = (parents[j] >= 0 ? p[static_cast<std::size_t>(parents[j])] : glm::vec3(0)) + offsets[j];
        return p;
    }
    // World joint frames of the bind pose (the skeleton's joint frames posed by bindPose).
    std::vector<RigidTransform> bindJoints() const {
        std::vector<RigidTransform> w(names.size());
        for (std::size_t j = 0; j < names.size(); ++j) {
            const RigidTransform local{offsets[j], bindPose.empty() ? glm::quat(1, 0, 0, 0) : bindPose[j]};
            w[j] = parents[j] >= 0 ? w[static_cast<std::size_t>(parents[j])] * local : local;
        }
        return w;
    }
    // Bind-space vertices (before `model`) and their joints/weights.
    struct Vertex {
        glm::vec3 position;
        std::uint8_t joints[4];
        float weights[4];
    };
    std::vector<Vertex> vertices() const {
        const auto bind = bindJoints();
        std::vector<Vertex> out;
        const glm::vec3 corners[4] = {{0.05f, 0.0f, 0.05f}, {-0.05f, 0.0f, 0.05f}, {0.0f, 0.0f, -0.06f}, {0.0f, 0.08f, 0.0f}};
        for (std::size_t j = 0; j < bind.size(); ++j)
            for (const glm::vec3& c : corners)
                out.push_back({bind[j].translation + bind[j].rotation * c, {static_cast<std::uint8_t>(j), 0, 0, 0}, {1, 0, 0, 0}});
        out.push_back({(bind[0].translation + bind[1].translation) * 0.5f + glm::vec3(0.07f, 0, 0), {0, 1, 0, 0}, {0.5f, 0.5f, 0, 0}});
        return out;
    }
    std::vector<std::uint16_t> indices() const {
        std::vector<std::uint16_t> out;
        for (std::uint16_t j = 0; j < names.size(); ++j) {
            const auto b = static_cast<std::uint16_t>(4 * j);
            for (std::uint16_t t : {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3}) out.push_back(static_cast<std::uint16_t>(b + t));
        }
        const auto shared = static_cast<std::uint16_t>(4 * names.size());
        for (std::uint16_t t : {0, 1, 4}) out.push_back(t == 4 ? shared : t);
        return out;
    }

    std::string gltf() const {
        using json = nlohmann::json;
        std::string bin;
        auto add = [&](const void* data, std::size_t bytes) {
            bin.resize((bin.size() + 3) & ~std::size_t{3}, '\0');
            const std::size_t at = bin.size();
            bin.append(static_cast<const char*>(data), bytes);
            return std::make_pair(at, bytes);
        };
        json views = json::array(), accessors = json::array();
        auto accessor = [&](const void* data, std::size_t bytes, int type, std::size_t count, const char* shape) {
            const auto [at, len] = add(data, bytes);
            views.push_back({{"buffer", 0}, {"byteOffset", at}, {"byteLength", len}});
            accessors.push_back({{"bufferView", views.size() - 1}, {"componentType", type}, {"count", count}, {"type", shape}});
            return static_cast<int>(accessors.size()) - 1;
        };
        const auto verts = vertices();
        std::vector<float> pos, nrm, wts;
        std::vector<std::uint8_t> jts;
        glm::vec3 lo(1e9f), hi(-1e9f);
        for (std::size_t i = 0; i < verts.size(); ++i) {
            const glm::vec3 p = glm::vec3(model * glm::vec4(verts[i].position, 1.0f));
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
            pos.insert(pos.end(), {p.x, p.y, p.z});
            const glm::vec3 n = glm::normalize(glm::mat3(model) * glm::vec3(0, 1, 0));
            nrm.insert(nrm.end(), {n.x, n.y, n.z});
            const bool none = static_cast<int>(i) == unweightedVertex;
            for (int k = 0; k < 4; ++k) {
                jts.push_back(verts[i].joints[k]);
                wts.push_back(none ? 0.0f : verts[i].weights[k]);
            }
        }
        const auto idx = indices();
        const int aPos = accessor(pos.data(), pos.size() * 4, 5126, verts.size(), "VEC3");
        accessors[static_cast<std::size_t>(aPos)]["min"] = {lo.x, lo.y, lo.z};
        accessors[static_cast<std::size_t>(aPos)]["max"] = {hi.x, hi.y, hi.z};
        const int aNrm = accessor(nrm.data(), nrm.size() * 4, 5126, verts.size(), "VEC3");
        const int aIdx = accessor(idx.data(), idx.size() * 2, 5123, idx.size(), "SCALAR");
        json attributes = {{"POSITION", aPos}, {"NORMAL", aNrm}};
        json doc;
        doc["asset"] = {{"version", "2.0"}};
        json nodes = json::array();
        const auto bindFrames = bindJoints();
        std::vector<float> ibm;
        for (std::size_t j = 0; j < names.size(); ++j) {
            json node = {{"name", names[j]}, {"translation", {offsets[j].x, offsets[j].y, offsets[j].z}}};
            json children = json::array();
            for (std::size_t c = 0; c < names.size(); ++c)
                if (parents[c] == static_cast<int>(j)) children.push_back(c);
            if (!children.empty()) node["children"] = children;
            nodes.push_back(node);
            // Bind frame: the joint's, turned by boneTurn, then the whole model moved.
            glm::mat4 bind = glm::translate(glm::mat4(1.0f), bindFrames[j].translation) * glm::mat4_cast(bindFrames[j].rotation);
            if (!boneTurn.empty()) bind = bind * glm::mat4_cast(boneTurn[j]);
            const glm::mat4 inv = glm::inverse(model * bind);
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) ibm.push_back(inv[c][r]);
        }
        std::vector<int> roots;
        for (std::size_t j = 0; j < names.size(); ++j)
            if (parents[j] < 0) roots.push_back(static_cast<int>(j));
        json sceneNodes = json::array();
        for (int r : roots) sceneNodes.push_back(r);
        if (skinned) {
            attributes["JOINTS_0"] = accessor(jts.data(), jts.size(), 5121, verts.size(), "VEC4");
            attributes["WEIGHTS_0"] = accessor(wts.data(), wts.size() * 4, 5126, verts.size(), "VEC4");
            const int aIbm = accessor(ibm.data(), ibm.size() * 4, 5126, names.size(), "MAT4");
            json joints = json::array();
            for (std::size_t j = 0; j < names.size(); ++j) joints.push_back(j);
            doc["skins"] = json::array({{{"inverseBindMatrices", aIbm}, {"joints", joints}, {"skeleton", roots.front()}}});
        }
        json meshNode = {{"name", "body"}, {"mesh", 0}};
        if (skinned) meshNode["skin"] = 0;
        nodes.push_back(meshNode);
        sceneNodes.push_back(nodes.size() - 1);
        doc["nodes"] = nodes;
        doc["meshes"] = json::array({{{"name", "body"}, {"primitives", json::array({{{"attributes", attributes}, {"indices", aIdx}}})}}});
        doc["scenes"] = json::array({{{"nodes", sceneNodes}}});
        doc["scene"] = 0;
        doc["bufferViews"] = views;
        doc["accessors"] = accessors;
        doc["buffers"] = json::array(
            {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + exporter::base64(bin)}}});
        return doc.dump();
    }
};

}  // namespace fray::test
