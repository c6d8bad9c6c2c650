#include <charconv>
#include <string>
#include <vector>

#include "fray/core/atomic_file.h"
#include "fray/core/rotation.h"
#include "fray/io/bvh.h"

namespace fray {
namespace {

void appendNumber(std::string& out, double v, int precision) {
    char buf[64];
    if (v == 0.0) v = 0.0;  // no "-0"
    auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, precision);
    out.append(buf, res.ptr);
}

void appendVec(std::string& out, const glm::vec3& v, int precision) {
    for (int i = 0; i < 3; ++i) {
        out.push_back(' ');
        appendNumber(out, static_cast<double>(v[i]), precision);
    }
}

void writeJoint(std::string& out, const Skeleton& sk, int j, int depth, int precision) {
    const std::string indent(static_cast<std::size_t>(depth), '\t');
    const auto ju = static_cast<std::size_t>(j);
    out += indent + (sk.parents[ju] < 0 ? "ROOT " : "JOINT ") + sk.names[ju] + "\n" + indent + "{\n";
    out += indent + "\tOFFSET";
    appendVec(out, sk.offsets[ju], precision);
    out += "\n";
    if (!sk.channels[ju].empty() || sk.parents[ju] < 0) {
        out += indent + "\tCHANNELS " + std::to_string(sk.channels[ju].size());
        for (Channel c : sk.channels[ju]) out += " " + std::string(toString(c));
        out += "\n";
    }
    for (int c : sk.children(j)) writeJoint(out, sk, c, depth + 1, precision);
    if (sk.endSites[ju]) {
        out += indent + "\tEnd Site\n" + indent + "\t{\n" + indent + "\t\tOFFSET";
        appendVec(out, *sk.endSites[ju], precision);
        out += "\n" + indent + "\t}\n";
    }
    out += indent + "}\n";
}

}  // namespace

std::string writeBvhToString(const Motion& motion, const BvhWriteOptions& options) {
    const Skeleton& sk = motion.skeleton();
    std::string out = "HIERARCHY\n";
    if (sk.jointCount() > 0) writeJoint(out, sk, 0, 0, options.precision);
    out += "MOTION\nFrames: " + std::to_string(motion.frameCount()) + "\nFrame Time: ";
    appendNumber(out, 1.0 / motion.fps(), 17);
    out += "\n";
    const auto jc = static_cast<std::size_t>(sk.jointCount());
    std::vector<glm::dvec3> previous(jc);
    out.reserve(out.size() + static_cast<std::size_t>(motion.frameCount()) * static_cast<std::size_t>(sk.channelCount()) * 12);
    for (int f = 0; f < motion.frameCount(); ++f) {
        const auto t = motion.translations(f);
        const auto r = motion.rotations(f);
        bool first = true;
        for (std::size_t j = 0; j < jc; ++j) {
            if (sk.channels[j].empty()) continue;
            glm::dvec3 e = quatToEuler(glm::dquat(r[j]), sk.rotationOrders[j]);
            if (options.continuousEuler && f > 0) e = nearestEquivalentEuler(e, previous[j], sk.rotationOrders[j]);
            previous[j] = e;
            for (Channel c : sk.channels[j]) {
                if (!first) out.push_back(' ');
                first = false;
                switch (c) {
                    case Channel::Xposition: appendNumber(out, static_cast<double>(t[j].x), options.precision); break;
                    case Channel::Yposition: appendNumber(out, static_cast<double>(t[j].y), options.precision); break;
                    case Channel::Zposition: appendNumber(out, static_cast<double>(t[j].z), options.precision); break;
                    case Channel::Xrotation: appendNumber(out, e.x, options.precision); break;
                    case Channel::Yrotation: appendNumber(out, e.y, options.precision); break;
                    case Channel::Zrotation: appendNumber(out, e.z, options.precision); break;
                }
            }
        }
        out.push_back('\n');
    }
    return out;
}

Status writeBvh(const Motion& motion, const std::filesystem::path& path, const BvhWriteOptions& options) {
    if (auto bad = motion.skeleton().validate()) return makeError(path.string() + ": cannot write BVH: " + *bad);
    return writeFileAtomically(path, writeBvhToString(motion, options));
}

}  // namespace fray
