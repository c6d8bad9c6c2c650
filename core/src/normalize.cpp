#include "fray/core/normalize.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "fray/core/joint_guess.h"
#include "fray/core/kinematics.h"

namespace fray {
namespace {

constexpr int kSamples = 64;

// Head-above-ankles vectors on up to `samples` frames spread over the take.
std::vector<glm::vec3> headVectors(const Motion& motion, int samples) {
    std::vector<glm::vec3> out;
    if (motion.frameCount() == 0) return out;
    const StandardJoints sj = guessStandardJoints(motion.skeleton());
    const auto jc = static_cast<std::size_t>(motion.jointCount());
    std::vector<glm::vec3> pos(jc);
    std::vector<glm::quat> rot(jc);
    const int step = std::max(1, motion.frameCount() / samples);
    for (int f = 0; f < motion.frameCount(); f += step) {
        worldTransforms(motion, f, pos, rot);
        glm::vec3 top, bottom;
        if (sj.head >= 0 && sj.hasFeet()) {
            top = pos[static_cast<std::size_t>(sj.head)];
            bottom = 0.5f * (pos[static_cast<std::size_t>(sj.leftFoot)] + pos[static_cast<std::size_t>(sj.rightFoot)]);
        } else if (sj.head >= 0) {
            top = pos[static_cast<std::size_t>(sj.head)];
            bottom = pos[static_cast<std::size_t>(sj.pelvis)];
            top = bottom + 2.0f * (top - bottom);  // pelvis sits about halfway up
        } else {
            // No named joints: use the pose's bounding box along its largest axis.
            glm::vec3 lo(1e30f), hi(-1e30f);
            for (const auto& p : pos) lo = glm::min(lo, p), hi = glm::max(hi, p);
            const glm::vec3 e = hi - lo;
            const int axis = e.y >= e.z ? 1 : 2;
            top = glm::vec3(0);
            bottom = glm::vec3(0);
            top[axis] = e[axis];
        }
        out.push_back(top - bottom);
    }
    return out;
}

UpAxis upAxisFrom(const std::vector<glm::vec3>& vectors) {
    glm::dvec3 sum(0);
    for (const auto& v : vectors) sum += glm::dvec3(v);
    return std::abs(sum.z) > std::abs(sum.y) ? UpAxis::Z : UpAxis::Y;
}

struct Unit {
    double scale;
    const char* name;
};
constexpr Unit kUnits[] = {{1.0, "m"}, {0.01, "cm"}, {0.001, "mm"}, {0.0254, "inch"}, {0.056444, "cmu"}};

UnitGuess unitsFrom(const std::vector<glm::vec3>& vectors) {
    std::vector<float> heights;
    for (const auto& v : vectors) heights.push_back(glm::length(v));
    UnitGuess g;
    if (heights.empty()) return g;
    // A high percentile: the actor standing upright, not crouched or lying down.
    std::sort(heights.begin(), heights.end());
    const double h = static_cast<double>(heights[std::min(heights.size() - 1, heights.size() * 9 / 10)]);
    g.heightInFileUnits = h;
    // Head joint to ankles of an adult is about 1.5 m.
    double best = 1e30;
    for (const Unit& u : kUnits) {
        const double err = std::abs(std::log(std::max(h * u.scale, 1e-9) / 1.5));
        if (err < best) {
            best = err;
            g.scale = u.scale;
            g.name = u.name;
        }
    }
    return g;
}

}  // namespace

std::optional<double> unitScaleByName(std::string_view name) {
    if (name == "in") name = "inch";
    for (const Unit& u : kUnits) {
        if (name == u.name) return u.scale;
    }
    return std::nullopt;
}

std::optional<UpAxis> upAxisByName(std::string_view name) {
    if (name == "y" || name == "Y") return UpAxis::Y;
    if (name == "z" || name == "Z") return UpAxis::Z;
    return std::nullopt;
}

NormalizeOptions normalizeOptionsFor(std::string_view units, std::string_view up) {
    return {unitScaleByName(units), upAxisByName(up)};
}

UpAxis guessUpAxis(const Motion& motion) { return upAxisFrom(headVectors(motion, kSamples)); }
UnitGuess guessUnits(const Motion& motion) { return unitsFrom(headVectors(motion, kSamples)); }

void normalize(Motion& motion, const NormalizeOptions& options) {
    SourceInfo& src = motion.source();
    if (src.normalized) return;
    // Measured once, on the raw data, for both guesses.
    std::vector<glm::vec3> vectors;
    if (!options.upAxis || !options.unitScale) vectors = headVectors(motion, kSamples);
    const UpAxis up = options.upAxis ? *options.upAxis : upAxisFrom(vectors);
    double scale = 1.0;
    std::string unitName = "m";
    if (options.unitScale) {
        scale = *options.unitScale;
        unitName = "given";
    } else {
        const UnitGuess g = unitsFrom(vectors);
        scale = g.scale;
        unitName = g.name;
    }
    const float s = static_cast<float>(scale);
    for (auto& t : motion.allTranslations()) t *= s;
    Skeleton& sk = motion.skeleton();
    for (auto& o : sk.offsets) o *= s;
    for (auto& e : sk.endSites)
        if (e) *e *= s;
    if (up == UpAxis::Z) {
        // Rotate the whole take -90 degrees about X: (x, y, z) -> (x, z, -y).
        // Only the root changes; joint-local data stays as in the file.
        const glm::quat r = glm::angleAxis(-glm::half_pi<float>(), glm::vec3(1, 0, 0));
        const auto jc = static_cast<std::size_t>(motion.jointCount());
        auto& T = motion.allTranslations();
        auto& R = motion.allRotations();
        for (std::size_t f = 0; f < static_cast<std::size_t>(motion.frameCount()); ++f) {
            T[f * jc] = r * T[f * jc];
            R[f * jc] = r * R[f * jc];
        }
        sk.offsets[0] = r * sk.offsets[0];
    }
    src.unitScale = scale;
    src.unitName = unitName;
    src.sourceUp = up;
    src.normalized = true;
}

}  // namespace fray
