#pragma once
#include "sdfgen/sdfgen.hpp"

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace sdfgen::cli {

// Each command adds its subcommand and options to the app and runs when it is chosen.
void addBakeCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addSurfaceCommand(CLI::App& app);
void addQueryCommand(CLI::App& app);
void addSampleCommand(CLI::App& app);
// Sets exitCode to 1 when any mesh failed (the batch itself went on).
void addBatchCommand(CLI::App& app, int& exitCode);

// The options every generating command shares (--res, --rays, --padding, --threads).
void addBakeOptions(CLI::App& command, BakeSettings& settings, int& threads);

// The field file extensions, for help texts: ".sdf, .npy, ...".
std::string fieldFormatList();
// A CLI11 check that the value is a finite number in [min, max] (CLI::Range lets NaN through).
CLI::Validator finiteRange(double min, double max);

// Refuses (Error) an output path that names one of the inputs, also through symbolic or hard links.
void refuseOverwritingInput(const std::string& output, const std::vector<std::string>& inputs);
// One mesh, or several merged into one scene (mergeMeshes, in place, named "A.obj+B.obj").
Mesh loadScene(const std::vector<std::string>& paths);

// The mesh the project ships, used when a command is given none.
std::string defaultMeshPath();

// The sampling options `sample` and `batch --format samples` share (--seed, --surface-fraction, variances).
void addSampleOptions(CLI::App& command, SampleSettings& settings);

} // namespace sdfgen::cli
