#include "fray/prep/motion_graph.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <string>

#include "fray/core/kinematics.h"

namespace fray::prep {
namespace {

constexpr float kVelScale = static_cast<float>(kVelocityScale);

// Frames of the ~1/60 s finite-difference step at this capture rate.
int derivativeStep(double fps) { return std::max(1, static_cast<int>(std::lround(fps / 60.0))); }

glm::quat yawRotation(double yaw) {
    return glm::angleAxis(static_cast<float>(yaw), glm::vec3(0.0f, 1.0f, 0.0f));
}

// Rotation vector (axis * angle) of the rotation taking a to b, in a's frame.
glm::vec3 rotationVector(const glm::quat& a, const glm::quat& b) {
    glm::quat d = glm::conjugate(a) * b;
    if (d.w < 0.0f) d = -d;
    const glm::vec3 v(d.x, d.y, d.z);
    const float s = glm::length(v);
    if (s < 1e-7f) return 2.0f * v;
    return v * (2.0f * std::atan2(s, d.w) / s);
}

// asin on [0, 1] without a libm call (the clustering's hot spot): the odd
// Taylor series to x^11 on [0, 0.5] (error < 3e-6 rad), and above 0.5
// asin(x) = pi/2 - 2 asin(sqrt((1 - x) / 2)), whose argument is <= 0.5.
inline float asinSmall(float x) {
    const float x2 = x * x;
    return x * (1.0f + x2 * (1.0f / 6.0f + x2 * (3.0f / 40.0f + x2 * (5.0f / 112.0f +
                                                  x2 * (35.0f / 1152.0f + x2 * (63.0f / 2816.0f))))));
}
inline float fastAsin(float x) {
    if (x <= 0.5f) return asinSmall(x);
    return 1.57079633f - 2.0f * asinSmall(std::sqrt(0.5f * (1.0f - std::min(x, 1.0f))));
}

// Angle (rad) between two unit quaternions. From the chord |a -+ b| =
// 2 sin(angle / 4), which is exact near zero (acos of the dot is not in float).
inline float rotationAngle(const float* a, const float* b) {
    const float dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    const float s = dot < 0.0f ? -1.0f : 1.0f;
    float c2 = 0.0f;
    for (int i = 0; i < 4; ++i) {
        const float d = a[i] - s * b[i];
        c2 += d * d;
    }
    return 4.0f * fastAsin(0.5f * std::sqrt(c2));
}

inline float dist3(const float* a, const float* b) {
    const float x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return std::sqrt(x * x + y * y + z * z);
}

// Features packed into one float row, so clustering touches contiguous memory:
// n quaternions (x y z w), n angular velocities, legs l r, leg velocities l r,
// height, height velocity.
struct Layout {
    int n = 0;  // rotations per pose
    int quats() const { return 0; }
    int vels() const { return 4 * n; }
    int legs() const { return 7 * n; }
    int legVels() const { return 7 * n + 6; }
    int height() const { return 7 * n + 12; }
    int stride() const { return 7 * n + 14; }
};

struct Weights {
    float upper, upperVel, leg, legVel, height, heightVel;
    explicit Weights(const GraphWeights& w)
        : upper(static_cast<float>(w.upper)),
          upperVel(static_cast<float>(w.upperVel) * kVelScale),
          leg(static_cast<float>(w.leg)),
          legVel(static_cast<float>(w.legVel) * kVelScale),
          height(static_cast<float>(w.height)),
          heightVel(static_cast<float>(w.heightVel) * kVelScale) {}
    bool nonNegative() const {
        return upper >= 0.0f && upperVel >= 0.0f && leg >= 0.0f && legVel >= 0.0f && height >= 0.0f &&
               heightVel >= 0.0f;
    }
};

// The terms of packedDistance after the per-joint sums: legs and height.
struct LowerTerms {
    float leg, legVel, h, hv;
    LowerTerms(const float* a, const float* b, const Layout& l)
        : leg(0.5f * (dist3(a + l.legs(), b + l.legs()) + dist3(a + l.legs() + 3, b + l.legs() + 3))),
          legVel(0.5f * (dist3(a + l.legVels(), b + l.legVels()) + dist3(a + l.legVels() + 3, b + l.legVels() + 3))),
          h(std::abs(a[l.height()] - b[l.height()])),
          hv(std::abs(a[l.height() + 1] - b[l.height() + 1])) {}
};

// packedDistance from the per-joint sums and the other terms.
float combineDistance(const Layout& l, const Weights& w, float rot, float vel, const LowerTerms& t) {
    const float inv = l.n > 0 ? 1.0f / static_cast<float>(l.n) : 0.0f;
    return w.upper * rot * inv + w.upperVel * vel * inv + w.leg * t.leg + w.legVel * t.legVel + w.height * t.h +
           w.heightVel * t.hv;
}

float packedDistance(const float* a, const float* b, const Layout& l, const Weights& w) {
    float rot = 0.0f, vel = 0.0f;
    for (int i = 0; i < l.n; ++i) {
        rot += rotationAngle(a + l.quats() + 4 * i, b + l.quats() + 4 * i);
        vel += dist3(a + l.vels() + 3 * i, b + l.vels() + 3 * i);
    }
    return combineDistance(l, w, rot, vel, LowerTerms(a, b, l));
}

// offset + packedDistance when that is below bound, else nothing. Every term
// is non-negative (so must the weights be), and float sums and products of
// non-negative values never decrease as a value grows: the distance with
// the per-joint sums of the joints summed so far is at most the whole one,
// so once it reaches the bound the rest is not summed.
std::optional<double> packedDistanceBelow(const float* a, const float* b, const Layout& l, const Weights& w,
                                          double offset, double bound) {
    const LowerTerms terms(a, b, l);
    float rot = 0.0f, vel = 0.0f;
    for (int i = 0; i < l.n; ++i) {
        // Every fourth joint (the test costs about half a joint), from the first.
        if (i % 4 == 0 && static_cast<double>(combineDistance(l, w, rot, vel, terms)) + offset >= bound) {
            return std::nullopt;
        }
        rot += rotationAngle(a + l.quats() + 4 * i, b + l.quats() + 4 * i);
        vel += dist3(a + l.vels() + 3 * i, b + l.vels() + 3 * i);
    }
    const double d = static_cast<double>(combineDistance(l, w, rot, vel, terms)) + offset;
    if (d < bound) return d;
    return std::nullopt;
}

void pack(const PoseFeature& f, const Layout& l, float* out) {
    for (int i = 0; i < l.n; ++i) {
        const glm::quat& q = f.rotations[static_cast<std::size_t>(i)];
        const glm::vec3& v = f.angularVelocities[static_cast<std::size_t>(i)];
        float* qo = out + l.quats() + 4 * i;
        qo[0] = q.x, qo[1] = q.y, qo[2] = q.z, qo[3] = q.w;
        float* vo = out + l.vels() + 3 * i;
        vo[0] = v.x, vo[1] = v.y, vo[2] = v.z;
    }
    for (int s = 0; s < 2; ++s) {
        for (int c = 0; c < 3; ++c) {
            out[l.legs() + 3 * s + c] = f.legs[static_cast<std::size_t>(s)][c];
            out[l.legVels() + 3 * s + c] = f.legVelocities[static_cast<std::size_t>(s)][c];
        }
    }
    out[l.height()] = f.height;
    out[l.height() + 1] = f.heightVelocity;
}

PoseFeature unpack(const float* in, const Layout& l) {
    PoseFeature f;
    f.rotations.resize(static_cast<std::size_t>(l.n));
    f.angularVelocities.resize(static_cast<std::size_t>(l.n));
    for (int i = 0; i < l.n; ++i) {
        const float* q = in + l.quats() + 4 * i;
        const float* v = in + l.vels() + 3 * i;
        f.rotations[static_cast<std::size_t>(i)] = glm::quat(q[3], q[0], q[1], q[2]);
        f.angularVelocities[static_cast<std::size_t>(i)] = glm::vec3(v[0], v[1], v[2]);
    }
    for (int s = 0; s < 2; ++s) {
        for (int c = 0; c < 3; ++c) {
            f.legs[static_cast<std::size_t>(s)][c] = in[l.legs() + 3 * s + c];
            f.legVelocities[static_cast<std::size_t>(s)][c] = in[l.legVels() + 3 * s + c];
        }
    }
    f.height = in[l.height()];
    f.heightVelocity = in[l.height() + 1];
    return f;
}

// Reusable buffers for the features of one skeleton.
class FeatureExtractor {
public:
    FeatureExtractor(const Skeleton& skeleton, const StandardJoints& joints)
        : joints_(joints),
          upper_(upperBodyJoints(skeleton, joints)),
          invLeg_(static_cast<float>(1.0 / legLength(skeleton, joints))),
          pos_(static_cast<std::size_t>(skeleton.jointCount())),
          rot_(pos_.size()) {}

