// The skeleton of a user's rig file, as a retarget target (fray/io/rig_import.h).
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "assimp_errors.h"
#include "fray/io/import.h"
#include "fray/io/rig_import.h"

namespace fray {
namespace {

glm::dmat4 toGlm(const aiMatrix4x4& m) {
    glm::dmat4 out(1.0);
    for (unsigned r = 0; r < 4; ++r)
        for (unsigned c = 0; c < 4; ++c)
            out[static_cast<glm::length_t>(c)][static_cast<glm::length_t>(r)] = static_cast<double>(m[r][c]);
    return out;
}

// Rotation of a transform with its scale removed (Gram-Schmidt on the axes).
glm::dquat rotationOf(const glm::dmat4& m) {
    glm::dvec3 x(m[0]), y(m[1]);
    if (glm::length(x) < 1e-12 || glm::length(y) < 1e-12) return {1, 0, 0, 0};
    x = glm::normalize(x);
    y = glm::normalize(y - x * glm::dot(x, y));
    return glm::normalize(glm::quat_cast(glm::dmat3(x, y, glm::cross(x, y))));
}

bool isHelper(const std::string& name) { return name.find("_$AssimpFbx$_") != std::string::npos; }

struct Node {
    const aiNode* ai = nullptr;
    int parent = -1;
    glm::dmat4 global{1.0};
};

Result<RigSkeleton> fromBvh(const std::filesystem::path& path) {
    auto m = loadMotion(path);
    if (!m) return m.error();
    if (auto st = checkRetargetable(m->skeleton(), path.string()); !st) return st.error();
    RigSkeleton out;
    out.target = retargetTargetFromRest(m->skeleton(), path.filename().string());
    // Z-up files lie on their back in the rest pose: stand them up as normalize() does.
    if (m->source().sourceUp == UpAxis::Z) out.target.rotations[0] = glm::angleAxis(-glm::half_pi<float>(), glm::vec3(1, 0, 0));
    out.warnings.push_back("a BVH file has no mesh: the rig's skeleton is used with Fray's capsule body");
    return out;
}

}  // namespace

Result<RigSkeleton> loadRigSkeleton(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return makeError(file + ": file not found");
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".bvh") return fromBvh(path);

    Assimp::Importer importer;
    configureRigImporter(importer);
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
    const aiScene* scene = importer.ReadFile(file, aiProcess_ValidateDataStructure);
    if (!scene || !scene->mRootNode) return makeError(file + ": Assimp cannot read the file: " + assimpErrorText(importer));

