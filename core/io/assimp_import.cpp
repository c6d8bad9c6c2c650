// Assimp importer: one animation of an Assimp scene -> fray::Motion.
//
// Assimp gives a node tree with rest transforms and, per animation, key tracks
// (aiNodeAnim) that replace a node's translation/rotation/scale over time. We
// pick the skeleton's nodes, fold FBX helper nodes into the joints they belong
// to, and sample every joint's local rigid transform on a fixed time grid.
#include "fray/io/assimp_import.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/scene.h>
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "assimp_errors.h"

namespace fray {
namespace {

// Marker Assimp's FBX importer puts into the names of the helper nodes it
// inserts for pre/post rotation, pivots and offsets ("Hips_$AssimpFbx$_PreRotation").
constexpr std::string_view kFbxHelper = "_$AssimpFbx$_";

bool isHelperName(std::string_view name) { return name.find(kFbxHelper) != std::string_view::npos; }

// A rigid transform in double precision: p -> t + r * p.
struct Rigid {
    glm::dvec3 t{0.0};
    glm::dquat r{1.0, 0.0, 0.0, 0.0};
};

Rigid compose(const Rigid& a, const Rigid& b) { return {a.t + a.r * b.t, a.r * b.r}; }

glm::dvec3 toGlm(const aiVector3D& v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

// aiQuaternion stores (w, x, y, z); glm's quaternion members are named, so set
// them one by one and let the storage order be whatever GLM uses.
glm::dquat toGlm(const aiQuaternion& q) {
    glm::dquat out;
    out.w = static_cast<double>(q.w);
    out.x = static_cast<double>(q.x);
    out.y = static_cast<double>(q.y);
    out.z = static_cast<double>(q.z);
    return glm::normalize(out);
}

std::string inQuotes(std::string_view s) { return "'" + std::string(s) + "'"; }

std::string formatVec(const glm::dvec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", v.x, v.y, v.z);
    return buf;
}

bool nonUnit(const glm::dvec3& s) {
    return std::abs(s.x - 1.0) > 1e-3 || std::abs(s.y - 1.0) > 1e-3 || std::abs(s.z - 1.0) > 1e-3;
}

// Index of the key to interpolate from at time t (the last key with time <= t,
// or 0). The cursor makes a forward sweep over the frames linear in the keys.
template <class Key>
unsigned seekKey(const Key* keys, unsigned n, double t, unsigned& cursor) {
    if (cursor >= n || keys[cursor].mTime > t) cursor = 0;
    while (cursor + 1 < n && keys[cursor + 1].mTime <= t) ++cursor;
    return cursor;
}

template <class Key>
double keyWeight(const Key* keys, unsigned n, unsigned i, double t) {
    if (i + 1 >= n || t <= keys[i].mTime) return 0.0;
    const double span = keys[i + 1].mTime - keys[i].mTime;
    if (!(span > 0.0)) return 0.0;
    return std::clamp((t - keys[i].mTime) / span, 0.0, 1.0);
}

struct Node {
    const aiNode* ai = nullptr;
    int parent = -1;      // index in the flattened tree
    bool helper = false;  // FBX "$AssimpFbx$" helper node
    int realParent = -1;  // nearest ancestor that is not a helper
    std::vector<int> chain;  // helper nodes directly above, top-down
    const aiNodeAnim* anim = nullptr;
    Rigid rest;
    glm::dvec3 restScale{1.0};
    bool animated = false;  // real node whose own track or helper chain is animated
    int depth = 0;          // depth among real nodes
};

struct Track {
    unsigned posCursor = 0, rotCursor = 0;
};

class Importer {
public:
    Importer(const std::filesystem::path& path, const AssimpImportOptions& options) : path_(path), opt_(options) {}

    Result<Motion> run() {
        if (auto st = load(); !st) return st.error();
        int root = -1;
        if (auto st = chooseRoot(root); !st) return st.error();
        return skeletonAt(root);
    }

    // One motion per skeleton: with a named root, that one; otherwise, when
    // the animated nodes' common ancestor is not animated itself and more than
    // one of its child subtrees holds animated nodes (a file with several
    // characters), one per such subtree, rooted at the common ancestor of its
    // animated nodes; else the one skeleton run() gives.
    Result<std::vector<Motion>> runAll() {
        if (auto st = load(); !st) return st.error();
        int root = -1;
        if (auto st = chooseRoot(root); !st) return st.error();
        std::vector<int> roots;
        if (opt_.skeletonRoot.empty() && !nodes_[static_cast<std::size_t>(root)].animated) roots = subtreeRoots(root);
        if (roots.size() < 2) roots = {root};
        std::vector<Motion> out;
        for (int r : roots) {
            auto m = skeletonAt(r);
            if (!m) return m.error();
            out.push_back(std::move(*m));
        }
        return out;
    }

private:
    Status load() {
        const std::string file = path_.string();
        bool preservePivots = opt_.preserveFbxPivots;
        const aiScene* scene = nullptr;
        for (int attempt = 0; attempt < 2; ++attempt) {
            importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, preservePivots);
            importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_MATERIALS, false);
            importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_TEXTURES, false);
            importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_CAMERAS, false);
            importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_LIGHTS, false);
            // The BVH loader would otherwise build a mesh of the skeleton we never use.
            importer_.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
            scene = importer_.ReadFile(file, 0);
            if (!scene) return makeError(file + ": Assimp cannot read the file: " + assimpErrorText(importer_));
            if (preservePivots || !needsPivotNodes(scene)) break;
            // Some channels animate pivot helpers that Assimp baked away; import
            // again with the helpers kept so those tracks have nodes to drive.
            preservePivots = true;
            importer_.FreeScene();
        }
        scene_ = scene;

        const aiAnimation* anim = nullptr;
        if (auto st = chooseAnimation(anim); !st) return st.error();
        anim_ = anim;
        flatten();
        bindChannels();
        return {};
    }

    // The skeleton rooted at `root` and its motion (per-skeleton state reset).
    Result<Motion> skeletonAt(int root) {
        joints_.clear();
        jointParents_.clear();
        rootPrefix_.clear();
        warnings_ = sceneWarnings_;
        selectJoints(root);
        return sample();
    }

    // Per child subtree of `top` that holds animated real nodes, the common
    // ancestor of those nodes, in file order.
    std::vector<int> subtreeRoots(int top) const {
        std::vector<int> roots;
        std::vector<int> subtreeOf(nodes_.size(), -1);  // child of `top` each node descends from
        for (std::size_t i = static_cast<std::size_t>(top) + 1; i < nodes_.size(); ++i) {
            const int p = nodes_[i].parent;
            if (p == top) subtreeOf[i] = static_cast<int>(i);
            else if (p >= 0) subtreeOf[i] = subtreeOf[static_cast<std::size_t>(p)];
        }
        std::vector<int> subtrees;
        for (std::size_t i = 0; i < nodes_.size(); ++i) {
            if (nodes_[i].helper || !nodes_[i].animated || subtreeOf[i] < 0) continue;
            const auto at = std::find(subtrees.begin(), subtrees.end(), subtreeOf[i]);
            if (at == subtrees.end()) {
                subtrees.push_back(subtreeOf[i]);
                roots.push_back(static_cast<int>(i));
            } else {
                int& r = roots[static_cast<std::size_t>(at - subtrees.begin())];
                r = lowestCommonAncestor(r, static_cast<int>(i));
                if (r < 0) return {};
            }
        }
        return roots;
    }

    Error fail(const std::string& what) const { return makeError(path_.string() + ": " + what); }

    std::string animName(const aiAnimation* a) const {
        return a->mName.length > 0 ? std::string(a->mName.C_Str()) : std::string("(unnamed)");
    }

    bool needsPivotNodes(const aiScene* scene) const {
        for (unsigned a = 0; a < scene->mNumAnimations; ++a) {
            const aiAnimation* an = scene->mAnimations[a];
            for (unsigned c = 0; c < an->mNumChannels; ++c) {
                const aiString& n = an->mChannels[c]->mNodeName;
                if (isHelperName(n.C_Str()) && !scene->mRootNode->FindNode(n)) return true;
            }
        }
        return false;
    }

    Status chooseAnimation(const aiAnimation*& out) const {
        if (scene_->mNumAnimations == 0 || !scene_->mAnimations)
            return fail("no animation in the file (the scene has " + std::to_string(countNodes(scene_->mRootNode)) +
                        " nodes but no animation to import)");
        if (opt_.animation.empty()) {
            out = scene_->mAnimations[0];
            return {};
        }
        std::string names;
        for (unsigned a = 0; a < scene_->mNumAnimations; ++a) {
            const aiAnimation* an = scene_->mAnimations[a];
            if (opt_.animation == an->mName.C_Str()) {
                out = an;
                return {};
            }
            names += (a ? ", " : "") + inQuotes(animName(an));
        }
        return fail("no animation named " + inQuotes(opt_.animation) + "; available: " + names);
    }

    static std::size_t countNodes(const aiNode* n) {
        if (!n) return 0;
        std::size_t c = 1;
        for (unsigned i = 0; i < n->mNumChildren; ++i) c += countNodes(n->mChildren[i]);
        return c;
    }

    // Depth-first (pre-order) flattening; parents precede children.
    void flatten() {
        struct Item {
            const aiNode* node;
            int parent;
        };
        std::vector<Item> stack{{scene_->mRootNode, -1}};
        while (!stack.empty()) {
            const Item it = stack.back();
            stack.pop_back();
            if (!it.node) continue;
            Node n;
            n.ai = it.node;
            n.parent = it.parent;
            n.helper = isHelperName(it.node->mName.C_Str());
            aiVector3D s, p;
            aiQuaternion q;
            it.node->mTransformation.Decompose(s, q, p);
            n.rest = {toGlm(p), toGlm(q)};
            n.restScale = toGlm(s);
            const int self = static_cast<int>(nodes_.size());
            if (it.parent >= 0) {
                const Node& par = nodes_[static_cast<std::size_t>(it.parent)];
                n.realParent = par.helper ? par.realParent : it.parent;
                if (!n.helper) {
                    for (int a = it.parent; a >= 0 && nodes_[static_cast<std::size_t>(a)].helper;
                         a = nodes_[static_cast<std::size_t>(a)].parent)
                        n.chain.push_back(a);
                    std::reverse(n.chain.begin(), n.chain.end());
                }
                n.depth = (n.realParent >= 0 ? nodes_[static_cast<std::size_t>(n.realParent)].depth + 1 : 0);
            }
            nodes_.push_back(std::move(n));
            byName_.emplace(it.node->mName.C_Str(), self);  // first in pre-order wins, as in aiNode::FindNode
            allByName_[it.node->mName.C_Str()].push_back(self);
            for (unsigned c = it.node->mNumChildren; c-- > 0;) stack.push_back({it.node->mChildren[c], self});
        }
    }

    // Channels name their nodes. Where several nodes share a name (glTF
    // allows it: Fray's own glTF has a "Hips" per character), the k-th channel
    // of that name drives the k-th node of that name in pre-order, the order
    // Assimp keeps for both; a name with one channel drives its first node.
    void bindChannels() {
        int missing = 0;
        std::string firstMissing;
        std::unordered_map<std::string, std::size_t> seen;
        for (unsigned c = 0; c < anim_->mNumChannels; ++c) {
            const aiNodeAnim* ch = anim_->mChannels[c];
            if (!ch) continue;
            const auto it = allByName_.find(ch->mNodeName.C_Str());
            if (it == allByName_.end()) {
                if (missing++ == 0) firstMissing = ch->mNodeName.C_Str();
                continue;
            }
            const std::size_t k = seen[it->first]++;
            Node& n = nodes_[static_cast<std::size_t>(it->second[k < it->second.size() ? k : 0])];
            if (!n.anim) n.anim = ch;
        }
        if (missing > 0)
            sceneWarnings_.push_back(std::to_string(missing) + " animation channel(s) name nodes that are not in the scene (first: " +
                                inQuotes(firstMissing) + "); ignored");
        for (Node& n : nodes_) {
            if (n.helper) continue;
            n.animated = n.anim != nullptr;
            for (int h : n.chain) n.animated = n.animated || nodes_[static_cast<std::size_t>(h)].anim != nullptr;
        }
    }

    int lowestCommonAncestor(int a, int b) const {
        while (a != b) {
            const Node& na = nodes_[static_cast<std::size_t>(a)];
            const Node& nb = nodes_[static_cast<std::size_t>(b)];
            if (na.depth >= nb.depth) a = na.realParent;
            else b = nb.realParent;
            if (a < 0 || b < 0) return -1;
        }
        return a;
    }

    Status chooseRoot(int& root) {
        if (!opt_.skeletonRoot.empty()) {
            const auto it = byName_.find(opt_.skeletonRoot);
            if (it == byName_.end() || nodes_[static_cast<std::size_t>(it->second)].helper)
                return fail("skeleton root " + inQuotes(opt_.skeletonRoot) + " is not a node of the scene");
            root = it->second;
            return {};
        }
        for (std::size_t i = 0; i < nodes_.size(); ++i) {
            if (nodes_[i].helper || !nodes_[i].animated) continue;
            root = root < 0 ? static_cast<int>(i) : lowestCommonAncestor(root, static_cast<int>(i));
            if (root < 0) break;
        }
        if (root < 0)
            return fail("no skeleton: none of the " + std::to_string(anim_->mNumChannels) + " channels of animation " +
                        inQuotes(animName(anim_)) + " names a node of the scene");
        return {};
    }

    // BVH "End Site" nodes and exporters' end bones ("HeadTop_End"): leaf
    // markers, not joints (our BVH reader keeps them as end-site offsets).
    static bool isEndMarker(std::string_view name) {
        std::string n;
        for (char c : name) n.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
        return n.rfind("endsite", 0) == 0 || (n.size() >= 3 && n.compare(n.size() - 3, 3, "end") == 0);
    }

    // The root and every bone below it (animated or not: a toe without keys is
    // still a joint the later steps need), in pre-order. Nodes carrying meshes
    // are geometry, not bones.
    void selectJoints(int root) {
        std::vector<char> keep(nodes_.size(), 0);
        keep[static_cast<std::size_t>(root)] = 1;
        bool anyAnimated = nodes_[static_cast<std::size_t>(root)].animated;
        for (std::size_t i = static_cast<std::size_t>(root) + 1; i < nodes_.size(); ++i) {
            if (nodes_[i].helper || nodes_[i].ai->mNumMeshes > 0) continue;
            if (!nodes_[i].animated && nodes_[i].ai->mNumChildren == 0 && isEndMarker(nodes_[i].ai->mName.C_Str()))
                continue;
            // Is i below the root? Walk up real parents (depth bounds the walk).
            std::vector<int> path;
            int a = static_cast<int>(i);
            while (a >= 0 && nodes_[static_cast<std::size_t>(a)].depth > nodes_[static_cast<std::size_t>(root)].depth) {
                path.push_back(a);
                a = nodes_[static_cast<std::size_t>(a)].realParent;
            }
            if (a != root) continue;
            anyAnimated = anyAnimated || nodes_[i].animated;
            for (int p : path) keep[static_cast<std::size_t>(p)] = 1;
        }
        if (!anyAnimated)
            warnings_.push_back("skeleton root " + inQuotes(nodes_[static_cast<std::size_t>(root)].ai->mName.C_Str()) +
                                ": animation " + inQuotes(animName(anim_)) + " moves nothing at or below it");
        std::vector<int> jointOf(nodes_.size(), -1);
        for (std::size_t i = static_cast<std::size_t>(root); i < nodes_.size(); ++i) {
            if (!keep[i]) continue;
            const int parent = static_cast<int>(i) == root ? -1 : jointOf[static_cast<std::size_t>(nodes_[i].realParent)];
            jointOf[i] = static_cast<int>(joints_.size());
            joints_.push_back(static_cast<int>(i));
            jointParents_.push_back(parent);
        }
        // Nodes above the root (their transforms place the root in the scene).
        for (int a = nodes_[static_cast<std::size_t>(root)].parent; a >= 0; a = nodes_[static_cast<std::size_t>(a)].parent)
            rootPrefix_.push_back(a);
        std::reverse(rootPrefix_.begin(), rootPrefix_.end());
        // The root's own helpers are already in its chain; drop them from the prefix.
        const auto& rootChain = nodes_[static_cast<std::size_t>(root)].chain;
        rootPrefix_.resize(rootPrefix_.size() - rootChain.size());
    }

    // Every node whose transform is needed per frame, each once.
    std::vector<int> involvedNodes() const {
        std::vector<int> out = rootPrefix_;
        for (int j : joints_) {
            const Node& n = nodes_[static_cast<std::size_t>(j)];
            out.insert(out.end(), n.chain.begin(), n.chain.end());
            out.push_back(j);
        }
        return out;
    }

    Rigid evaluate(int index, double t, Track& track) const {
        const Node& n = nodes_[static_cast<std::size_t>(index)];
        if (!n.anim) return n.rest;
        const aiNodeAnim* ch = n.anim;
        Rigid out = n.rest;
        if (ch->mNumPositionKeys > 0 && ch->mPositionKeys) {
            const unsigned i = seekKey(ch->mPositionKeys, ch->mNumPositionKeys, t, track.posCursor);
            const double w = keyWeight(ch->mPositionKeys, ch->mNumPositionKeys, i, t);
            out.t = toGlm(ch->mPositionKeys[i].mValue);
            if (w > 0.0) out.t = glm::mix(out.t, toGlm(ch->mPositionKeys[i + 1].mValue), w);
        }
        if (ch->mNumRotationKeys > 0 && ch->mRotationKeys) {
            const unsigned i = seekKey(ch->mRotationKeys, ch->mNumRotationKeys, t, track.rotCursor);
            const double w = keyWeight(ch->mRotationKeys, ch->mNumRotationKeys, i, t);
            out.r = toGlm(ch->mRotationKeys[i].mValue);
            if (w > 0.0) out.r = glm::normalize(glm::slerp(out.r, toGlm(ch->mRotationKeys[i + 1].mValue), w));
        }
        return out;
    }

    Result<Motion> sample() {
        const std::vector<int> involved = involvedNodes();
        // Scale is not part of the motion model: say so where it is not 1.
        for (int i : involved) {
            const Node& n = nodes_[static_cast<std::size_t>(i)];
            const char* name = n.ai->mName.C_Str();
            if (nonUnit(n.restScale))
                warnings_.push_back("node " + inQuotes(name) + ": rest scale " + formatVec(n.restScale) + " ignored");
            if (n.anim) {
                for (unsigned k = 0; k < n.anim->mNumScalingKeys && n.anim->mScalingKeys; ++k) {
                    if (nonUnit(toGlm(n.anim->mScalingKeys[k].mValue))) {
                        warnings_.push_back("node " + inQuotes(name) + ": scale keys (e.g. " +
                                            formatVec(toGlm(n.anim->mScalingKeys[k].mValue)) + " at tick " +
                                            std::to_string(n.anim->mScalingKeys[k].mTime) + ") ignored");
                        break;
                    }
                }
            }
        }

        // Time range and key spacing of the tracks that move the skeleton.
        double tmin = 0.0, tmax = 0.0, regular = 0.0, irregular = 0.0, spacing = 0.0;
        bool haveRange = false, haveSingle = false;
        double singleMin = 0.0;
        std::vector<double> gaps;
        auto scanKeys = [&](auto* keys, unsigned count) {
            if (!keys || count == 0) return;
            if (count == 1) {
                singleMin = haveSingle ? std::min(singleMin, keys[0].mTime) : keys[0].mTime;
                haveSingle = true;
                return;
            }
            const double a = keys[0].mTime, b = keys[count - 1].mTime;
            tmin = haveRange ? std::min(tmin, a) : a;
            tmax = haveRange ? std::max(tmax, b) : b;
            haveRange = true;
            gaps.clear();
            for (unsigned k = 1; k < count; ++k) {
                const double g = keys[k].mTime - keys[k - 1].mTime;
                if (g > 0.0) gaps.push_back(g);
            }
            if (gaps.empty()) return;
            // The track's typical gap is its median; on a regular grid (every
            // gap within 1% of it) the mean gap is the better estimate, as key
            // times stored in float milliseconds or rounded ticks wobble.
            auto mid = gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2);
            std::nth_element(gaps.begin(), mid, gaps.end());
            const double median = *mid;
            const auto [lo, hi] = std::minmax_element(gaps.begin(), gaps.end());
            if (*hi - *lo <= 0.01 * median) {
                const double mean = (b - a) / static_cast<double>(count - 1);
                regular = regular > 0.0 ? std::min(regular, mean) : mean;
            } else {
                irregular = irregular > 0.0 ? std::min(irregular, median) : median;
            }
        };
        for (int i : involved) {
            const aiNodeAnim* ch = nodes_[static_cast<std::size_t>(i)].anim;
            if (!ch) continue;
            scanKeys(ch->mPositionKeys, ch->mNumPositionKeys);
            scanKeys(ch->mRotationKeys, ch->mNumRotationKeys);
        }
        if (!haveRange) {
            tmin = tmax = haveSingle ? singleMin : 0.0;
        }
        // Prefer the regular tracks' spacing unless an irregular track is
        // clearly denser.
        spacing = regular;
        if (irregular > 0.0 && (spacing <= 0.0 || irregular < 0.99 * spacing)) spacing = irregular;

        double ticksPerSecond = anim_->mTicksPerSecond;
        if (!(ticksPerSecond > 0.0) || !std::isfinite(ticksPerSecond)) {
            ticksPerSecond = spacing > 0.0 ? 30.0 * spacing : 30.0;
            warnings_.push_back("animation " + inQuotes(animName(anim_)) +
                                " gives no tick rate; its keys are taken as frames at 30 fps");
        }
        double fps = opt_.fps;
        double step = 0.0;  // ticks per frame
        if (fps > 0.0 && std::isfinite(fps)) {
            step = ticksPerSecond / fps;
        } else {
            fps = spacing > 0.0 ? ticksPerSecond / spacing : 0.0;
            step = spacing;
            if (!(fps >= 1.0 && fps <= 1000.0)) {
                if (haveRange)
                    warnings_.push_back("frame rate from the keys (" + std::to_string(fps) +
                                        " fps) is implausible; sampled at 30 fps");
                fps = 30.0;
                step = ticksPerSecond / fps;
            }
        }
        const double frameSpan = (tmax - tmin) / step;
        constexpr double kMaxFrames = 10'000'000.0;
        if (!std::isfinite(frameSpan) || frameSpan + 1.0 > kMaxFrames)
            return fail("animation " + inQuotes(animName(anim_)) + " would need more than 10 million frames at " +
                        std::to_string(fps) + " fps");
        const int frames = static_cast<int>(std::floor(frameSpan + 1e-6)) + 1;
        const double bytes = static_cast<double>(frames) * static_cast<double>(joints_.size()) *
                             static_cast<double>(sizeof(glm::vec3) + sizeof(glm::quat));
        if (bytes > static_cast<double>(opt_.maxMotionBytes))
            return fail("animation " + inQuotes(animName(anim_)) + ": " + std::to_string(frames) + " frames x " +
                        std::to_string(joints_.size()) + " joints needs " +
                        std::to_string(static_cast<long long>(bytes / (1 << 20))) + " MiB, over the limit of " +
                        std::to_string(opt_.maxMotionBytes >> 20) + " MiB");

        // Skeleton: names (unique, non-empty), parents, rest offsets.
        Skeleton sk;
        std::unordered_set<std::string> used;
        std::vector<Track> tracks(nodes_.size());
        Rigid prefixRest;
        for (int a : rootPrefix_) prefixRest = compose(prefixRest, nodes_[static_cast<std::size_t>(a)].rest);
        for (std::size_t j = 0; j < joints_.size(); ++j) {
            const Node& n = nodes_[static_cast<std::size_t>(joints_[j])];
            std::string name = n.ai->mName.C_Str();
            if (name.empty()) name = "joint" + std::to_string(j);
            if (!used.insert(name).second) {
                const std::string base = name;
                for (int k = 2; !used.insert(name = base + "_" + std::to_string(k)).second; ++k) {
                }
                warnings_.push_back("duplicate node name " + inQuotes(base) + " renamed to " + inQuotes(name));
            }
            Rigid rest = j == 0 ? prefixRest : Rigid{};
            for (int h : n.chain) rest = compose(rest, nodes_[static_cast<std::size_t>(h)].rest);
            rest = compose(rest, n.rest);
            sk.addJoint(std::move(name), jointParents_[j], glm::vec3(rest.t), {}, RotationOrder::ZXY);
        }

        const auto jc = joints_.size();
        Motion motion(sk, fps, frames);
        auto& T = motion.allTranslations();
        auto& R = motion.allRotations();
        for (int f = 0; f < frames; ++f) {
            const double t = tmin + f * step;
            Rigid prefix;
            for (int a : rootPrefix_) prefix = compose(prefix, evaluate(a, t, tracks[static_cast<std::size_t>(a)]));
            for (std::size_t j = 0; j < jc; ++j) {
                const Node& n = nodes_[static_cast<std::size_t>(joints_[j])];
                Rigid local = j == 0 ? prefix : Rigid{};
                // A track on the joint itself already holds its whole local
                // transform (Assimp bakes pre/post rotation into such keys even
                // when it keeps the helper nodes); helpers count only otherwise.
                if (!n.anim)
                    for (int h : n.chain) local = compose(local, evaluate(h, t, tracks[static_cast<std::size_t>(h)]));
                local = compose(local, evaluate(joints_[j], t, tracks[static_cast<std::size_t>(joints_[j])]));
                const std::size_t k = static_cast<std::size_t>(f) * jc + j;
                T[k] = glm::vec3(local.t);
                R[k] = glm::quat(glm::normalize(local.r));
            }
        }

        // Channels: the root moves freely; other joints get position channels
        // only where their translation leaves the rest offset.
        Skeleton& s = motion.skeleton();
        for (std::size_t j = 0; j < jc; ++j) {
            if (j == 0) {
                s.channels[j] = {Channel::Xposition, Channel::Yposition, Channel::Zposition,
                                 Channel::Zrotation, Channel::Xrotation, Channel::Yrotation};
                continue;
            }
            const glm::vec3 offset = s.offsets[j];
            const float tolerance = 1e-4f * std::max(1.0f, glm::length(offset));
            bool moves = false;
            for (int f = 0; f < frames && !moves; ++f)
                moves = glm::length(T[static_cast<std::size_t>(f) * jc + j] - offset) > tolerance;
            if (moves)
                s.channels[j] = {Channel::Xposition, Channel::Yposition, Channel::Zposition,
                                 Channel::Zrotation, Channel::Xrotation, Channel::Yrotation};
            else
                s.channels[j] = {Channel::Zrotation, Channel::Xrotation, Channel::Yrotation};
        }

        SourceInfo& src = motion.source();
        src.path = path_.string();
        std::string ext = path_.extension().string();
        if (!ext.empty() && ext.front() == '.') ext.erase(0, 1);
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        src.format = ext.empty() ? "assimp" : ext;
        src.warnings = std::move(warnings_);
        return motion;
    }

    std::filesystem::path path_;
    const AssimpImportOptions& opt_;
    Assimp::Importer importer_;
    std::vector<std::string> sceneWarnings_;  // about the file, given with every skeleton
    const aiScene* scene_ = nullptr;
    const aiAnimation* anim_ = nullptr;
    std::vector<Node> nodes_;
    std::unordered_map<std::string, int> byName_;
    std::unordered_map<std::string, std::vector<int>> allByName_;  // every node of each name, in pre-order
    std::vector<int> joints_;        // node index per joint
    std::vector<int> jointParents_;  // joint index of the parent, -1 for the root
    std::vector<int> rootPrefix_;    // nodes above the root (and its helper chain), top-down
    std::vector<std::string> warnings_;
};

}  // namespace

Result<Motion> importWithAssimp(const std::filesystem::path& path, const AssimpImportOptions& options) {
    Importer importer(path, options);
    return importer.run();
}

Result<std::vector<Motion>> importAllWithAssimp(const std::filesystem::path& path, const AssimpImportOptions& options) {
    Importer importer(path, options);
    return importer.runAll();
}

}  // namespace fray
