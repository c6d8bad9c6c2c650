// fray-cli info FILE [--json]: what is in a capture file, skeleton by
// skeleton when it holds several characters.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "fray/core/joint_guess.h"
#include "fray/core/kinematics.h"
#include "options.h"
#include "verbs.h"

namespace fray::cli {
namespace {

struct InfoArgs {
    std::string file;
    bool json = false;
    ImportFlags flags;
};

nlohmann::json describe(const Motion& m) {
    const Skeleton& sk = m.skeleton();
    nlohmann::json j;
    j["file"] = m.source().path;
    j["format"] = m.source().format;
    j["joints"] = sk.jointCount();
    j["joint_names"] = sk.names;
    j["frames"] = m.frameCount();
    j["fps"] = m.fps();
    j["duration_s"] = m.duration();
    j["units"] = m.source().unitName;
    j["unit_scale_to_m"] = m.source().unitScale;
    j["up_axis"] = m.source().sourceUp == UpAxis::Z ? "Z" : "Y";
    j["normalized"] = m.source().normalized;
    j["channels"] = sk.channelCount();
    j["warnings"] = m.source().warnings;
    nlohmann::json layout = nlohmann::json::array();
    for (int i = 0; i < sk.jointCount(); ++i) {
        std::string s;
        for (Channel c : sk.channels[static_cast<std::size_t>(i)]) s += (s.empty() ? "" : " ") + std::string(toString(c));
        layout.push_back({{"joint", sk.names[static_cast<std::size_t>(i)]},
                          {"channels", sk.channels[static_cast<std::size_t>(i)].size()},
                          {"order", std::string(toString(sk.rotationOrders[static_cast<std::size_t>(i)]))},
                          {"layout", s}});
    }
    j["channel_layout"] = layout;
    // Path extent of the pelvis (not the file's root, which may be a static
    // helper joint) on the floor and in height.
    const StandardJoints sj = guessStandardJoints(sk);
    const auto pelvis = static_cast<std::size_t>(sj.pelvis >= 0 ? sj.pelvis : 0);
    glm::vec3 lo(1e30f), hi(-1e30f), prev(0);
    double path = 0;
    std::vector<glm::vec3> pos(static_cast<std::size_t>(m.jointCount()));
    std::vector<glm::quat> rot(pos.size());
    for (int f = 0; f < m.frameCount(); ++f) {
        worldTransforms(m, f, pos, rot);
        const glm::vec3 p = pos[pelvis];
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
        if (f > 0) {
            const glm::vec3 d = p - prev;
            path += std::sqrt(static_cast<double>(d.x * d.x + d.z * d.z));
        }
        prev = p;
    }
    if (m.frameCount() == 0) lo = hi = glm::vec3(0);
    j["root_extent"] = {{"joint", sk.names[pelvis]}, {"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}, {"floor_path_length", path}};
    auto nameOf = [&](int i) { return i >= 0 ? nlohmann::json(sk.names[static_cast<std::size_t>(i)]) : nlohmann::json(nullptr); };
    j["standard_joints"] = {{"pelvis", nameOf(sj.pelvis)},     {"head", nameOf(sj.head)},
                            {"left_hand", nameOf(sj.leftHand)}, {"right_hand", nameOf(sj.rightHand)},
                            {"left_foot", nameOf(sj.leftFoot)}, {"right_foot", nameOf(sj.rightFoot)},
                            {"left_toe", nameOf(sj.leftToe)},   {"right_toe", nameOf(sj.rightToe)}};
    return j;
}

void printText(const Motion& motion, const nlohmann::json& j) {
    const auto& ext = j["root_extent"];
    std::printf("file        %s (%s)\n", j["file"].get<std::string>().c_str(), j["format"].get<std::string>().c_str());
    std::printf("frames      %d at %.3f fps (%.2f s)\n", motion.frameCount(), motion.fps(), motion.duration());
    std::printf("units       %s (x%g to metres), up axis %s%s\n", j["units"].get<std::string>().c_str(),
                motion.source().unitScale, j["up_axis"].get<std::string>().c_str(),
                motion.source().normalized ? ", normalised to metres Y-up" : ", raw");
    std::printf("joints      %d, %d channels\n", motion.jointCount(), motion.skeleton().channelCount());
    for (const auto& l : j["channel_layout"])
        std::printf("  %-24s %d  %s\n", l["joint"].get<std::string>().c_str(), l["channels"].get<int>(),
                    l["layout"].get<std::string>().c_str());
    std::printf("%s extent x [%.3f, %.3f]  y [%.3f, %.3f]  z [%.3f, %.3f], floor path %.2f\n",
                ext["joint"].get<std::string>().c_str(), ext["min"][0].get<double>(), ext["max"][0].get<double>(), ext["min"][1].get<double>(),
                ext["max"][1].get<double>(), ext["min"][2].get<double>(), ext["max"][2].get<double>(),
                ext["floor_path_length"].get<double>());
    std::string sj;
    for (auto& [k, v] : j["standard_joints"].items())
        sj += " " + k + "=" + (v.is_null() ? std::string("?") : v.get<std::string>());
    std::printf("standard   %s\n", sj.c_str());
    for (const auto& w : motion.source().warnings) std::printf("warning     %s\n", w.c_str());
}

void run(const InfoArgs& a) {
    auto opts = toLoadOptions(a.flags);
    if (!opts) return fail(opts.error().message, 2);
    // Every skeleton: a file with several characters (Fray's own glTF and FBX
    // exports) is described character by character.
    auto motions = loadMotions(a.file, *opts);
    if (!motions) return fail(motions.error().message);
    const auto n = motions->size();
    if (a.json) {
        // The first skeleton's fields at the top, as for a one-skeleton file;
        // with several, "skeletons" describes each.
        nlohmann::json j = describe(motions->front());
        j["skeleton_count"] = n;
        if (n > 1) {
            j["skeletons"] = nlohmann::json::array();
            for (const Motion& m : *motions) j["skeletons"].push_back(describe(m));
        }
        // Joint and file names from a capture need not be UTF-8: U+FFFD, not an exception.
        std::printf("%s\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
        return;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const Motion& m = (*motions)[i];
        if (n > 1) {
            std::printf("%sskeleton   %zu of %zu, root %s\n", i ? "\n" : "", i + 1, n,
                        m.skeleton().names.empty() ? "?" : m.skeleton().names.front().c_str());
        }
        printText(m, describe(m));
    }
}

}  // namespace

void registerInfo(CLI::App& app) {
    auto args = std::make_shared<InfoArgs>();
    auto* cmd = app.add_subcommand("info", "Describe a capture file: skeleton, frames, fps, units, up axis, channels");
    cmd->add_option("file", args->file, "BVH, FBX, glTF/GLB or DAE file (every character of a multi-character file)")
        ->required();
    cmd->add_flag("--json", args->json, "Print JSON");
    addImportFlags(cmd, args->flags);
    cmd->callback([args] { run(*args); });
}

}  // namespace fray::cli