    PoseFeature operator()(const Motion& motion, int frame) {
        const int last = motion.frameCount() - 1;
        const int k = derivativeStep(motion.fps());
        const int fa = std::max(0, frame - k);
        const int fb = std::min(last, frame + k);
        PoseFeature f;
        raw(motion, frame, f);
        if (fb > fa) {
            PoseFeature before, after;
            raw(motion, fa, before);
            raw(motion, fb, after);
            const float invH = static_cast<float>(motion.fps() / (fb - fa));
            f.angularVelocities.resize(f.rotations.size());
            for (std::size_t i = 0; i < f.rotations.size(); ++i)
                f.angularVelocities[i] = rotationVector(before.rotations[i], after.rotations[i]) * invH;
            for (std::size_t s = 0; s < 2; ++s) f.legVelocities[s] = (after.legs[s] - before.legs[s]) * invH;
            f.heightVelocity = (after.height - before.height) * invH;
        } else {
            f.angularVelocities.assign(f.rotations.size(), glm::vec3(0.0f));
        }
        return f;
    }

    std::size_t rotationCount() const { return upper_.size() + 1; }

private:
    // Pose values of one frame (no derivatives).
    void raw(const Motion& motion, int frame, PoseFeature& f) {
        worldTransforms(motion, frame, pos_, rot_);
        const auto pelvis = static_cast<std::size_t>(joints_.pelvis);
        const glm::quat unturn = yawRotation(-headingOf(pos_, joints_));
        const auto local = motion.rotations(frame);
        f.rotations.resize(upper_.size() + 1);
        f.rotations[0] = glm::normalize(unturn * rot_[pelvis]);
        for (std::size_t i = 0; i < upper_.size(); ++i)
            f.rotations[i + 1] = glm::normalize(local[static_cast<std::size_t>(upper_[i])]);
        const int ankles[2] = {joints_.leftFoot, joints_.rightFoot};
        for (std::size_t s = 0; s < 2; ++s)
            f.legs[s] = (unturn * (pos_[static_cast<std::size_t>(ankles[s])] - pos_[pelvis])) * invLeg_;
        f.height = pos_[pelvis].y * invLeg_;
    }

