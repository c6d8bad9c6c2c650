#include "fray/core/body_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

#include "fray/core/joint_guess.h"

namespace fray {
namespace {

constexpr float kPi = 3.14159265358979f;

// Rest-pose size of the skeleton (largest side of the box around the joints),
// used to scale capsule radii for children or unusual rigs.
float restExtent(const Skeleton& sk) {
    std::vector<glm::vec3> pos(static_cast<std::size_t>(sk.jointCount()));
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (int j = 0; j < sk.jointCount(); ++j) {
        const auto u = static_cast<std::size_t>(j);
        const int p = sk.parents[u];
        pos[u] = (p >= 0 ? pos[static_cast<std::size_t>(p)] : glm::vec3(0.0f)) + sk.offsets[u];
        lo = glm::min(lo, pos[u]);
        hi = glm::max(hi, pos[u]);
    }
    if (sk.jointCount() == 0) return 0.0f;
    const glm::vec3 d = hi - lo;
    return std::max({d.x, d.y, d.z});
}

bool isAncestor(const Skeleton& sk, int ancestor, int joint) {
    for (int j = joint; j >= 0; j = sk.parents[static_cast<std::size_t>(j)])
        if (j == ancestor) return true;
    return false;
}

struct Roles {
    StandardJoints sj;
    std::vector<char> torso;  // pelvis and the spine joints below the neck
    int leftClavicle = -1, rightClavicle = -1;
};

Roles findRoles(const Skeleton& sk) {
    Roles r;
    r.sj = guessStandardJoints(sk);
    r.torso.assign(static_cast<std::size_t>(sk.jointCount()), 0);
    const int top = r.sj.neck >= 0 ? r.sj.neck : r.sj.head;
    if (r.sj.pelvis >= 0 && top >= 0 && isAncestor(sk, r.sj.pelvis, top)) {
        for (int j = sk.parents[static_cast<std::size_t>(top)]; j >= 0; j = sk.parents[static_cast<std::size_t>(j)]) {
            r.torso[static_cast<std::size_t>(j)] = 1;
            if (j == r.sj.pelvis) break;
        }
    }
    auto parentOf = [&](int j) { return j >= 0 ? sk.parents[static_cast<std::size_t>(j)] : -1; };
    r.leftClavicle = parentOf(r.sj.leftShoulder);
    r.rightClavicle = parentOf(r.sj.rightShoulder);
    return r;
}

// Radius in metres for a 1.7 m actor of the bone from joint p towards its
// child c (c < 0: towards p's end site).
float boneRadius(const Roles& r, int p, int c, float length) {
    const auto& sj = r.sj;
    const bool pTorso = r.torso[static_cast<std::size_t>(p)] != 0;
    const bool cTorso = c >= 0 && r.torso[static_cast<std::size_t>(c)] != 0;
    if (pTorso && cTorso) return 0.12f;
    if (c >= 0 && (c == sj.leftHip || c == sj.rightHip)) return 0.075f;
    if (p == sj.neck || (c >= 0 && c == sj.neck)) return 0.05f;
    if (c >= 0 && (c == r.leftClavicle || c == r.rightClavicle)) return 0.05f;
    if (p == r.leftClavicle || p == r.rightClavicle) return 0.05f;
    if (p == sj.leftShoulder || p == sj.rightShoulder) return 0.05f;
    if (p == sj.leftElbow || p == sj.rightElbow) return 0.042f;
    if (p == sj.leftHand || p == sj.rightHand) return 0.035f;
    if (p == sj.leftHip || p == sj.rightHip) return 0.07f;
    if (p == sj.leftKnee || p == sj.rightKnee) return 0.055f;
    if (p == sj.leftFoot || p == sj.rightFoot) return 0.045f;
    if (p == sj.leftToe || p == sj.rightToe) return 0.035f;
    return std::clamp(0.18f * length, 0.025f, 0.06f);
}

class CapsuleWriter {
public:
    CapsuleWriter(BodyMesh& mesh, const BodyMeshOptions& o)
        : mesh_(mesh), sides_(std::max(3, o.sides)), capRings_(std::max(1, o.capRings)) {}

