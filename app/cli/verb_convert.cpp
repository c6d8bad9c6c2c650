// fray-cli convert IN OUT [--fps N]: anything importable to BVH (metres, Y-up).
#include <cstdio>
#include <memory>

#include "fray/io/bvh.h"
#include "options.h"
#include "verbs.h"

namespace fray::cli {
namespace {

struct ConvertArgs {
    std::string in, out;
    double fps = 0;
    ImportFlags flags;
};

void run(const ConvertArgs& a) {
    auto opts = toLoadOptions(a.flags);
    if (!opts) return fail(opts.error().message, 2);
    std::error_code ec;
    if (std::filesystem::equivalent(a.in, a.out, ec))
        return fail(a.out + ": output is the input file; refusing to overwrite it", 2);
    auto motion = loadMotion(a.in, *opts);
    if (!motion) return fail(motion.error().message);
    Motion m = std::move(*motion);
    if (a.fps > 0) {
        auto r = resample(m, a.fps);
        if (!r) return fail(r.error().message);
        m = std::move(*r);
    }
    if (auto st = writeBvh(m, a.out); !st) return fail(st.error().message);
    std::fprintf(stderr, "wrote %s: %d joints, %d frames at %.3f fps\n", a.out.c_str(), m.jointCount(), m.frameCount(),
                 m.fps());
}

}  // namespace

void registerConvert(CLI::App& app) {
    auto args = std::make_shared<ConvertArgs>();
    auto* cmd = app.add_subcommand("convert", "Convert any importable file to BVH (metres, Y-up)");
    cmd->add_option("in", args->in, "Input file (BVH, FBX, glTF/GLB, DAE)")->required();
    cmd->add_option("out", args->out, "Output BVH file")->required();
    cmd->add_option("--fps", args->fps, "Resample to this frame rate (at most 1000)")->check(finitePositive(kMaxFps));
    addImportFlags(cmd, args->flags);
    cmd->callback([args] { run(*args); });
}

}  // namespace fray::cli