    // Every node, parents first, with its global rest transform.
    std::vector<Node> nodes;
    std::vector<std::pair<const aiNode*, int>> stack{{scene->mRootNode, -1}};
    while (!stack.empty()) {
        auto [n, parent] = stack.back();
        stack.pop_back();
        Node node{n, parent, toGlm(n->mTransformation)};
        if (parent >= 0) node.global = nodes[static_cast<std::size_t>(parent)].global * node.global;
        const int self = static_cast<int>(nodes.size());
        nodes.push_back(node);
        for (unsigned c = n->mNumChildren; c-- > 0;) stack.push_back({n->mChildren[c], self});
    }
    // Bones of skinned meshes, if any.
    std::vector<std::string> bones;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* mesh = scene->mMeshes[m];
        for (unsigned b = 0; mesh && b < mesh->mNumBones; ++b) bones.emplace_back(mesh->mBones[b]->mName.C_Str());
    }
    RigSkeleton out;
    out.skinned = !bones.empty();
    if (!out.skinned)
        out.warnings.push_back(scene->mNumMeshes == 0 ? "the file has no mesh (a skeleton only): the rig's skeleton is used with "
                                                        "Fray's capsule body"
                                                      : "no mesh of the file is skinned (no bone weights): the rig's skeleton "
                                                        "is used with Fray's capsule body");

    // Candidate joints: nodes that hold no mesh and are not FBX helpers; the
    // skeleton is the subtree of the pelvis the joint names give.
    Skeleton all;
    std::vector<int> nodeOfJoint, jointOfNode(nodes.size(), -1);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const std::string name = nodes[i].ai->mName.C_Str();
        if (nodes[i].ai->mNumMeshes > 0 || isHelper(name) || name.empty()) continue;
        int p = nodes[i].parent;
        while (p >= 0 && jointOfNode[static_cast<std::size_t>(p)] < 0) p = nodes[static_cast<std::size_t>(p)].parent;
        if (all.find(name) >= 0) continue;  // a second node of one name: not a joint of ours
        jointOfNode[i] = all.addJoint(name, p >= 0 ? jointOfNode[static_cast<std::size_t>(p)] : -1, glm::vec3(0),
                                      {Channel::Zrotation, Channel::Xrotation, Channel::Yrotation}, RotationOrder::ZXY);
        nodeOfJoint.push_back(static_cast<int>(i));
    }
    if (all.jointCount() == 0) return makeError(file + ": no skeleton: the file has no nodes that could be joints");
    const StandardJoints guess = guessStandardJoints(all);
    if (auto st = checkRetargetable(all, file); !st) return st.error();
    int root = guess.pelvis;
    // Keep the pelvis's subtree (the nodes above it only place it in the world).
    std::vector<int> keep;
    for (int j = 0; j < all.jointCount(); ++j) {
        int a = j;
        while (a >= 0 && a != root) a = all.parents[static_cast<std::size_t>(a)];
        if (a == root) keep.push_back(j);
    }
    // World positions (file units) and rotations of the kept joints.
    std::vector<glm::dvec3> wp;
    std::vector<glm::dquat> wr;
    for (int j : keep) {
        const glm::dmat4& g = nodes[static_cast<std::size_t>(nodeOfJoint[static_cast<std::size_t>(j)])].global;
        wp.emplace_back(g[3]);
        wr.push_back(rotationOf(g));
    }
    // Units and up axis from the head-above-feet vector, as for captures.
    auto index = [&](int j) { return static_cast<std::size_t>(std::find(keep.begin(), keep.end(), j) - keep.begin()); };
    const glm::dvec3 feet = 0.5 * (wp[index(guess.leftFoot)] + wp[index(guess.rightFoot)]);
    const int top = guess.head >= 0 ? guess.head : (guess.neck >= 0 ? guess.neck : guess.chest);
    const glm::dvec3 up = top >= 0 && index(top) < keep.size() ? wp[index(top)] - feet : glm::dvec3(0, 1, 0);
    const bool zUp = std::abs(up.z) > std::abs(up.y);
    const double height = glm::length(up);
    double scale = 1.0;
    const char* unit = "m";
    double best = 1e300;
    for (auto [s, name] : {std::pair{1.0, "m"}, std::pair{0.01, "cm"}, std::pair{0.001, "mm"}, std::pair{0.0254, "inch"}}) {
        const double err = std::abs(std::log(std::max(height * s, 1e-12) / 1.5));
        if (err < best) best = err, scale = s, unit = name;
    }
    if (std::string(unit) != "m" || zUp)
        out.warnings.push_back(std::string("rig read as ") + unit + (zUp ? ", Z up" : "") + " (from its height, " +
                               std::to_string(height) + " file units head to ankles)");
    const glm::dquat toYUp = zUp ? glm::angleAxis(-glm::half_pi<double>(), glm::dvec3(1, 0, 0)) : glm::dquat(1, 0, 0, 0);

    RetargetTarget& t = out.target;
    t.name = path.filename().string();
    std::vector<int> newIndex(static_cast<std::size_t>(all.jointCount()), -1);
    for (std::size_t k = 0; k < keep.size(); ++k) {
        const int j = keep[k];
        const int p = j == root ? -1 : newIndex[static_cast<std::size_t>(all.parents[static_cast<std::size_t>(j)])];
        const glm::dvec3 pos = toYUp * wp[k] * scale;
        const glm::dquat rot = toYUp * wr[k];
        glm::dvec3 local = pos;
        glm::dquat localRot = rot;
        if (p >= 0) {
            const std::size_t pk = index(all.parents[static_cast<std::size_t>(j)]);
            const glm::dquat prot = toYUp * wr[pk];
            local = glm::inverse(prot) * (pos - toYUp * wp[pk] * scale);
            localRot = glm::inverse(prot) * rot;
        }
        std::vector<Channel> channels = {Channel::Zrotation, Channel::Xrotation, Channel::Yrotation};
        if (p < 0) channels.insert(channels.begin(), {Channel::Xposition, Channel::Yposition, Channel::Zposition});
        newIndex[static_cast<std::size_t>(j)] =
            t.skeleton.addJoint(all.names[static_cast<std::size_t>(j)], p, glm::vec3(local), std::move(channels), RotationOrder::ZXY);
        t.translations.push_back(glm::vec3(local));
        t.rotations.push_back(glm::quat(glm::normalize(localRot)));
    }
    if (auto msg = t.skeleton.validate()) return makeError(file + ": the rig's skeleton is not usable: " + *msg);
    if (out.skinned) {
        auto skin = loadRig(path, t.skeleton);
        if (skin) {
            out.skin = std::move(*skin);
            out.warnings.push_back("the rig's own skinned mesh (" + std::to_string(out.skin->vertices.size()) +
                                   " vertices) is the exported body");
        } else {
            out.warnings.push_back("the rig's skin could not be bound to its skeleton (" + skin.error().message +
                                   "): Fray's capsule body is used");
        }
    }
    return out;
}

}  // namespace fray