    StandardJoints joints_;
    std::vector<int> upper_;
    float invLeg_;
    std::vector<glm::vec3> pos_;
    std::vector<glm::quat> rot_;
};

std::string jointsMissingForGraph(const StandardJoints& j) {
    std::string out;
    auto need = [&](int index, const char* name) {
        if (index >= 0) return;
        if (!out.empty()) out += ", ";
        out += name;
    };
    need(j.pelvis, "pelvis");
    need(j.head, "head");
    need(j.leftHand, "leftHand");
    need(j.rightHand, "rightHand");
    need(j.leftHip, "leftHip");
    need(j.rightHip, "rightHip");
    need(j.leftFoot, "leftFoot");
    need(j.rightFoot, "rightFoot");
    return out;
}

// K-means over packed rows. Centres are means (quaternions sign-aligned to
// the current centre, then normalised); assignment uses D itself. D is a
// metric, so Hamerly's bounds apply: each pose keeps an upper bound on the
// distance to its centre and a lower bound on the distance to every other
// centre, and only poses whose bounds overlap are compared with all centres.
// Once K is large and assignments settle, most poses skip the scan.
class KMeans {
public:
    KMeans(const std::vector<float>& rows, int count, const Layout& layout, const Weights& weights)
        : rows_(rows), count_(count), l_(layout), w_(weights), assign_(static_cast<std::size_t>(count), -1),
          upper_(assign_.size(), 0.0f), lower_(assign_.size(), 0.0f), dist_(assign_.size(), 0.0f) {}

    int k() const { return static_cast<int>(centres_.size() / stride()); }
    const std::vector<int>& assignment() const { return assign_; }
    const std::vector<float>& distances() const { return dist_; }
    const float* centre(int c) const { return centres_.data() + static_cast<std::size_t>(c) * stride(); }
    const float* row(int i) const { return rows_.data() + static_cast<std::size_t>(i) * stride(); }

    // New centres at these poses; the lower bounds learn about them.
    void addCentres(const std::vector<int>& poses) {
        const int first = k();
        for (int p : poses) centres_.insert(centres_.end(), row(p), row(p) + stride());
        const int last = k();
        tbb::parallel_for(tbb::blocked_range<int>(0, count_, 16), [&](const tbb::blocked_range<int>& r) {
            for (int i = r.begin(); i < r.end(); ++i) {
                const auto ii = static_cast<std::size_t>(i);
                if (assign_[ii] < 0) continue;
                for (int c = first; c < last; ++c) lower_[ii] = std::min(lower_[ii], distance(i, c));
            }
        });
    }

    // Lloyd iterations until no pose changes cluster (or the cap); then the
    // exact distance of every pose to its centre.
    void run(int maxIterations) {
        bool stale = false;
        for (int it = 0; it < maxIterations; ++it) {
            stale = false;
            if (!assign()) break;
            update();
            stale = true;
        }
        if (stale) assign();
        tbb::parallel_for(tbb::blocked_range<int>(0, count_, 16), [&](const tbb::blocked_range<int>& r) {
            for (int i = r.begin(); i < r.end(); ++i) {
                const auto ii = static_cast<std::size_t>(i);
                dist_[ii] = upper_[ii] = distance(i, assign_[ii]);
            }
        });
    }

    float maxDistance() const { return dist_.empty() ? 0.0f : *std::max_element(dist_.begin(), dist_.end()); }

private:
    std::size_t stride() const { return static_cast<std::size_t>(l_.stride()); }
    float distance(int pose, int c) const { return packedDistance(row(pose), centre(c), l_, w_); }

    // Bound slack: D is summed in float, so the triangle inequality holds only
    // to rounding; a pose is skipped only when its bounds are clearly apart.
    static constexpr float kSlack = 1e-5f;

    bool assign() {
        const int kk = k();
        std::atomic<bool> changed = false;
        // Each pose is independent, so the result does not depend on the split.
        tbb::parallel_for(tbb::blocked_range<int>(0, count_, 16), [&](const tbb::blocked_range<int>& r) {
            bool local = false;
            for (int i = r.begin(); i < r.end(); ++i) {
                const auto ii = static_cast<std::size_t>(i);
                if (assign_[ii] >= 0) {
                    if (upper_[ii] + kSlack < lower_[ii]) continue;
                    upper_[ii] = distance(i, assign_[ii]);
                    if (upper_[ii] + kSlack < lower_[ii]) continue;
                }
                int best = 0;
                float d1 = std::numeric_limits<float>::max(), d2 = d1;
                for (int c = 0; c < kk; ++c) {
                    const float d = distance(i, c);
                    if (d < d1) {
                        d2 = d1, d1 = d, best = c;
                    } else if (d < d2) {
                        d2 = d;
                    }
                }
                if (assign_[ii] != best) local = true;
                assign_[ii] = best;
                upper_[ii] = d1;
                lower_[ii] = d2;
            }
            if (local) changed.store(true, std::memory_order_relaxed);
        });
        return changed.load();
    }

