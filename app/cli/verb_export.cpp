// fray-cli export: a planned scene as files other tools read (docs/EXPORT.md).
//
//   export SCENE.frayscene [--format gltf|glb|bvh|fbx] --out DIR [--fps N] [--name NAME]
//          [--rig FILE] [--root-motion none|floor|in-place]
//          [--posture kinematic|physics]
//
// glTF/GLB/FBX: one file with every character skinned and animated; BVH: one
// file per character; always DIR/NAME.FORMAT.scene.json (who does what, when,
// where).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "fray/export/export.h"
#include "fray/io/rig_import.h"

#include "fray/posture/posture.h"
#include "cli_session.h"
#include "options.h"
#include "verbs.h"

namespace fray::cli {
namespace {

namespace fs = std::filesystem;

struct ExportArgs {
    std::string scene, format = "gltf", out, name, posture;
    std::string rig, rootMotion = "none";
    double fps = 30.0;
    bool quiet = false, handPins = false;
};

void runExport(const ExportArgs& a) {
    const auto format = exporter::parseFormat(a.format);
    if (!format) {
        return fail("export: unknown format '" + a.format + "' (expected " + std::string(exporter::kFormatNames) + ")");
    }
    exporter::ExportOptions options;
    options.format = *format;
    options.outDir = a.out;
    options.fps = a.fps;
    // An explicit --name must be file-safe (refused otherwise); the scene
    // file's stem is made file-safe ("my duel.frayscene" -> "my_duel").
    options.name = a.name.empty() ? exporter::fileSafeName(fs::path(a.scene).stem().string()) : a.name;
    options.source = fs::path(a.scene).filename().string();
    if (auto st = exporter::validateOptions(options); !st) return fail(st.error().message);
    const auto rootMotion = exporter::parseRootMotion(a.rootMotion);
    if (!rootMotion) return fail("export: --root-motion: expected none, floor or in-place, got '" + a.rootMotion + "'");
    options.rootMotion = *rootMotion;
    if (!a.rig.empty()) {
        auto rig = loadRigSkeleton(a.rig);
        if (!rig) return fail("export: --rig: " + rig.error().message);
        if (!a.quiet)
            for (const auto& w : rig->warnings) std::fprintf(stderr, "fray-cli: note: %s: %s\n", a.rig.c_str(), w.c_str());
        options.rig = std::move(rig->target);
        if (rig->skin) options.rigSkin = std::make_shared<const SkinnedMesh>(std::move(*rig->skin));
    }
    const auto progress = stderrProgress(a.quiet);
    const auto mode = postureMode(a.posture);
    if (!mode) return fail(mode.error().message);
    const auto postureOpts = postureOptions(a.posture, a.handPins);
    if (!postureOpts) return fail(postureOpts.error().message);
    auto loaded = openScene(a.scene, progress);
    if (!loaded) return fail(loaded.error().message);
    // --posture physics: the solver's poses (docs/POSTURE.md), simulated once
    // at 60 fps and sampled at the export rate.
    std::optional<posture::ScenePoses> physics;
    if (*mode == posture::Mode::Physics) {
        auto poses = posture::ScenePoses::make(*mode, loaded->scene, loaded->session->library, *postureOpts, progress);
        if (!poses) return fail(poses.error().message);
        physics.emplace(std::move(*poses));
        printPostureNotes(physics->report(), a.quiet);
        options.poses = [&physics](int c, double t, Pose& out) { physics->pose(c, t, out); };
    }
    auto report = exporter::exportScene(loaded->scene, loaded->session->library, options, progress);
    if (!report) return fail(report.error().message);
    std::printf("%s: %zu characters, %d frames at %g fps (%.1f s) as %s:\n", a.scene.c_str(),
                loaded->scene.characters.size(), report->frames, options.fps, loaded->scene.duration, a.format.c_str());
    for (const auto& f : report->files) std::printf("  %s\n", f.string().c_str());
    for (const auto& n : report->notes) std::printf("note: %s\n", n.c_str());
    if (physics) std::printf("posture: physics (the posture solver's poses)\n");
}

}  // namespace

void registerExport(CLI::App& app) {
    auto args = std::make_shared<ExportArgs>();
    auto* cmd = app.add_subcommand("export", "Write a planned scene as glTF 2.0 / GLB, BVH or FBX (docs/EXPORT.md)");
    cmd->add_option("scene", args->scene, "Scene file (*.frayscene)")->required();
    cmd->add_option("--format", args->format, "gltf (one .gltf, buffer embedded; default), glb, bvh (one file per "
                                              "character) or fbx (centimetres)");
    cmd->add_option("-o,--out", args->out, "Output folder (created when missing)")->required();
    cmd->add_option("--fps", args->fps, "Samples per second of scene time (1-1000, default 30)");
    cmd->add_option("--name", args->name,
                    "File stem: letters, digits, '_', '-', '.' (default: the scene file's, other characters as '_')");
    cmd->add_option("--rig", args->rig,
                    "Retarget every character onto this rig's skeleton (glTF/GLB, FBX, BVH, ...): its joint names, "
                    "hierarchy, proportions and local frames");
    cmd->add_option("--root-motion", args->rootMotion,
                    "none (default), floor (a root bone on the floor carries the trajectory) or in-place (the root bone "
                    "stays at the origin)");
    addPostureFlag(cmd, args->posture,
                   "Posture mode: kinematic (the captured clips; default) or physics (the posture solver, docs/POSTURE.md)");
    addHandPinsFlag(cmd, args->handPins);
    cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
    cmd->callback([args] { runExport(*args); });
}

}  // namespace fray::cli
