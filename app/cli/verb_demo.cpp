// fray-cli demo-library OUTDIR: the procedural synthetic actor (issue 3).
#include "verbs.h"

namespace fray::cli {
void registerDemoLibrary(CLI::App&) {}
}  // namespace fray::cli
