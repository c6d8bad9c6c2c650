#pragma once
// <name>.scene.json: who does which action when and where, the files of the
// export, and the files of earlier exports of the same name in the folder (a
// later export may replace those and no others).
#include <filesystem>
#include <string>
#include <vector>

#include "fray/core/result.h"
#include "fray/export/export.h"
#include "sampled_scene.h"

namespace fray::exporter {

struct SummaryFiles {
    std::vector<std::string> files;    // written by this export, relative to the folder
    std::vector<std::string> earlier;  // left by earlier exports, still there, not rewritten
};

std::string summaryJson(const sim::Scene& scene, const sim::ActionLibrary& lib, const SampledScene& sampled,
                        const ExportOptions& options, const SummaryFiles& files);

// The files an earlier summary lists ("files" and "earlier_files"), or an
// error when the file exists but is not a summary of ours. None when absent.
Result<std::vector<std::string>> earlierExportFiles(const std::filesystem::path& summary);

}  // namespace fray::exporter
