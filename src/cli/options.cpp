#include "cli/commands.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/error.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <unistd.h>

namespace sdfgen::cli {

void addBakeOptions(CLI::App& command, BakeSettings& settings, int& threads) {
    command.add_option("--res", settings.res, "Voxels along the longest side of the padded bounding box (1 to " + std::to_string(kMaxRes) + ")")
        ->capture_default_str();
    command.add_option("--method", settings.method, "Distance: " + describeChoices(distanceMethodChoices()))
        ->transform(choiceOf(distanceMethodChoices(), "distance method"))
        ->default_str(toString(settings.method));
    command.add_option("--sign", settings.sign, "Inside test: " + describeChoices(signMethodChoices()))
        ->transform(choiceOf(signMethodChoices(), "sign method"))
        ->default_str(toString(settings.sign));
    command.add_option("--rays", settings.rays, "Rays per sample for --method rays and --sign rays (1 to " + std::to_string(kMaxRays) + ")")
        ->capture_default_str();
    command.add_option("--padding", settings.padding, "Margin around the mesh, as a fraction of its longest side (0 to 100)")
        ->capture_default_str();
    command.add_option("--device", settings.device, "Where exact distances and winding signs run: " + describeChoices(deviceChoices()))
        ->transform(choiceOf(deviceChoices(), "device"))
        ->type_name("ENUM") // one of the names listed, as --method's and --sign's
        ->default_str(settings.device);
    addThreadsOption(command, threads);
}

void checkBakeSettings(const BakeSettings& settings) {
    if (const std::optional<SettingsProblem> refused = problem(settings)) throw Error("--" + refused->setting + ": " + refused->message);
}

void addThreadsOption(CLI::App& command, int& threads) {
    command.add_option("--threads", threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, kMaxThreads))->capture_default_str();
}

RunControl commandControl(int threads) {
    RunControl control;
    control.threads = threads;
    // On a terminal the line is cleared first: a progress bar may be drawn there.
    control.warn = [terminal = isatty(fileno(stderr)) != 0](const std::string& warning) {
        std::fprintf(stderr, "%ssdfgen: warning: %s\n", terminal ? "\r\033[K" : "", warning.c_str());
    };
    return control;
}

std::string fieldFormatList() {
    std::string list;
    for (const std::string& extension : fieldFormatExtensions()) list += (list.empty() ? "" : ", ") + extension;
    return list;
}

std::string meshFormatList() {
    std::string list;
    for (const std::string& extension : meshFormatExtensions()) list += (list.empty() ? "" : ", ") + extension;
    return list;
}

CLI::Validator finiteRange(double min, double max) {
    return CLI::Validator(
        [min, max](std::string& text) -> std::string {
            char* end = nullptr;
            const double value = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || !std::isfinite(value)) return "'" + text + "' is not a finite number";
            if (value < min || value > max) {
                char range[96];
                std::snprintf(range, sizeof(range), "%g is not in [%g, %g]", value, min, max);
                return range;
            }
            return "";
        },
        "FINITE in [" + CLI::detail::to_string(min) + " - " + CLI::detail::to_string(max) + "]");
}

CLI::Validator wholeNumber(std::uint64_t min, std::uint64_t max) {
    return CLI::Validator(
        [min, max](std::string& text) -> std::string {
            const bool digits = !text.empty() && std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
            errno = 0;
            const unsigned long long value = digits ? std::strtoull(text.c_str(), nullptr, 10) : 0;
            if (!digits || errno == ERANGE || value < min || value > max) {
                return "'" + text + "' is not a whole number from " + std::to_string(min) + " to " + std::to_string(max);
            }
            return "";
        },
        "UINT in [" + std::to_string(min) + " - " + std::to_string(max) + "]");
}

Mesh loadScene(const std::vector<std::string>& paths) {
    if (paths.size() == 1) return loadMesh(paths[0]);
    std::vector<Mesh> meshes;
    for (const std::string& path : paths) meshes.push_back(loadMesh(path));
    return mergeScene(meshes, paths);
}

Mesh mergeScene(const std::vector<Mesh>& meshes, const std::vector<std::string>& paths) {
    std::vector<MeshInstance> parts;
    std::string name;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        parts.push_back({&meshes[i], glm::dmat4(1.0)});
        name += (name.empty() ? "" : "+") + std::filesystem::path(paths[i]).filename().string();
    }
    return mergeMeshes(parts, name);
}

std::string defaultMeshPath() {
    // Next to the source tree the binary was built from, or beside an installed binary.
    const std::filesystem::path built = std::filesystem::path(SDFGEN_SOURCE_DIR) / "assets" / "bunny.obj";
    if (std::filesystem::exists(built)) return built.string();
    char self[4096];
    const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
    if (n > 0) {
        self[n] = '\0';
        const std::filesystem::path bin = std::filesystem::path(self).parent_path();
        for (const std::filesystem::path& beside : {bin / "assets" / "bunny.obj", bin.parent_path() / "share" / "sdfgen" / "assets" / "bunny.obj"}) {
            if (std::filesystem::exists(beside)) return beside.string();
        }
    }
    return built.string();
}

} // namespace sdfgen::cli