    void update() {
        const int kk = k();
        const std::size_t s = stride();
        std::vector<double> sum(static_cast<std::size_t>(kk) * s, 0.0);
        std::vector<int> members(static_cast<std::size_t>(kk), 0);
        for (int i = 0; i < count_; ++i) {
            const int c = assign_[static_cast<std::size_t>(i)];
            const float* x = row(i);
            const float* ref = centre(c);
            double* acc = sum.data() + static_cast<std::size_t>(c) * s;
            ++members[static_cast<std::size_t>(c)];
            for (int q = 0; q < l_.n; ++q) {
                const float* xq = x + 4 * q;
                const float* rq = ref + 4 * q;
                const float dot = xq[0] * rq[0] + xq[1] * rq[1] + xq[2] * rq[2] + xq[3] * rq[3];
                const double sign = dot < 0.0f ? -1.0 : 1.0;
                for (int e = 0; e < 4; ++e) acc[4 * q + e] += sign * static_cast<double>(xq[e]);
            }
            for (std::size_t e = static_cast<std::size_t>(l_.vels()); e < s; ++e) acc[e] += static_cast<double>(x[e]);
        }
        // How far each centre moves: the bounds widen by that much.
        std::vector<float> moved(static_cast<std::size_t>(kk), 0.0f);
        std::vector<float> old(s);
        for (int c = 0; c < kk; ++c) {
            const int m = members[static_cast<std::size_t>(c)];
            if (m == 0) continue;  // an empty cluster keeps its centre
            const double* acc = sum.data() + static_cast<std::size_t>(c) * s;
            float* out = centres_.data() + static_cast<std::size_t>(c) * s;
            std::copy_n(out, s, old.begin());
            for (int q = 0; q < l_.n; ++q) {
                const double* a = acc + 4 * q;
                const double len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3]);
                if (len < 1e-9) continue;  // opposite rotations cancelled: keep the old one
                for (int e = 0; e < 4; ++e) out[4 * q + e] = static_cast<float>(a[e] / len);
            }
            for (std::size_t e = static_cast<std::size_t>(l_.vels()); e < s; ++e)
                out[e] = static_cast<float>(acc[e] / m);
            moved[static_cast<std::size_t>(c)] = packedDistance(old.data(), out, l_, w_);
        }
        int far = 0;
        for (int c = 1; c < kk; ++c)
            if (moved[static_cast<std::size_t>(c)] > moved[static_cast<std::size_t>(far)]) far = c;
        float second = 0.0f;
        for (int c = 0; c < kk; ++c)
            if (c != far) second = std::max(second, moved[static_cast<std::size_t>(c)]);
        const float first = moved[static_cast<std::size_t>(far)];
        for (std::size_t i = 0; i < assign_.size(); ++i) {
            const int a = assign_[i];
            upper_[i] += moved[static_cast<std::size_t>(a)];
            lower_[i] -= a == far ? second : first;
        }
    }

    const std::vector<float>& rows_;
    int count_;
    Layout l_;
    Weights w_;
    std::vector<float> centres_;
    std::vector<int> assign_;
    std::vector<float> upper_, lower_, dist_;
};

// Strongly connected components of a graph (Tarjan, iterative so deep chains
// cannot overflow the stack). Returns the component of every vertex.
std::vector<int> stronglyConnected(int nodes, const std::vector<std::vector<int>>& adjacency) {
    std::vector<int> index(static_cast<std::size_t>(nodes), -1), low(index.size(), 0), comp(index.size(), -1);
    std::vector<std::uint8_t> onStack(index.size(), 0);
    std::vector<int> stack;
    std::vector<std::pair<int, std::size_t>> calls;  // node, next edge to visit
    int counter = 0, comps = 0;
    auto visit = [&](int v) {
        const auto vi = static_cast<std::size_t>(v);
        index[vi] = low[vi] = counter++;
        stack.push_back(v);
        onStack[vi] = 1;
        calls.emplace_back(v, 0);
    };
    for (int root = 0; root < nodes; ++root) {
        if (index[static_cast<std::size_t>(root)] >= 0) continue;
        visit(root);
        while (!calls.empty()) {
            const int u = calls.back().first;
            const auto ui = static_cast<std::size_t>(u);
            const auto& edges = adjacency[ui];
            if (calls.back().second < edges.size()) {
                const int v = edges[calls.back().second++];
                const auto vi = static_cast<std::size_t>(v);
                if (index[vi] < 0) {
                    visit(v);
                } else if (onStack[vi]) {
                    low[ui] = std::min(low[ui], index[vi]);
                }
                continue;
            }
            if (low[ui] == index[ui]) {
                int w;
                do {
                    w = stack.back();
                    stack.pop_back();
                    onStack[static_cast<std::size_t>(w)] = 0;
                    comp[static_cast<std::size_t>(w)] = comps;
                } while (w != u);
                ++comps;
            }
            calls.pop_back();
            if (!calls.empty()) {
                const auto pi = static_cast<std::size_t>(calls.back().first);
                low[pi] = std::min(low[pi], low[ui]);
            }
        }
    }
    return comp;
}

}  // namespace

