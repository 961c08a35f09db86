#pragma once
#include "core/io/atomic_file.hpp"
#include "sdfgen/sdfgen.hpp"

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <type_traits>
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

// The options every generating command shares (--res, --rays, --padding, --threads). Their
// limits are problem()'s (sdfgen/bake.hpp), checked by checkBakeSettings once all are read.
void addBakeOptions(CLI::App& command, BakeSettings& settings, int& threads);
// Throws Error for settings that problem() refuses, naming the setting as its option: "--rays:
// rays must be from 1 to 65536 per sample (got 0)". Each command calls it before it loads anything.
void checkBakeSettings(const BakeSettings& settings);

// The --threads option, 0 (all cores) to kMaxThreads, the same for every command.
void addThreadsOption(CLI::App& command, int& threads);

// A command's RunControl, made before it loads anything: `threads`, and warnings printed to
// stderr as "sdfgen: warning: ..." the moment they arise. Progress is the command's to add.
RunControl commandControl(int threads);

// The field file extensions, for help texts: ".sdf, .npy, ...".
std::string fieldFormatList();
// The mesh file extensions sdfgen is tested with, for help texts: ".obj, .ply, ...".
std::string meshFormatList();

// An option named from a registry's choices (in any case), turned into its id (an enum's value, or
// the device's name); an unknown name is refused with parseChoice's Error (the known names and what
// each is).
template <class Id>
CLI::Validator choiceOf(const std::vector<Choice<Id>>& choices, const std::string& what) {
    std::string names;
    for (const Choice<Id>& choice : choices) names += (names.empty() ? "" : ",") + std::string(choice.name);
    return CLI::Validator(
        [choices, what](std::string& text) -> std::string {
            try {
                if constexpr (std::is_enum_v<Id>) {
                    text = std::to_string(int(parseChoice(choices, text, what)));
                } else {
                    text = parseChoice(choices, text, what);
                }
                return "";
            } catch (const Error& e) {
                return e.what();
            }
        },
        "{" + names + "}");
}
// The checks of numeric options other than the bake settings (every one uses one of them):
// CLI::Range lets NaN and infinities through, and an unsigned option saturates negative and too
// large values at its maximum.
// A finite number in [min, max].
CLI::Validator finiteRange(double min, double max);
// A whole number in [min, max] written in decimal digits alone (no sign, no exponent).
CLI::Validator wholeNumber(std::uint64_t min, std::uint64_t max);

// One mesh, or several merged into one scene (mergeMeshes, in place, named "A.obj+B.obj").
Mesh loadScene(const std::vector<std::string>& paths);
// The meshes of `paths` merged as loadScene merges them (`meshes[i]` loaded from `paths[i]`).
Mesh mergeScene(const std::vector<Mesh>& meshes, const std::vector<std::string>& paths);

// The mesh the project ships, used when a command is given none.
std::string defaultMeshPath();

// The sampling options `sample` and `batch --format samples` share (--seed, --surface-fraction, variances).
void addSampleOptions(CLI::App& command, SampleSettings& settings);

} // namespace sdfgen::cli
