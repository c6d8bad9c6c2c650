#pragma once
// Each fray-cli verb registers its subcommand here. A verb's callback returns
// the process exit code; errors go to stderr as one line.
#include <CLI/CLI.hpp>

namespace fray::cli {

// Set by a verb's callback; main() returns it.
int& exitCode();

void registerInfo(CLI::App& app);
void registerConvert(CLI::App& app);
void registerBench(CLI::App& app);
void registerDemoLibrary(CLI::App& app);
void registerPrep(CLI::App& app);
void registerSim(CLI::App& app);
void registerPatches(CLI::App& app);
void registerSetup(CLI::App& app);
void registerRender(CLI::App& app);
void registerExport(CLI::App& app);
void registerEdit(CLI::App& app);  // annotate, cuts: built when fray_authoring is (FRAY_CLI_EDIT)

// Prints "fray-cli: <message>" on stderr and sets a failing exit code.
void fail(const std::string& message, int code = 1);

}  // namespace fray::cli