GraphWeights GraphWeights::fighting() { return GraphWeights{}; }

GraphWeights GraphWeights::locomotion() {
    GraphWeights w;
    w.upper = 0.1;
    w.upperVel = 0.1;
    return w;
}

std::optional<GraphWeights> GraphWeights::preset(std::string_view name) {
    if (name == "fighting") return fighting();
    if (name == "locomotion") return locomotion();
    return std::nullopt;
}

std::vector<int> upperBodyJoints(const Skeleton& skeleton, const StandardJoints& joints) {
    std::vector<std::uint8_t> take(static_cast<std::size_t>(skeleton.jointCount()), 0);
    for (int end : {joints.head, joints.leftHand, joints.rightHand}) {
        for (int j = end; j >= 0 && j != joints.pelvis; j = skeleton.parents[static_cast<std::size_t>(j)])
            take[static_cast<std::size_t>(j)] = 1;
    }
    std::vector<int> out;
    for (int j = 0; j < skeleton.jointCount(); ++j)
        if (take[static_cast<std::size_t>(j)]) out.push_back(j);
    return out;
}

double legLength(const Skeleton& skeleton, const StandardJoints& joints) {
    double total = 0.0;
    int legs = 0;
    for (auto [hip, ankle] :
         {std::pair{joints.leftHip, joints.leftFoot}, std::pair{joints.rightHip, joints.rightFoot}}) {
        if (hip < 0 || ankle < 0) continue;
        double len = 0.0;
        int j = ankle;
        while (j >= 0 && j != hip) {
            len += glm::length(glm::dvec3(skeleton.offsets[static_cast<std::size_t>(j)]));
            j = skeleton.parents[static_cast<std::size_t>(j)];
        }
        if (j == hip && len > 1e-6) total += len, ++legs;
    }
    return legs > 0 ? total / legs : 1.0;
}

double headingOf(std::span<const glm::vec3> world, const StandardJoints& joints) {
    auto across = [&](int left, int right) -> std::optional<glm::dvec3> {
        if (left < 0 || right < 0) return std::nullopt;
        const glm::dvec3 d = glm::dvec3(world[static_cast<std::size_t>(left)]) -
                             glm::dvec3(world[static_cast<std::size_t>(right)]);
        if (d.x * d.x + d.z * d.z < 1e-8) return std::nullopt;  // hip line vertical: no heading
        return d;
    };
    auto d = across(joints.leftHip, joints.rightHip);
    if (!d) d = across(joints.leftShoulder, joints.rightShoulder);
    if (!d) return 0.0;
    // forward = (left - right) x up, projected on the floor.
    return std::atan2(-d->z, d->x);
}

PoseFeature poseFeature(const Motion& motion, const StandardJoints& joints, int frame) {
    FeatureExtractor extract(motion.skeleton(), joints);
    return extract(motion, frame);
}

double poseDistance(const PoseFeature& a, const PoseFeature& b, const GraphWeights& weights) {
    Layout l;
    l.n = static_cast<int>(std::min(a.rotations.size(), b.rotations.size()));
    std::vector<float> pa(static_cast<std::size_t>(l.stride())), pb(pa.size());
    pack(a, l, pa.data());
    pack(b, l, pb.data());
    return static_cast<double>(packedDistance(pa.data(), pb.data(), l, Weights(weights)));
}

void PoseMatcher::add(const PoseFeature& pose) {
    Layout l;
    l.n = static_cast<int>(pose.rotations.size());
    offset_.push_back(packed_.size());
    count_.push_back(l.n);
    packed_.resize(packed_.size() + static_cast<std::size_t>(l.stride()));
    pack(pose, l, packed_.data() + offset_.back());
}

const float* PoseMatcher::row(Probe& probe, std::size_t i, int& n) const {
    // poseDistance compares the first min(n_a, n_b) rotations of both.
    Layout l;
    l.n = std::min(count_[i], static_cast<int>(probe.pose_->rotations.size()));
    n = l.n;
    Layout mine;
    mine.n = count_[i];
    if (probe.n_ != l.n) {
        probe.n_ = l.n;
        probe.packed_.assign(static_cast<std::size_t>(l.stride()), 0.0f);
        pack(*probe.pose_, l, probe.packed_.data());
    }
    const float* stored = packed_.data() + offset_[i];
    if (mine.n == l.n) return stored;
    // A pose with more rotations than the probe: repack its first ones.
    thread_local std::vector<float> shorter;
    shorter.assign(static_cast<std::size_t>(l.stride()), 0.0f);
    pack(unpack(stored, mine), l, shorter.data());
    return shorter.data();
}

