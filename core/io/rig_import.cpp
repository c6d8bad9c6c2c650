// Rig loader: the skinned meshes of an Assimp scene bound to a motion's
// skeleton (see fray/io/rig_import.h for what it decides and why).
//
// Assimp's skinning model: a vertex v of a mesh lands at
// sum_b w_b * global_b(t) * offset_b * v, where offset_b (aiBone::mOffsetMatrix)
// takes mesh space to bone space in the bind pose, so inverse(offset_b) is the
// bone's bind frame in mesh space. We express every mesh in one "model" space
// (the first skinned mesh's), find each joint's bind frame there, then scale
// and turn the model into the skeleton's units and axes.
#include "fray/io/rig_import.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "assimp_errors.h"
#include "fray/core/body_mesh.h"

namespace fray {
namespace {

constexpr std::size_t kNamesShown = 5;

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// "a, b, c and 4 more" with the names quoted.
std::string listNames(const std::vector<std::string>& names) {
    std::string out;
    for (std::size_t i = 0; i < names.size() && i < kNamesShown; ++i) out += (i ? ", '" : "'") + names[i] + "'";
    if (names.size() > kNamesShown) out += " and " + std::to_string(names.size() - kNamesShown) + " more";
    return out;
}

// aiMatrix4x4 is row-major for column vectors (m[row][col]); glm is column-major.
glm::dmat4 toGlm(const aiMatrix4x4& m) {
    glm::dmat4 out(1.0);
    for (unsigned r = 0; r < 4; ++r)
        for (unsigned c = 0; c < 4; ++c) out[static_cast<glm::length_t>(c)][static_cast<glm::length_t>(r)] = static_cast<double>(m[r][c]);
    return out;
}

glm::dvec3 toGlm(const aiVector3D& v) { return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)}; }

// Name after the last ':' or '|' ("mixamorig:Hips" -> "Hips", "Armature|Hips" -> "Hips").
std::string_view withoutNamespace(std::string_view name) {
    const auto at = name.find_last_of(":|");
    return at == std::string_view::npos ? name : name.substr(at + 1);
}

// The prefix every name shares, up to and including its last separator
// ("red_Hips", "red_Spine" -> "red_"); empty when there is none.
std::string sharedPrefix(const std::vector<std::string>& names) {
    if (names.size() < 2) return {};
    std::string p = names.front();
    for (const std::string& n : names) {
        std::size_t k = 0;
        while (k < p.size() && k < n.size() && p[k] == n[k]) ++k;
        p.resize(k);
    }
    const auto sep = p.find_last_of(":|_.- ");
    return sep == std::string::npos ? std::string() : p.substr(0, sep + 1);
}

// Rig bone name -> skeleton joint: exact, then ignoring case, each tried on
// the name as it is, without its namespace, and without the shared prefix;
// skeleton names are also compared without their own namespace.
class JointMatcher {
public:
    JointMatcher(const Skeleton& sk, const std::vector<std::string>& boneNames) : sk_(sk), prefix_(sharedPrefix(boneNames)) {
        for (int j = 0; j < sk.jointCount(); ++j) {
            const std::string& n = sk.names[static_cast<std::size_t>(j)];
            byLower_.emplace(lower(n), j);  // first joint of a name wins
            byLowerStripped_.emplace(lower(withoutNamespace(n)), j);
        }
    }

    int match(std::string_view bone) const {
        const std::array<std::string_view, 3> candidates{
            bone, withoutNamespace(bone),
            !prefix_.empty() && bone.size() > prefix_.size() && bone.substr(0, prefix_.size()) == prefix_ ? bone.substr(prefix_.size())
                                                                                                          : bone};
        for (std::string_view c : candidates) {
            if (const int j = sk_.find(c); j >= 0) return j;
            const std::string l = lower(c);
            if (auto it = byLower_.find(l); it != byLower_.end()) return it->second;
            if (auto it = byLowerStripped_.find(l); it != byLowerStripped_.end()) return it->second;
        }
        return -1;
    }

private:
    const Skeleton& sk_;
    std::string prefix_;
    std::map<std::string, int> byLower_, byLowerStripped_;
};

