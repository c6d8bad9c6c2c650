#include "assimp_scene.h"

#include <map>
#include <set>
#include <vector>

#include <assimp/material.h>

#include "rig.h"

namespace fray::exporter {
namespace {

aiVector3D toAi(const glm::vec3& v) { return {v.x, v.y, v.z}; }

aiMatrix4x4 translation(const glm::vec3& t) {
    aiMatrix4x4 m;
    aiMatrix4x4::Translation(toAi(t), m);
    return m;
}

template <class T>
T* copyArray(const std::vector<T>& v) {
    T* out = new T[v.size()];
    std::copy(v.begin(), v.end(), out);
    return out;
}

void setChildren(aiNode* parent, const std::vector<aiNode*>& children) {
    parent->mNumChildren = static_cast<unsigned>(children.size());
    parent->mChildren = copyArray(children);
    for (aiNode* c : children) c->mParent = parent;
}

// The joint hierarchy in its rest pose; returns the root joint's node.
aiNode* jointNodes(const CharacterTake& c, float scale) {
    const Skeleton& sk = c.motion.skeleton();
    std::vector<aiNode*> nodes;
    for (int j = 0; j < sk.jointCount(); ++j) {
        nodes.push_back(new aiNode(jointNodeName(c, j)));
        nodes.back()->mTransformation = translation(sk.offsets[static_cast<std::size_t>(j)] * scale);
    }
    for (int j = 0; j < sk.jointCount(); ++j) {
        std::vector<aiNode*> kids;
        for (int k : sk.children(j)) kids.push_back(nodes[static_cast<std::size_t>(k)]);
        if (!kids.empty()) setChildren(nodes[static_cast<std::size_t>(j)], kids);
    }
    return nodes.front();
}

aiMatrix4x4 toAiMatrix(const glm::mat4& m, float scale) {
    aiMatrix4x4 out;
    for (unsigned r = 0; r < 4; ++r)
        for (unsigned c = 0; c < 4; ++c) out[r][c] = m[static_cast<glm::length_t>(c)][static_cast<glm::length_t>(r)];
    out.a4 *= scale;
    out.b4 *= scale;
    out.c4 *= scale;
    return out;
}

// One bone per joint, the inverse bind as offset. Every joint is a bone, even
// one that moves no vertex (an end site, the root bone): Assimp's FBX exporter
// makes LimbNodes only of bones and their parents, and readers (Blender) leave
// the other joints out of the armature.
void addBones(aiMesh* mesh, const CharacterTake& c, const ExportBody& body, float scale) {
    const Skeleton& sk = c.motion.skeleton();
    std::vector<std::vector<aiVertexWeight>> weights(static_cast<std::size_t>(sk.jointCount()));
    for (std::size_t v = 0; v < body.joints.size(); ++v) {
        for (std::size_t k = 0; k < 4; ++k) {
            const float w = body.weights[v][static_cast<glm::length_t>(k)];
            if (w > 0.0f) weights[body.joints[v][k]].emplace_back(static_cast<unsigned>(v), w);
        }
    }
    std::vector<aiBone*> bones;
    for (int j = 0; j < sk.jointCount(); ++j) {
        auto* bone = new aiBone();
        const auto& w = weights[static_cast<std::size_t>(j)];
        bone->mName = jointNodeName(c, j);
        bone->mNumWeights = static_cast<unsigned>(w.size());
        bone->mWeights = w.empty() ? nullptr : copyArray(w);
        bone->mOffsetMatrix = toAiMatrix(body.inverseBind[static_cast<std::size_t>(j)], scale);
        bones.push_back(bone);
    }
    mesh->mNumBones = static_cast<unsigned>(bones.size());
    mesh->mBones = copyArray(bones);
}

aiMesh* bodyMesh(const CharacterTake& c, unsigned material, float scale) {
    const ExportBody body = exportBody(c.motion.skeleton(), c.skin.get());
    auto* mesh = new aiMesh();
    mesh->mName = c.fileName + "_body";
    mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    mesh->mMaterialIndex = material;
    mesh->mNumVertices = static_cast<unsigned>(body.positions.size());
    mesh->mVertices = new aiVector3D[mesh->mNumVertices];
    mesh->mNormals = new aiVector3D[mesh->mNumVertices];
    for (std::size_t v = 0; v < body.positions.size(); ++v) {
        mesh->mVertices[v] = toAi(body.positions[v] * scale);
        mesh->mNormals[v] = toAi(body.normals[v]);
    }
    mesh->mNumFaces = static_cast<unsigned>(body.indices.size() / 3);
    mesh->mFaces = new aiFace[mesh->mNumFaces];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        mesh->mFaces[f].mNumIndices = 3;
        mesh->mFaces[f].mIndices = new unsigned[3];
        for (unsigned k = 0; k < 3; ++k) mesh->mFaces[f].mIndices[k] = body.indices[f * 3 + k];
    }
    addBones(mesh, c, body, scale);
    return mesh;
}

aiNodeAnim* jointChannel(const SampledScene& s, const CharacterTake& c, int j, float scale) {
    const Motion& m = c.motion;
    const auto frames = static_cast<unsigned>(m.frameCount());
    auto* ch = new aiNodeAnim();
    ch->mNodeName = jointNodeName(c, j);
    ch->mNumPositionKeys = frames;
    ch->mPositionKeys = new aiVectorKey[frames];
    ch->mNumRotationKeys = frames;
    ch->mRotationKeys = new aiQuatKey[frames];
    for (unsigned f = 0; f < frames; ++f) {
        const glm::quat q = m.rotations(static_cast<int>(f))[static_cast<std::size_t>(j)];
        const double t = s.time(static_cast<int>(f));
        ch->mPositionKeys[f] = aiVectorKey(t, toAi(m.translations(static_cast<int>(f))[static_cast<std::size_t>(j)] * scale));
        ch->mRotationKeys[f] = aiQuatKey(t, aiQuaternion(q.w, q.x, q.y, q.z));
    }
    ch->mNumScalingKeys = 1;
    ch->mScalingKeys = new aiVectorKey[1];
    ch->mScalingKeys[0] = aiVectorKey(0.0, aiVector3D(1.0f, 1.0f, 1.0f));
    return ch;
}

aiAnimation* animation(const SampledScene& s, std::string_view name, float scale) {
    auto* anim = new aiAnimation();
    anim->mName = std::string(name);
    // Key times in seconds (one tick per second): Assimp 5.2's FBX exporter
    // writes a key's time as if its ticks were seconds (it ignores
    // mTicksPerSecond there, but not for the animation's length).
    anim->mTicksPerSecond = 1.0;
    anim->mDuration = s.time(s.frames - 1);
    std::vector<aiNodeAnim*> channels;
    for (const auto& c : s.characters) {
        for (int j = 0; j < c.motion.jointCount(); ++j) channels.push_back(jointChannel(s, c, j, scale));
    }
    anim->mNumChannels = static_cast<unsigned>(channels.size());
    anim->mChannels = copyArray(channels);
    return anim;
}

std::vector<aiMaterial*> materials(const SampledScene& s, std::map<int, unsigned>& index) {
    std::set<int> sides;
    for (const auto& c : s.characters) sides.insert(c.side);
    std::vector<aiMaterial*> out;
    for (int side : sides) {
        auto* mat = new aiMaterial();
        const aiString name("side " + std::to_string(side));
        mat->AddProperty(&name, AI_MATKEY_NAME);
        const glm::vec3 col = sideColour(side);
        const aiColor3D diffuse(col.x, col.y, col.z);
        mat->AddProperty(&diffuse, 1, AI_MATKEY_COLOR_DIFFUSE);
        index[side] = static_cast<unsigned>(out.size());
        out.push_back(mat);
    }
    return out;
}

}  // namespace

