#pragma once
// One function per subcommand (cli/<name>.cpp); main.cpp wires them to CLI11 and maps errors
// to exit codes.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace tc {
class TechniqueRegistry;
}

namespace tc::cli {

void addRenderCommand(CLI::App& app);
void addValidateCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addConvertCommand(CLI::App& app);
void addPartitionCommand(CLI::App& app);
void addMergeTimingsCommand(CLI::App& app);  // cli/batch_commands.cpp
void addTechniquesCommand(CLI::App& app);
void addSceneCommand(CLI::App& app);
void addEncodeCommand(CLI::App& app);

// The technique table of `tubecast techniques --markdown` (README.md's).
std::string techniquesMarkdown(const TechniqueRegistry& registry);

// Set by subcommands that end with a non-zero code without an exception (compare --fail).
extern int g_exitCode;

}  // namespace tc::cli