    // Capsule around the segment a-b (joint-local), radius r, skinned to joint.
    void add(glm::vec3 a, glm::vec3 b, float r, std::uint32_t joint) {
        glm::vec3 w = b - a;
        const float len = glm::length(w);
        w = len > 1e-6f ? w / len : glm::vec3(0.0f, 1.0f, 0.0f);
        const glm::vec3 helper = std::abs(w.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
        const glm::vec3 u = glm::normalize(glm::cross(helper, w));
        const glm::vec3 v = glm::cross(w, u);

        const auto base = static_cast<std::uint32_t>(mesh_.vertices.size());
        auto push = [&](glm::vec3 center, glm::vec3 n) { mesh_.vertices.push_back({center + n * r, n, joint}); };
        push(a, -w);  // bottom pole
        const int rings = 2 * capRings_;
        for (int ring = 0; ring < rings; ++ring) {
            // Latitude from the bottom pole: bottom cap rings end at the
            // equator around a, top cap rings start at the equator around b.
            const bool top = ring >= capRings_;
            const int k = top ? ring - capRings_ : ring + 1;
            const float phi = top ? (kPi * 0.5f) * static_cast<float>(k) / static_cast<float>(capRings_)
                                  : -kPi * 0.5f + (kPi * 0.5f) * static_cast<float>(k) / static_cast<float>(capRings_);
            const glm::vec3 center = top ? b : a;
            for (int s = 0; s < sides_; ++s) {
                const float theta = 2.0f * kPi * static_cast<float>(s) / static_cast<float>(sides_);
                const glm::vec3 n = std::cos(phi) * (std::cos(theta) * u + std::sin(theta) * v) + std::sin(phi) * w;
                push(center, n);
            }
        }
        push(b, w);  // top pole
        const auto ringStart = [&](int ring) { return base + 1u + static_cast<std::uint32_t>(ring * sides_); };
        const std::uint32_t topPole = base + 1u + static_cast<std::uint32_t>(rings * sides_);
        for (int s = 0; s < sides_; ++s) {
            const auto s0 = static_cast<std::uint32_t>(s);
            const auto s1 = static_cast<std::uint32_t>((s + 1) % sides_);
            tri(base, ringStart(0) + s0, ringStart(0) + s1);
            for (int ring = 0; ring + 1 < rings; ++ring) {
                tri(ringStart(ring) + s0, ringStart(ring) + s1, ringStart(ring + 1) + s1);
                tri(ringStart(ring) + s0, ringStart(ring + 1) + s1, ringStart(ring + 1) + s0);
            }
            tri(topPole, ringStart(rings - 1) + s1, ringStart(rings - 1) + s0);
        }
        ++mesh_.bones;
    }

private:
    // Emits the triangle counter-clockwise as seen from outside (its normal
    // agrees with the vertex normals), whatever order it was given in.
    void tri(std::uint32_t i0, std::uint32_t i1, std::uint32_t i2) {
        const BodyVertex& a = mesh_.vertices[i0];
        const BodyVertex& b = mesh_.vertices[i1];
        const BodyVertex& c = mesh_.vertices[i2];
        const glm::vec3 n = glm::cross(b.position - a.position, c.position - a.position);
        if (glm::dot(n, a.normal + b.normal + c.normal) < 0.0f) std::swap(i1, i2);
        mesh_.indices.insert(mesh_.indices.end(), {i0, i1, i2});
    }

    BodyMesh& mesh_;
    int sides_;
    int capRings_;
};

}  // namespace

std::vector<BodyCapsule> bodyCapsules(const Skeleton& sk) {
    std::vector<BodyCapsule> capsules;
    if (sk.jointCount() == 0) return capsules;
    if (sk.jointCount() == 1 && sk.endSites[0] && glm::length(*sk.endSites[0]) >= 1e-3f) {
        // A one-joint creature (a rat): one plump capsule from the joint to its end site.
        const glm::vec3 e = *sk.endSites[0];
        if (sk.names[0] == "ball") {
            // A ball (the football carrier's): a capsule whose tips are the
            // joint and the end site, 0.6 of its length across (a 0.28 m
            // ball is 0.17 m thick).
            const float r = 0.3f * glm::length(e);
            const glm::vec3 u = glm::normalize(e);
            capsules.push_back({u * r, e - u * r, r, 0});
            return capsules;
        }
        capsules.push_back({glm::vec3(0.0f), e, 0.22f * glm::length(e), 0});
        return capsules;
    }
    const Roles roles = findRoles(sk);
    const float scale = std::clamp(restExtent(sk) / 1.7f, 0.3f, 3.0f);
    const int pelvis = roles.sj.pelvis;
    for (int c = 0; c < sk.jointCount(); ++c) {
        const auto cu = static_cast<std::size_t>(c);
        const int p = sk.parents[cu];
        if (p < 0) continue;
        // Helper joints above the pelvis (a root on the floor, say) get no bone.
        if (pelvis >= 0 && pelvis != c && isAncestor(sk, c, pelvis)) continue;
        if (pelvis >= 0 && c == pelvis) continue;
        const glm::vec3 off = sk.offsets[cu];
        const float len = glm::length(off);
        if (len < 1e-3f) continue;
        capsules.push_back({glm::vec3(0.0f), off, boneRadius(roles, p, c, len) * scale, static_cast<std::uint32_t>(p)});
    }
    for (int j = 0; j < sk.jointCount(); ++j) {
        const auto ju = static_cast<std::size_t>(j);
        const bool head = j == roles.sj.head;
        const auto joint = static_cast<std::uint32_t>(j);
        if (sk.endSites[ju] && glm::length(*sk.endSites[ju]) >= 1e-3f) {
            const glm::vec3 e = *sk.endSites[ju];
            if (head) {
                // A head: a short, round capsule from just above the joint.
                capsules.push_back({e * 0.3f, e * 0.6f, 0.1f * scale, joint});
            } else {
                capsules.push_back({glm::vec3(0.0f), e, boneRadius(roles, j, -1, glm::length(e)) * scale, joint});
            }
        } else if (head && sk.children(j).empty()) {
            // No end site: a ball continuing the neck's direction.
            const glm::vec3 dir = glm::length(sk.offsets[ju]) > 1e-4f ? glm::normalize(sk.offsets[ju]) : glm::vec3(0, 1, 0);
            capsules.push_back({dir * 0.1f * scale, dir * 0.1f * scale, 0.1f * scale, joint});
        }
    }
    return capsules;
}

BodyMesh buildBodyMesh(const Skeleton& sk, const BodyMeshOptions& options) {
    BodyMesh mesh;
    CapsuleWriter writer(mesh, options);
    for (const BodyCapsule& c : bodyCapsules(sk)) writer.add(c.a, c.b, c.radius, c.joint);
    return mesh;
}

std::uint64_t skeletonFingerprint(const Skeleton& sk) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](const void* data, std::size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < n; ++i) {
            h ^= p[i];
            h *= 1099511628211ull;
        }
    };
    const int count = sk.jointCount();
    mix(&count, sizeof count);
    for (int j = 0; j < count; ++j) {
        const auto u = static_cast<std::size_t>(j);
        mix(&sk.parents[u], sizeof(int));
        mix(&sk.offsets[u], sizeof(glm::vec3));
        const glm::vec3 e = sk.endSites[u].value_or(glm::vec3(0.0f));
        const char has = sk.endSites[u].has_value() ? 1 : 0;
        mix(&has, 1);
        mix(&e, sizeof e);
        mix(sk.names[u].data(), sk.names[u].size());
    }
    return h;
}

}  // namespace fray