std::string jointNodeName(const CharacterTake& c, int joint) {
    return c.fileName + "_" + c.motion.skeleton().names[static_cast<std::size_t>(joint)];
}

std::unique_ptr<aiScene> buildAssimpScene(const SampledScene& s, std::string_view name, float unitScale) {
    auto scene = std::make_unique<aiScene>();
    std::map<int, unsigned> materialOfSide;
    const auto mats = materials(s, materialOfSide);
    scene->mNumMaterials = static_cast<unsigned>(mats.size());
    scene->mMaterials = copyArray(mats);
    scene->mRootNode = new aiNode("RootNode");
    std::vector<aiMesh*> meshes;
    std::vector<aiNode*> characterNodes;
    for (const auto& c : s.characters) {
        auto* node = new aiNode(c.fileName);
        auto* meshNode = new aiNode(c.fileName + "_body");
        meshNode->mNumMeshes = 1;
        meshNode->mMeshes = new unsigned[1]{static_cast<unsigned>(meshes.size())};
        meshes.push_back(bodyMesh(c, materialOfSide.at(c.side), unitScale));
        setChildren(node, {jointNodes(c, unitScale), meshNode});
        characterNodes.push_back(node);
    }
    setChildren(scene->mRootNode, characterNodes);
    scene->mNumMeshes = static_cast<unsigned>(meshes.size());
    scene->mMeshes = copyArray(meshes);
    scene->mNumAnimations = 1;
    scene->mAnimations = new aiAnimation*[1]{animation(s, name, unitScale)};
    return scene;
}

}  // namespace fray::exporter