double PoseMatcher::distance(Probe& probe, std::size_t i) const {
    Layout l;
    const float* stored = row(probe, i, l.n);
    return static_cast<double>(packedDistance(probe.packed_.data(), stored, l, Weights(weights_)));
}

std::optional<double> PoseMatcher::distanceBelow(Probe& probe, std::size_t i, double offset, double bound) const {
    Layout l;
    const float* stored = row(probe, i, l.n);
    const Weights w(weights_);
    if (!w.nonNegative()) {
        const double d = static_cast<double>(packedDistance(probe.packed_.data(), stored, l, w)) + offset;
        return d < bound ? std::optional<double>(d) : std::nullopt;
    }
    return packedDistanceBelow(probe.packed_.data(), stored, l, w, offset, bound);
}

std::vector<int> naturalSuccessors(std::span<const ActionRef> actions) {
    std::vector<int> out(actions.size(), -1);
    std::map<std::pair<int, int>, int> byStart;  // (motion, first frame) -> action
    for (std::size_t a = 0; a < actions.size(); ++a) byStart.emplace(std::pair{actions[a].motion, actions[a].firstFrame}, static_cast<int>(a));
    for (std::size_t a = 0; a < actions.size(); ++a) {
        const auto it = byStart.find({actions[a].motion, actions[a].lastFrame + 1});
        if (it != byStart.end()) out[a] = it->second;
    }
    return out;
}

void connectNodes(MotionGraph& g, std::vector<int> startNode, std::vector<int> endNode, std::span<const int> successors) {
    g.startNode = std::move(startNode);
    g.endNode = std::move(endNode);
    g.next.clear();
    g.inLargestScc.clear();
    g.stats = {};
    g.naturalEdges = 0;
    const std::size_t actionCount = g.startNode.size();
    if (actionCount == 0 || g.nodeCount <= 0) return;
    std::vector<std::vector<int>> startsAt(static_cast<std::size_t>(g.nodeCount));
    for (std::size_t a = 0; a < actionCount; ++a) startsAt[static_cast<std::size_t>(g.startNode[a])].push_back(static_cast<int>(a));
    g.next.resize(actionCount);
    for (std::size_t a = 0; a < actionCount; ++a) {
        g.next[a] = startsAt[static_cast<std::size_t>(g.endNode[a])];
        // The capture's own continuation, when clustering put the two sides of
        // the cut in different nodes.
        const int s = a < successors.size() ? successors[a] : -1;
        if (s >= 0 && static_cast<std::size_t>(s) < actionCount && !std::binary_search(g.next[a].begin(), g.next[a].end(), s)) {
            g.next[a].insert(std::upper_bound(g.next[a].begin(), g.next[a].end(), s), s);
            ++g.naturalEdges;
        }
    }

    // Strongly connected components of the action graph (a -> every b in
    // Next(a)). An action alone in its component counts only if it can
    // follow itself.
    const std::vector<int> comp = stronglyConnected(static_cast<int>(actionCount), g.next);
    const int comps = *std::max_element(comp.begin(), comp.end()) + 1;
    std::vector<int> members(static_cast<std::size_t>(comps), 0);
    for (std::size_t a = 0; a < actionCount; ++a) ++members[static_cast<std::size_t>(comp[a])];
    std::vector<int> inside(static_cast<std::size_t>(comps), 0);
    for (std::size_t a = 0; a < actionCount; ++a) {
        const auto c = static_cast<std::size_t>(comp[a]);
        if (members[c] > 1 || std::binary_search(g.next[a].begin(), g.next[a].end(), static_cast<int>(a))) ++inside[c];
    }
    const int largest = static_cast<int>(std::max_element(inside.begin(), inside.end()) - inside.begin());
    g.inLargestScc.resize(actionCount);
    for (std::size_t a = 0; a < actionCount; ++a)
        g.inLargestScc[a] = comp[a] == largest && inside[static_cast<std::size_t>(largest)] > 0;

    GraphStats& st = g.stats;
    st.nodes = g.nodeCount;
    st.edges = static_cast<int>(actionCount);
    st.meanOutDegree = static_cast<double>(st.edges) / st.nodes;
    for (const auto& v : startsAt) st.maxOutDegree = std::max(st.maxOutDegree, static_cast<int>(v.size()));
    st.largestSccActions = inside[static_cast<std::size_t>(largest)];
    st.sccShare = static_cast<double>(st.largestSccActions) / st.edges;
    st.deadEnds =
        static_cast<int>(std::count_if(g.next.begin(), g.next.end(), [](const auto& n) { return n.empty(); }));
}

