#include "fray/export/export.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <set>

#include "fray/core/atomic_file.h"
#include "fray/io/bvh.h"
#include "fbx_writer.h"
#include "gltf_writer.h"
#include "retarget_export.h"
#include "rig.h"
#include "sampled_scene.h"
#include "summary.h"

namespace fray::exporter {
namespace {

namespace fs = std::filesystem;

constexpr std::array<std::pair<Format, std::string_view>, 4> kFormats = {
    {{Format::Gltf, "gltf"}, {Format::Glb, "glb"}, {Format::Bvh, "bvh"}, {Format::Fbx, "fbx"}}};

std::string summaryName(const ExportOptions& o) { return o.name + "." + std::string(toString(o.format)) + ".scene.json"; }
// Version 1 wrote one summary per name, whatever the format.
std::string legacySummaryName(const ExportOptions& o) { return o.name + ".scene.json"; }

// Output files in writing order, the summary last; BVH: one per character.
std::vector<std::string> plannedFiles(const SampledScene& s, const ExportOptions& o) {
    std::vector<std::string> out;
    if (o.format == Format::Bvh) {
        for (const auto& c : s.characters) out.push_back(o.name + "_" + c.fileName + ".bvh");
    } else {
        out.push_back(o.name + "." + std::string(toString(o.format)));
    }
    out.push_back(summaryName(o));
    return out;
}

// Creates the folder and checks that a file can be created in it, so an
// unwritable folder fails before any file is written.
Status prepareFolder(const fs::path& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return makeError(dir.string() + ": cannot create the output folder: " + ec.message());
    if (!fs::is_directory(dir, ec)) return makeError(dir.string() + ": exists and is not a folder");
    const fs::path probe = dir / ".fray-export-probe";
    const bool writable = static_cast<bool>(std::ofstream(probe, std::ios::binary | std::ios::trunc));
    fs::remove(probe, ec);
    if (!writable) return makeError(dir.string() + ": cannot write in the output folder (permission denied?)");
    return {};
}

// Existing files among `planned` must come from an earlier export of this
// name and format (its summary lists them) or, for folders written by version
// 1, of this name (the one summary it kept per name). Returns the earlier
// files of this name and format still there that this export does not rewrite.
Result<std::vector<std::string>> checkReplaceable(const fs::path& dir, const std::vector<std::string>& planned,
                                                  const std::string& summary, const std::string& legacySummary) {
    auto earlier = earlierExportFiles(dir / summary);
    if (!earlier) return earlier.error();
    std::set<std::string> allowed(earlier->begin(), earlier->end());
    // A legacy summary that is not ours is simply some other file: it is not
    // written any more, so it only grants nothing.
    if (auto legacy = earlierExportFiles(dir / legacySummary)) allowed.insert(legacy->begin(), legacy->end());
    const std::set<std::string> ours(earlier->begin(), earlier->end());
    std::error_code ec;
    for (const auto& f : planned) {
        const fs::path p = dir / f;
        if (!fs::exists(p, ec) || f == summary) continue;
        if (fs::is_directory(p, ec)) return makeError(p.string() + ": is a folder; cannot write the export there");
        if (!allowed.contains(f)) {
            return makeError(p.string() + ": exists and is not a file of an earlier Fray export; refusing to overwrite it");
        }
    }
    std::vector<std::string> kept;
    for (const auto& f : ours) {
        if (std::find(planned.begin(), planned.end(), f) == planned.end() && fs::exists(dir / f, ec)) kept.push_back(f);
    }
    return kept;
}

Result<std::string> encode(const SampledScene& s, const ExportOptions& o, std::size_t file) {
    switch (o.format) {
        case Format::Gltf: return writeGltf(s, o.name, GltfContainer::Embedded);
        case Format::Glb: return writeGltf(s, o.name, GltfContainer::Binary);
        case Format::Fbx: return writeFbx(s, o.name);
        case Format::Bvh: return writeBvhToString(s.characters[file].motion, BvhWriteOptions{.continuousEuler = true});
    }
    return makeError("unknown export format");
}

ProgressFn scaled(const ProgressFn& progress, double from, double to) {
    if (!progress) return {};
    return [=](double f, std::string_view stage) { return progress(from + (to - from) * f, stage); };
}

}  // namespace

std::string_view toString(Format format) {
    for (const auto& [f, name] : kFormats) {
        if (f == format) return name;
    }
    return "?";
}

std::optional<Format> parseFormat(std::string_view name) {
    for (const auto& [f, n] : kFormats) {
        if (n == name) return f;
    }
    return std::nullopt;
}

Status validateOptions(const ExportOptions& o) {
    if (!std::isfinite(o.fps) || o.fps < 1.0 || o.fps > 1000.0) {
        return makeError("export: --fps must be between 1 and 1000, got " + std::to_string(o.fps));
    }
    const bool plain = !o.name.empty() && o.name != "." && o.name != ".." && o.name.front() != '.' &&
                       o.name.find('/') == std::string::npos && o.name.find('\0') == std::string::npos;
    if (!plain) return makeError("export: the name '" + o.name + "' must be a plain file name (no '/', no leading '.')");
    const auto bad = std::find_if(o.name.begin(), o.name.end(), [](char c) { return !isFileSafe(c); });
    if (bad != o.name.end()) {
        return makeError("export: the name '" + o.name + "' has the character '" + std::string(1, *bad) +
                         "'; use only letters, digits, '_', '-' and '.' (e.g. '" + fileSafeName(o.name) + "')");
    }
    if (o.outDir.empty()) return makeError("export: no output folder given");
    return {};
}

Result<ExportReport> exportScene(const sim::Scene& scene, const sim::ActionLibrary& lib, const ExportOptions& options,
                                 const ProgressFn& progress) {
    if (auto st = validateOptions(options); !st) return st.error();
    auto sampled = sampleScene(scene, lib, options.fps, scaled(progress, 0.0, 0.5), options.poses);
    if (!sampled) return sampled.error();
    std::vector<std::string> rigNotes;
    std::vector<char> retargeted;
    if (options.rig) {
        if (auto st = retargetCharacters(*sampled, *options.rig, rigNotes, &retargeted); !st) return st.error();
        if (const int moved = landHits(*sampled, scene, retargeted); moved > 0)
            rigNotes.push_back(std::to_string(moved) + " of " + std::to_string(scene.hits.size()) +
                               " hits brought onto the defender's body by arm or leg IK (the rig's proportions left them off)");
    }
    for (auto& c : sampled->characters) addRootBone(c.motion, options.rootMotion);
    // The rig's own skin on every retargeted character, bound by joint name
    // (a root bone may have been added above the rig's pelvis).
    if (options.rig && options.rigSkin) {
        int worn = 0;
        for (std::size_t i = 0; i < sampled->characters.size(); ++i) {
            if (i >= retargeted.size() || !retargeted[i]) continue;
            auto& c = sampled->characters[i];
            auto skin = std::make_shared<SkinnedMesh>();
            if (!rebindSkin(*options.rigSkin, options.rig->skeleton, c.motion.skeleton(), *skin)) {
                rigNotes.push_back("character \"" + c.name + "\": the rig's skin does not fit its skeleton; Fray's capsule body is used");
                continue;
            }
            c.skin = std::move(skin);
            ++worn;
        }
        if (worn > 0)
            rigNotes.push_back(std::to_string(worn) + " character(s) wear the rig's own skinned mesh (" +
                               std::to_string(options.rigSkin->vertices.size()) + " vertices)");
    }
    const auto planned = plannedFiles(*sampled, options);
    if (auto st = prepareFolder(options.outDir); !st) return st.error();
    auto earlier = checkReplaceable(options.outDir, planned, summaryName(options), legacySummaryName(options));
    if (!earlier) return earlier.error();

    ExportReport report;
    report.frames = sampled->frames;
    report.notes = std::move(rigNotes);
    std::error_code ec;
    const fs::path legacy = options.outDir / legacySummaryName(options);
    if (fs::exists(legacy, ec) && earlierExportFiles(legacy)) {
        report.notes.push_back(legacy.string() +
                               " is an older summary (one per name, whatever the format) and was left as it is: it "
                               "describes an earlier export, not this one; this export's summary is " +
                               (options.outDir / planned.back()).string());
    }
    for (std::size_t i = 0; i + 1 < planned.size(); ++i) {
        if (!reportProgress(progress, 0.5 + 0.5 * static_cast<double>(i) / static_cast<double>(planned.size()),
                            "export: writing")) {
            return cancelled();
        }
        auto bytes = encode(*sampled, options, i);
        const fs::path file = options.outDir / planned[i];
        if (!bytes) return makeError(file.string() + ": " + bytes.error().message);
        if (auto st = writeFileAtomically(file, *bytes); !st) return st.error();
        report.files.push_back(file);
    }
    const std::vector<std::string> written(planned.begin(), planned.end() - 1);
    const fs::path summary = options.outDir / planned.back();
    const std::string text = summaryJson(scene, lib, *sampled, options, {written, *earlier});
    if (auto st = writeFileAtomically(summary, text); !st) return st.error();
    report.files.push_back(summary);
    reportProgress(progress, 1.0, "export: writing");
    return report;
}

}  // namespace fray::exporter
