#pragma once
#include "core/bake.hpp"

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace sdfgen::cli {

// Each command adds its subcommand and options to the app and runs when it is chosen.
void addBakeCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);

// The options every generating command shares (--res, --rays, --padding, --threads).
void addBakeOptions(CLI::App& command, BakeSettings& settings, int& threads);

// The mesh the project ships, used when a command is given none.
std::string defaultMeshPath();

} // namespace sdfgen::cli