namespace {
// Checks shared by buildMotionGraph and transitionGaps.
Status checkGraphInput(std::span<const Motion* const> motions, std::span<const StandardJoints> joints,
                       std::span<const ActionRef> actions) {
    if (motions.empty()) return makeError("motion graph: no motions");
    if (motions.size() != joints.size())
        return makeError("motion graph: " + std::to_string(motions.size()) + " motions but " +
                         std::to_string(joints.size()) + " joint sets");
    if (actions.empty()) return makeError("motion graph: no actions");
    for (std::size_t m = 0; m < motions.size(); ++m) {
        const std::string which = "motion graph: motion " + std::to_string(m);
        if (!motions[m]) return makeError(which + " is null");
        const Skeleton& s = motions[m]->skeleton();
        const Skeleton& s0 = motions[0]->skeleton();
        if (s.names != s0.names || s.parents != s0.parents)
            return makeError(which + ": skeleton differs from motion 0 (joint names or hierarchy)");
        if (const std::string missing = jointsMissingForGraph(joints[m]); !missing.empty())
            return makeError(which + ": cannot find the " + missing + " joints");
        if (upperBodyJoints(s, joints[m]) != upperBodyJoints(s0, joints[0]) || joints[m].pelvis != joints[0].pelvis)
            return makeError(which + ": its standard joints differ from motion 0's");
    }
    for (std::size_t a = 0; a < actions.size(); ++a) {
        const ActionRef& r = actions[a];
        const std::string which = "motion graph: action " + std::to_string(a);
        if (r.motion < 0 || static_cast<std::size_t>(r.motion) >= motions.size())
            return makeError(which + " refers to motion " + std::to_string(r.motion) + " of " +
                             std::to_string(motions.size()));
        const int frames = motions[static_cast<std::size_t>(r.motion)]->frameCount();
        if (r.firstFrame < 0 || r.lastFrame < r.firstFrame || r.lastFrame >= frames)
            return makeError(which + ": frames " + std::to_string(r.firstFrame) + ".." +
                             std::to_string(r.lastFrame) + " are not a range inside motion " +
                             std::to_string(r.motion) + " (frames 0.." + std::to_string(frames - 1) + ")");
    }
    return {};
}
}  // namespace

Result<MotionGraph> buildMotionGraph(std::span<const Motion* const> motions, std::span<const StandardJoints> joints,
                                     std::span<const ActionRef> actions, const GraphOptions& options,
                                     const ProgressFn& progress) {
    if (auto st = checkGraphInput(motions, joints, actions); !st) return st.error();
    if (!(options.threshold > 0.0)) return makeError("motion graph: the threshold must be positive");
    if (options.maxNodes < 1) return makeError("motion graph: maxNodes must be at least 1");
    const auto cancelled = [] { return fray::cancelled("motion graph"); };
    if (!reportProgress(progress, 0.0, "pose features")) return cancelled();

    // Start pose of action a is row 2a, its end pose row 2a+1.
    FeatureExtractor extract(motions[0]->skeleton(), joints[0]);
    Layout layout;
    layout.n = static_cast<int>(extract.rotationCount());
    const int poses = 2 * static_cast<int>(actions.size());
    const auto stride = static_cast<std::size_t>(layout.stride());
    std::vector<float> rows(static_cast<std::size_t>(poses) * stride);
    for (std::size_t a = 0; a < actions.size(); ++a) {
        const Motion& m = *motions[static_cast<std::size_t>(actions[a].motion)];
        pack(extract(m, actions[a].firstFrame), layout, rows.data() + (2 * a) * stride);
        pack(extract(m, actions[a].lastFrame), layout, rows.data() + (2 * a + 1) * stride);
    }
    if (!reportProgress(progress, 0.1, "clustering")) return cancelled();

    // K grows until every pose lies within the threshold of its centre. Each
    // round runs Lloyd from the previous centres and then adds new centres
    // among the poses still too far, at most half as many as there are, so K
    // grows geometrically and a few rounds suffice.
    const Weights weights(options.weights);
    const auto threshold = static_cast<float>(options.threshold);
    KMeans km(rows, poses, layout, weights);
    std::mt19937_64 rng(options.seed);
    km.addCentres({static_cast<int>(std::uniform_int_distribution<int>(0, poses - 1)(rng))});
    int rounds = 0;
    double reported = 0.1;
    constexpr int kLloydIterations = 30;
    for (;;) {
        ++rounds;
        km.run(kLloydIterations);
        const float worst = km.maxDistance();
        if (worst < threshold || km.k() >= std::min(options.maxNodes, poses)) break;
        // threshold / worst approaches 1 as K grows; kept monotone for the progress bar.
        reported = std::max(reported, 0.1 + 0.85 * std::clamp(static_cast<double>(threshold / worst), 0.0, 1.0));
        if (!reportProgress(progress, reported, "clustering")) return cancelled();
        // k-means++ among the poses still too far: pick with probability
        // proportional to D^2 (seeded), skipping poses a centre picked in
        // this round already covers.
        std::vector<double> weight(static_cast<std::size_t>(poses), 0.0);
        int remaining = 0;
        for (int i = 0; i < poses; ++i) {
            const auto d = static_cast<double>(km.distances()[static_cast<std::size_t>(i)]);
            if (d >= static_cast<double>(threshold)) weight[static_cast<std::size_t>(i)] = d * d, ++remaining;
        }
        const int room = std::min(options.maxNodes, poses) - km.k();
        const int cap = std::min(room, std::max(1, km.k() / 2));
        std::vector<int> added;
        while (static_cast<int>(added.size()) < cap && remaining > 0) {
            // The total is summed afresh for every pick so no rounding residue accumulates.
            const double total = std::accumulate(weight.begin(), weight.end(), 0.0);
            double pick = std::uniform_real_distribution<double>(0.0, total)(rng);
            int chosen = -1;
            for (int i = 0; i < poses; ++i) {
                const double w = weight[static_cast<std::size_t>(i)];
                if (w <= 0.0) continue;
                chosen = i;  // the last candidate when rounding runs past the end
                pick -= w;
                if (pick < 0.0) break;
            }
            weight[static_cast<std::size_t>(chosen)] = 0.0;
            --remaining;
            const bool covered = std::any_of(added.begin(), added.end(), [&](int c) {
                return packedDistance(km.row(chosen), km.row(c), layout, weights) < threshold;
            });
            if (!covered) added.push_back(chosen);
        }
        km.addCentres(added);
    }
    if (!reportProgress(progress, 0.95, "graph")) return cancelled();

    // Nodes: non-empty clusters, numbered in order of first use.
    std::vector<int> relabel(static_cast<std::size_t>(km.k()), -1);
    MotionGraph g;
    for (int i = 0; i < poses; ++i) {
        int& r = relabel[static_cast<std::size_t>(km.assignment()[static_cast<std::size_t>(i)])];
        if (r < 0) {
            r = g.nodeCount++;
            g.centres.push_back(unpack(km.centre(km.assignment()[static_cast<std::size_t>(i)]), layout));
        }
    }
    std::vector<int> startNode(actions.size()), endNode(actions.size());
    for (std::size_t a = 0; a < actions.size(); ++a) {
        startNode[a] = relabel[static_cast<std::size_t>(km.assignment()[2 * a])];
        endNode[a] = relabel[static_cast<std::size_t>(km.assignment()[2 * a + 1])];
    }
    connectNodes(g, std::move(startNode), std::move(endNode), naturalSuccessors(actions));
    g.maxClusterDistance = static_cast<double>(km.maxDistance());
    g.kmeansRounds = rounds;
    if (!reportProgress(progress, 1.0, "graph")) return cancelled();
    return g;
}

