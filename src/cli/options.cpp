#include "cli/commands.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/error.hpp"

#include <cmath>
#include <filesystem>
#include <map>
#include <unistd.h>

namespace sdfgen::cli {

void addBakeOptions(CLI::App& command, BakeSettings& settings, int& threads) {
    command.add_option("--res", settings.res, "Voxels along the longest side of the padded bounding box")
        ->check(CLI::Range(1, 1 << 16))
        ->capture_default_str();
    const std::map<std::string, DistanceMethod> methods = {
        {"exact", DistanceMethod::Exact}, {"rays", DistanceMethod::Rays}, {"brute", DistanceMethod::Brute}};
    command.add_option("--method", settings.method, "Distance: exact (nearest triangle), rays (the report's ray sampling) or brute (reference, slow)")
        ->transform(CLI::CheckedTransformer(methods, CLI::ignore_case))
        ->default_str("exact");
    const std::map<std::string, SignMethod> signs = {{"auto", SignMethod::Auto},
                                                     {"rays", SignMethod::Rays},
                                                     {"pseudonormal", SignMethod::Pseudonormal},
                                                     {"winding", SignMethod::Winding}};
    command.add_option("--sign", settings.sign,
                       "Inside test: auto (pseudonormal when the mesh check proves it right, else winding), winding "
                       "(generalized winding number), pseudonormal, or rays (majority of back faces). Default: rays "
                       "for --method rays, auto otherwise")
        ->transform(CLI::CheckedTransformer(signs, CLI::ignore_case));
    command.add_option("--rays", settings.rays, "Rays per sample for --method rays and --sign rays")->check(CLI::Range(1, 65536))->capture_default_str();
    command.add_option("--padding", settings.padding, "Margin around the mesh, as a fraction of its longest side")
        ->check(finiteRange(0.0, 100.0))
        ->capture_default_str();
    const std::map<std::string, Device> devices = {{"cpu", Device::Cpu}, {"gpu", Device::Gpu}, {"auto", Device::Auto}};
    command.add_option("--device", settings.device,
                       "Where exact distances and winding signs run: gpu (OpenGL 4.5 compute, also on Mesa's llvmpipe), "
                       "cpu, or auto (the GPU when a hardware OpenGL 4.5 driver is there, else the CPU)")
        ->transform(CLI::CheckedTransformer(devices, CLI::ignore_case))
        ->default_str("auto");
    command.add_option("--threads", threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024))->capture_default_str();
}

std::string fieldFormatList() {
    std::string list;
    for (const std::string& extension : fieldFormatExtensions()) list += (list.empty() ? "" : ", ") + extension;
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

void refuseOverwritingInput(const std::string& output, const std::vector<std::string>& inputs) {
    for (const std::string& input : inputs) {
        std::error_code ec;
        if (!input.empty() && std::filesystem::equivalent(output, input, ec) && !ec) {
            throw Error(output + ": is the input file " + input + "; refusing to overwrite it");
        }
    }
}

Mesh loadScene(const std::vector<std::string>& paths) {
    if (paths.size() == 1) return loadMesh(paths[0]);
    std::vector<Mesh> meshes;
    std::vector<MeshInstance> parts;
    std::string name;
    for (const std::string& path : paths) {
        meshes.push_back(loadMesh(path));
        name += (name.empty() ? "" : "+") + std::filesystem::path(path).filename().string();
    }
    for (const Mesh& mesh : meshes) parts.push_back({&mesh, glm::dmat4(1.0)});
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
