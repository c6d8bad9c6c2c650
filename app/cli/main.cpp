// fray-cli: every pipeline step headless, for batch jobs and tests.
#include <cstdio>
#include <exception>

#include "verbs.h"

namespace fray::cli {

int& exitCode() {
    static int code = 0;
    return code;
}

void fail(const std::string& message, int code) {
    std::fprintf(stderr, "fray-cli: %s\n", message.c_str());
    exitCode() = code;
}

}  // namespace fray::cli

int main(int argc, char** argv) {
    CLI::App app{"fray-cli: turn single-actor motion capture into multi-character interaction scenes"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "fray-cli 0.1.0");
    fray::cli::registerInfo(app);
    fray::cli::registerConvert(app);
    fray::cli::registerBench(app);
    fray::cli::registerDemoLibrary(app);
    fray::cli::registerPrep(app);
    fray::cli::registerSim(app);
    fray::cli::registerPatches(app);
    fray::cli::registerSetup(app);
    fray::cli::registerRender(app);
    fray::cli::registerExport(app);
#ifdef FRAY_CLI_EDIT
    fray::cli::registerEdit(app);
#endif
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        fray::cli::fail(std::string("internal error: ") + e.what(), 70);
    }
    return fray::cli::exitCode();
}