Result<std::vector<double>> transitionGaps(std::span<const Motion* const> motions, std::span<const StandardJoints> joints,
                                           std::span<const ActionRef> actions, const GraphWeights& graphWeights, int maxEnds,
                                           const ProgressFn& progress) {
    if (auto st = checkGraphInput(motions, joints, actions); !st) return st.error();
    if (maxEnds < 1) return makeError("motion graph: maxEnds must be at least 1");
    const auto cancelled = [] { return fray::cancelled("transition gaps"); };
    if (!reportProgress(progress, 0.0, "pose features")) return cancelled();
    FeatureExtractor extract(motions[0]->skeleton(), joints[0]);
    Layout layout;
    layout.n = static_cast<int>(extract.rotationCount());
    const auto stride = static_cast<std::size_t>(layout.stride());
    const std::size_t n = actions.size();
    // Ends measured: every one, or an even stride over them.
    std::vector<std::size_t> ends;
    const std::size_t step = (n + static_cast<std::size_t>(maxEnds) - 1) / static_cast<std::size_t>(maxEnds);
    for (std::size_t a = 0; a < n; a += step) ends.push_back(a);
    std::vector<float> starts(n * stride), endRows(ends.size() * stride);
    for (std::size_t a = 0; a < n; ++a) {
        const Motion& m = *motions[static_cast<std::size_t>(actions[a].motion)];
        pack(extract(m, actions[a].firstFrame), layout, starts.data() + a * stride);
    }
    for (std::size_t e = 0; e < ends.size(); ++e) {
        const ActionRef& r = actions[ends[e]];
        pack(extract(*motions[static_cast<std::size_t>(r.motion)], r.lastFrame), layout, endRows.data() + e * stride);
    }
    if (!reportProgress(progress, 0.2, "transition gaps")) return cancelled();
    const std::vector<int> successor = naturalSuccessors(actions);
    const Weights w(graphWeights);
    std::vector<double> gaps(ends.size(), std::numeric_limits<double>::infinity());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ends.size(), 8), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t e = range.begin(); e != range.end(); ++e) {
            const int own = successor[ends[e]];
            double best = std::numeric_limits<double>::infinity();
            for (std::size_t b = 0; b < n; ++b) {
                if (static_cast<int>(b) == own) continue;
                best = std::min(best, static_cast<double>(packedDistance(endRows.data() + e * stride, starts.data() + b * stride, layout, w)));
            }
            gaps[e] = best;
        }
    });
    if (!reportProgress(progress, 1.0, "transition gaps")) return cancelled();
    // One action whose only start is its own continuation has no gap.
    gaps.erase(std::remove_if(gaps.begin(), gaps.end(), [](double g) { return !std::isfinite(g); }), gaps.end());
    std::sort(gaps.begin(), gaps.end());
    return gaps;
}

double thresholdFromGaps(std::span<const double> sortedGaps) {
    if (sortedGaps.empty()) return 0.0;
    const auto i = static_cast<std::size_t>(std::ceil(kDataThresholdShare * static_cast<double>(sortedGaps.size()))) - 1;
    // K-means centres are means of their poses, not poses: an end and a start
    // g apart share a cluster reliably only with some slack over g.
    constexpr double kMargin = 1.5;
    return kMargin * sortedGaps[std::min(i, sortedGaps.size() - 1)];
}

}  // namespace fray::prep