// The 24 rotations that map coordinate axes onto coordinate axes (signed
// permutation matrices with determinant +1).
std::vector<glm::dmat3> axisRotations() {
    std::vector<glm::dmat3> out;
    const std::array<std::array<int, 3>, 6> perms{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
    for (const auto& p : perms)
        for (int signs = 0; signs < 8; ++signs) {
            glm::dmat3 m(0.0);
            for (int c = 0; c < 3; ++c) m[c][p[static_cast<std::size_t>(c)]] = (signs >> c) & 1 ? -1.0 : 1.0;
            if (glm::determinant(m) > 0.0) out.push_back(m);
        }
    return out;
}

// Rotation and translation of a bind frame; scale and shear are dropped
// (reported by `scaled`).
struct Frame {
    glm::dmat3 rotation{1.0};
    glm::dvec3 position{0.0};
    bool scaled = false;
};

Frame rigidPart(const glm::dmat4& m) {
    Frame f;
    f.position = glm::dvec3(m[3]);
    glm::dvec3 x(m[0]), y(m[1]);
    const double sx = glm::length(x), sy = glm::length(y), sz = glm::length(glm::dvec3(m[2]));
    const double det = glm::determinant(glm::dmat3(m));
    f.scaled = std::abs(sx - 1.0) > 1e-3 || std::abs(sy - 1.0) > 1e-3 || std::abs(sz - 1.0) > 1e-3 || det < 0.0;
    if (!(sx > 1e-12) || !(sy > 1e-12)) return f;  // degenerate: identity rotation
    x /= sx;
    y = glm::normalize(y - x * glm::dot(x, y));
    f.rotation = glm::dmat3(x, y, glm::cross(x, y));
    return f;
}

// A matrix that cannot be inverted: a zero or non-finite axis, or axes in one
// plane (relative to their lengths, so tiny units are not mistaken for it).
bool singular(const glm::dmat4& m) {
    const double a = glm::length(glm::dvec3(m[0])), b = glm::length(glm::dvec3(m[1])), c = glm::length(glm::dvec3(m[2]));
    const double det = glm::determinant(glm::dmat3(m));
    return !std::isfinite(det) || !(a > 0.0 && b > 0.0 && c > 0.0) || std::abs(det) < 1e-9 * a * b * c;
}

// Global transform of the node holding mesh `index`, if any.
bool meshNodeTransform(const aiNode* node, unsigned index, const glm::dmat4& parent, glm::dmat4& out) {
    const glm::dmat4 global = parent * toGlm(node->mTransformation);
    for (unsigned i = 0; i < node->mNumMeshes; ++i)
        if (node->mMeshes[i] == index) {
            out = global;
            return true;
        }
    for (unsigned c = 0; c < node->mNumChildren; ++c)
        if (meshNodeTransform(node->mChildren[c], index, global, out)) return true;
    return false;
}

struct Influence {
    std::uint32_t vertex;
    int joint;
    float weight;
};

class RigBuilder {
public:
    RigBuilder(const std::filesystem::path& path, const Skeleton& sk) : file_(path.string()), sk_(sk) {}

    Result<SkinnedMesh> run() {
        std::error_code ec;
        if (!std::filesystem::exists(file_, ec)) return fail("file not found");
        if (sk_.jointCount() == 0) return fail("the skeleton to bind the rig to has no joints");
        if (sk_.jointCount() > kMaxSkinnedJoints)
            return fail("the skeleton has " + std::to_string(sk_.jointCount()) + " joints; rigs support at most " +
                        std::to_string(kMaxSkinnedJoints));
        Assimp::Importer importer;
        configureRigImporter(importer);
        const aiScene* scene = importer.ReadFile(file_, 0);
        if (!scene) return fail("Assimp cannot read the file: " + assimpErrorText(importer));
        // Said before validation, which would call a scene without meshes invalid.
        if (scene->mNumMeshes == 0 || !scene->mMeshes) return fail("no mesh in the file (a rig needs a skinned mesh)");
        // Validation turns inconsistent files (indices past the vertices, bad
        // weights) into errors before we read them.
        scene = importer.ApplyPostProcessing(aiProcess_ValidateDataStructure | aiProcess_Triangulate | aiProcess_GenSmoothNormals |
                                             aiProcess_PopulateArmatureData);
        if (!scene) return fail("Assimp cannot read the file: " + assimpErrorText(importer));
        if (Status s = pickMeshes(*scene); !s) return s.error();
        if (Status s = mapBones(); !s) return s.error();
        if (Status s = placeMeshes(*scene); !s) return s.error();
        if (Status s = gatherVertices(); !s) return s.error();
        fitToSkeleton();
        return finish();
    }

private:
    Error fail(const std::string& what) const { return makeError(file_ + ": " + what); }

    // The skinned meshes of the first armature (bone->mArmature, from
    // aiProcess_PopulateArmatureData; meshes without it form one group).
    Status pickMeshes(const aiScene& scene) {
        const aiNode* armature = nullptr;
        bool first = true;
        std::vector<std::string> others;
        for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
            const aiMesh* mesh = scene.mMeshes[m];
            if (!mesh || mesh->mNumBones == 0 || !mesh->mBones || mesh->mNumFaces == 0) continue;
            const aiNode* a = mesh->mBones[0]->mArmature;
            if (first) {
                armature = a;
                first = false;
            }
            if (a != armature) {
                others.push_back(a ? a->mName.C_Str() : "?");
                continue;
            }
            meshes_.push_back(mesh);
            meshIndex_.push_back(m);
        }
        if (meshes_.empty())
            return fail("no skinned mesh: none of the file's " + std::to_string(scene.mNumMeshes) + " meshes has bones");
        if (!others.empty())
            warnings_.push_back("the file has skinned meshes on " + std::to_string(others.size() + 1) +
                                " armatures; only the first ('" + std::string(armature ? armature->mName.C_Str() : "?") +
                                "') is used");
        return {};
    }

    // Every bone that carries weight must match a joint.
    Status mapBones() {
        std::vector<std::string> names;
        for (const aiMesh* mesh : meshes_)
            for (unsigned b = 0; b < mesh->mNumBones; ++b)
                if (mesh->mBones[b]->mNumWeights > 0) names.emplace_back(mesh->mBones[b]->mName.C_Str());
        const JointMatcher matcher(sk_, names);
        std::vector<std::string> unmatched;
        boneJoint_.resize(meshes_.size());
        boneOfJoint_.assign(static_cast<std::size_t>(sk_.jointCount()), std::string());
        for (std::size_t m = 0; m < meshes_.size(); ++m) {
            const aiMesh* mesh = meshes_[m];
            for (unsigned b = 0; b < mesh->mNumBones; ++b) {
                const aiBone* bone = mesh->mBones[b];
                const std::string name = bone->mName.C_Str();
                const int j = matcher.match(name);
                boneJoint_[m].push_back(j);
                if (j >= 0 && boneOfJoint_[static_cast<std::size_t>(j)].empty()) boneOfJoint_[static_cast<std::size_t>(j)] = name;
                if (j < 0 && bone->mNumWeights > 0 && std::find(unmatched.begin(), unmatched.end(), name) == unmatched.end())
                    unmatched.push_back(name);
            }
        }
        if (!unmatched.empty()) {
            std::vector<std::string> joints(sk_.names.begin(), sk_.names.end());
            return fail(std::to_string(unmatched.size()) + (unmatched.size() == 1 ? " bone matches" : " bones match") +
                        " no joint of the skeleton (by name, ignoring case and 'namespace:' prefixes): " + listNames(unmatched) +
                        "; the skeleton's joints are " + listNames(joints));
        }
        return {};
    }

    // Each mesh's transform into model space (the first mesh's space): through
    // a bone it shares with a mesh already placed, else through the nodes.
    Status placeMeshes(const aiScene& scene) {
        bindFrame_.assign(static_cast<std::size_t>(sk_.jointCount()), glm::dmat4(1.0));
        std::vector<char> known(static_cast<std::size_t>(sk_.jointCount()), 0);
        glm::dmat4 firstNode(1.0);
        const bool haveFirstNode = meshNodeTransform(scene.mRootNode, meshIndex_.front(), glm::dmat4(1.0), firstNode);
        for (std::size_t m = 0; m < meshes_.size(); ++m) {
            const aiMesh* mesh = meshes_[m];
            glm::dmat4 toModel(1.0);
            bool placed = m == 0;
            for (unsigned b = 0; b < mesh->mNumBones && !placed; ++b) {
                const int j = boneJoint_[m][b];
                if (j < 0 || !known[static_cast<std::size_t>(j)]) continue;
                toModel = bindFrame_[static_cast<std::size_t>(j)] * toGlm(mesh->mBones[b]->mOffsetMatrix);
                placed = true;
            }
            glm::dmat4 node(1.0);
            if (!placed && haveFirstNode && meshNodeTransform(scene.mRootNode, meshIndex_[m], glm::dmat4(1.0), node))
                toModel = glm::inverse(firstNode) * node;
            meshToModel_.push_back(toModel);
            for (unsigned b = 0; b < mesh->mNumBones; ++b) {
                const int j = boneJoint_[m][b];
                if (j < 0 || known[static_cast<std::size_t>(j)]) continue;
                const glm::dmat4 offset = toGlm(mesh->mBones[b]->mOffsetMatrix);
                if (singular(offset))
                    return fail("bone '" + std::string(mesh->mBones[b]->mName.C_Str()) + "' has a singular offset matrix");
                bindFrame_[static_cast<std::size_t>(j)] = toModel * glm::inverse(offset);
                known[static_cast<std::size_t>(j)] = 1;
            }
        }
        mapped_ = std::move(known);
        return {};
    }

    // Vertices in model space with their four heaviest joints; triangles.
    Status gatherVertices() {
        std::vector<Influence> influences;
        std::size_t total = 0;
        for (const aiMesh* mesh : meshes_) total += mesh->mNumVertices;
        if (total > std::size_t{1} << 31) return fail("the rig has too many vertices (" + std::to_string(total) + ")");
        positions_.reserve(total);
        normals_.reserve(total);
        for (std::size_t m = 0; m < meshes_.size(); ++m) {
            const aiMesh* mesh = meshes_[m];
            const auto base = static_cast<std::uint32_t>(positions_.size());
            const glm::dmat4& toModel = meshToModel_[m];
            const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(toModel)));
            for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
                positions_.push_back(glm::dvec3(toModel * glm::dvec4(toGlm(mesh->mVertices[v]), 1.0)));
                const glm::dvec3 n = mesh->mNormals ? normalMatrix * toGlm(mesh->mNormals[v]) : glm::dvec3(0.0, 1.0, 0.0);
                const double len = glm::length(n);
                normals_.push_back(len > 1e-12 ? n / len : glm::dvec3(0.0, 1.0, 0.0));
            }
            for (unsigned b = 0; b < mesh->mNumBones; ++b) {
                const aiBone* bone = mesh->mBones[b];
                const int j = boneJoint_[m][b];
                for (unsigned k = 0; k < bone->mNumWeights && j >= 0; ++k) {
                    const aiVertexWeight& w = bone->mWeights[k];
                    if (w.mVertexId >= mesh->mNumVertices)
                        return fail("bone '" + std::string(bone->mName.C_Str()) + "' weights vertex " + std::to_string(w.mVertexId) +
                                    " of mesh '" + mesh->mName.C_Str() + "', which has " + std::to_string(mesh->mNumVertices));
                    if (std::isfinite(w.mWeight) && w.mWeight > 0.0f) influences.push_back({base + w.mVertexId, j, w.mWeight});
                }
            }
            for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
                const aiFace& face = mesh->mFaces[f];
                if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
                for (unsigned k = 0; k < 3; ++k) indices_.push_back(base + face.mIndices[k]);
            }
        }
        if (indices_.empty()) return fail("the skinned meshes have no triangles");
        return keepHeaviest(influences);
    }

    // Sums the weights of each (vertex, joint), keeps the four largest, renormalises.
    Status keepHeaviest(std::vector<Influence>& influences) {
        std::sort(influences.begin(), influences.end(), [](const Influence& a, const Influence& b) {
            return a.vertex != b.vertex ? a.vertex < b.vertex : a.joint < b.joint;
        });
        skin_.assign(positions_.size(), {});
        std::vector<std::pair<float, int>> vertexJoints;
        std::size_t i = 0;
        while (i < influences.size()) {
            const std::uint32_t v = influences[i].vertex;
            vertexJoints.clear();
            for (; i < influences.size() && influences[i].vertex == v; ++i) {
                if (!vertexJoints.empty() && vertexJoints.back().second == influences[i].joint) vertexJoints.back().first += influences[i].weight;
                else vertexJoints.emplace_back(influences[i].weight, influences[i].joint);
            }
            std::sort(vertexJoints.begin(), vertexJoints.end(), [](const auto& a, const auto& b) {
                return a.first != b.first ? a.first > b.first : a.second < b.second;
            });
            if (vertexJoints.size() > 4) {
                vertexJoints.resize(4);
                ++trimmed_;
            }
            float sum = 0.0f;
            for (const auto& [w, j] : vertexJoints) sum += w;
            Skin& s = skin_[v];
            for (std::size_t k = 0; k < vertexJoints.size(); ++k) {
                s.joints[k] = static_cast<std::uint16_t>(vertexJoints[k].second);
                s.weights[static_cast<glm::length_t>(k)] = vertexJoints[k].first / sum;
            }
            s.weighted = true;
        }
        std::size_t unweighted = 0, firstUnweighted = 0;
        for (std::size_t v = 0; v < skin_.size(); ++v)
            if (!skin_[v].weighted && unweighted++ == 0) firstUnweighted = v;
        if (unweighted > 0) {
            const auto [mesh, local] = meshOfVertex(firstUnweighted);
            return fail(std::to_string(unweighted) + " of " + std::to_string(skin_.size()) +
                        " vertices have no bone weights (the first: vertex " + std::to_string(local) + " of mesh '" +
                        meshes_[mesh]->mName.C_Str() + "')");
        }
        if (trimmed_ > 0)
            warnings_.push_back(std::to_string(trimmed_) + " vertices had more than 4 bone weights; the 4 largest were kept");
        return {};
    }

    std::pair<std::size_t, std::size_t> meshOfVertex(std::size_t v) const {
        std::size_t m = 0;
        while (m + 1 < meshes_.size() && v >= meshes_[m]->mNumVertices) v -= meshes_[m++]->mNumVertices;
        return {m, v};
    }

    // Scale, axes and the bind mode (see the header): measured on the
    // matched parent-child pairs of the skeleton.
    void fitToSkeleton() {
        std::vector<int> pairs;  // child joints whose parent is matched too
        std::vector<double> ratios;
        for (int j = 0; j < sk_.jointCount(); ++j) {
            const int p = sk_.parents[static_cast<std::size_t>(j)];
            if (p < 0 || !mapped_[static_cast<std::size_t>(j)] || !mapped_[static_cast<std::size_t>(p)]) continue;
            const double skLen = glm::length(glm::dvec3(sk_.offsets[static_cast<std::size_t>(j)]));
            const double rigLen = glm::length(framePos(j) - framePos(p));
            if (skLen < 1e-6 || rigLen < 1e-12) continue;
            pairs.push_back(j);
            ratios.push_back(skLen / rigLen);
        }
        if (ratios.empty()) {
            warnings_.push_back("no two matched joints are parent and child, so the rig's units and axes could not be measured; "
                                "it is used as it is");
            return;
        }
        std::nth_element(ratios.begin(), ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2), ratios.end());
        scale_ = ratios[ratios.size() / 2];

        // Bone frames: the child's offset seen from the parent's bind frame.
        double errFrames = 0.0;
        int worstFrames = -1;
        for (int j : pairs) {
            const int p = sk_.parents[static_cast<std::size_t>(j)];
            const Frame fp = rigidPart(bindFrame_[static_cast<std::size_t>(p)]);
            const glm::dvec3 local = glm::transpose(fp.rotation) * (framePos(j) - fp.position) * scale_;
            const double e = glm::length(local - glm::dvec3(sk_.offsets[static_cast<std::size_t>(j)]));
            if (e > errFrames) errFrames = e, worstFrames = j;
        }
        // Rest pose: the best axis-aligned turn of the whole rig.
        double bestSum = 1e300;
        for (const glm::dmat3& a : axisRotations()) {
            double sum = 0.0;
            for (int j : pairs) {
                const int p = sk_.parents[static_cast<std::size_t>(j)];
                const glm::dvec3 d = a * (framePos(j) - framePos(p)) * scale_ - glm::dvec3(sk_.offsets[static_cast<std::size_t>(j)]);
                sum += glm::dot(d, d);
            }
            if (sum < bestSum - 1e-12) bestSum = sum, axes_ = a;
        }
        double errRest = 0.0;
        int worstRest = -1;
        for (int j : pairs) {
            const int p = sk_.parents[static_cast<std::size_t>(j)];
            const double e = glm::length(axes_ * (framePos(j) - framePos(p)) * scale_ - glm::dvec3(sk_.offsets[static_cast<std::size_t>(j)]));
            if (e > errRest) errRest = e, worstRest = j;
        }
        // Ties go to the bone frames: the offset matrices as the file gives them.
        restMode_ = errRest + 1e-6 < errFrames;
        const double err = restMode_ ? errRest : errFrames;
        const int worst = restMode_ ? worstRest : worstFrames;
        const double size = skeletonSize();
        if (worst >= 0 && err > 0.05 * size) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.1f cm", err * 100.0);
            warnings_.push_back("the rig's bind pose does not match the skeleton: joint '" + sk_.names[static_cast<std::size_t>(worst)] +
                                "' is " + buf + " from where the skeleton puts it (rest pose or bone frames), so the body may look "
                                "distorted");
        }
    }

    glm::dvec3 framePos(int j) const { return glm::dvec3(bindFrame_[static_cast<std::size_t>(j)][3]); }

    double skeletonSize() const {
        std::vector<glm::dvec3> pos(static_cast<std::size_t>(sk_.jointCount()));
        glm::dvec3 lo(1e300), hi(-1e300);
        for (int j = 0; j < sk_.jointCount(); ++j) {
            const int p = sk_.parents[static_cast<std::size_t>(j)];
            pos[static_cast<std::size_t>(j)] =
                (p >= 0 ? pos[static_cast<std::size_t>(p)] : glm::dvec3(0.0)) + glm::dvec3(sk_.offsets[static_cast<std::size_t>(j)]);
            lo = glm::min(lo, pos[static_cast<std::size_t>(j)]);
            hi = glm::max(hi, pos[static_cast<std::size_t>(j)]);
        }
        const glm::dvec3 d = hi - lo;
        return std::max({d.x, d.y, d.z});
    }

    Result<SkinnedMesh> finish() {
        SkinnedMesh out;
        out.source = file_;
        out.skeletonFingerprint = skeletonFingerprint(sk_);
        out.jointCount = sk_.jointCount();
        out.boneOfJoint = boneOfJoint_;
        const glm::dmat3 toSkeleton = axes_ * scale_;
        out.inverseBind.resize(static_cast<std::size_t>(sk_.jointCount()));
        std::vector<glm::dvec3> bindPos(static_cast<std::size_t>(sk_.jointCount()), glm::dvec3(0.0));
        int scaledBones = 0;
        for (int j = 0; j < sk_.jointCount(); ++j) {
            const auto u = static_cast<std::size_t>(j);
            if (!mapped_[u]) continue;
            const Frame f = rigidPart(bindFrame_[u]);
            scaledBones += f.scaled ? 1 : 0;
            bindPos[u] = toSkeleton * f.position;
            const glm::dmat3 rotation = restMode_ ? glm::dmat3(1.0) : axes_ * f.rotation;
            RigidTransform bind;
            bind.translation = glm::vec3(bindPos[u]);
            bind.rotation = glm::quat(glm::normalize(glm::quat_cast(rotation)));
            out.inverseBind[u] = invert(bind);
        }
        if (scaledBones > 0)
            warnings_.push_back(std::to_string(scaledBones) + " bones have scale or mirroring in their bind transform; "
                                "it is left out (bind frames are rigid)");
        out.vertices.resize(positions_.size());
        double reach = 0.0;
        for (std::size_t v = 0; v < positions_.size(); ++v) {
            SkinnedVertex& sv = out.vertices[v];
            const glm::dvec3 p = toSkeleton * positions_[v];
            sv.position = glm::vec3(p);
            sv.normal = glm::vec3(glm::normalize(axes_ * normals_[v]));
            sv.joints = skin_[v].joints;
            sv.weights = skin_[v].weights;
            reach = std::max(reach, glm::length(p - bindPos[sv.joints[0]]));
        }
        out.reach = static_cast<float>(reach);
        out.indices = std::move(indices_);
        out.warnings = std::move(warnings_);
        if (Status s = checkSkinnedMesh(out, sk_); !s) return fail(s.error().message);
        return out;
    }

    struct Skin {
        std::array<std::uint16_t, 4> joints{0, 0, 0, 0};
        glm::vec4 weights{0.0f};
        bool weighted = false;
    };

    std::string file_;
    const Skeleton& sk_;
    std::vector<const aiMesh*> meshes_;
    std::vector<unsigned> meshIndex_;
    std::vector<std::vector<int>> boneJoint_;  // per mesh, per bone: joint or -1
    std::vector<std::string> boneOfJoint_;
    std::vector<glm::dmat4> meshToModel_;
    std::vector<glm::dmat4> bindFrame_;  // per joint, model space
    std::vector<char> mapped_;           // per joint: has a bind frame
    std::vector<glm::dvec3> positions_, normals_;
    std::vector<Skin> skin_;
    std::vector<std::uint32_t> indices_;
    std::size_t trimmed_ = 0;
    double scale_ = 1.0;
    glm::dmat3 axes_{1.0};
    bool restMode_ = false;
    std::vector<std::string> warnings_;
};

}  // namespace

Result<SkinnedMesh> loadRig(const std::filesystem::path& path, const Skeleton& skeleton) {
    return RigBuilder(path, skeleton).run();
}

}  // namespace fray
