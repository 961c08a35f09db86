// `sdfgen info`: the SIMD path of the CPU kernel, the OpenGL driver the GPU device would use, and
// what --device auto would pick.
#include "cli/commands.hpp"
#include "core/simd/path.hpp"
#include "sdfgen/device.hpp"
#include "sdfgen/error.hpp"

#include <cstdio>

namespace sdfgen::cli {

void addInfoCommand(CLI::App& app) {
    CLI::App* info = app.add_subcommand("info", "Print the CPU kernel's SIMD path, the OpenGL driver the GPU device uses and what --device auto picks");
    info->callback([] {
        std::printf("CPU kernel: %s (AVX2 %s on this CPU; SDFGEN_SIMD=baseline or avx2 forces a path)\n", toString(simdPath()),
                    simdPathAvailable(SimdPath::Avx2) ? "available" : "not available");
        std::string why;
        try {
            selectComputeDevice(Device::Gpu, &why);
            std::printf("GPU device: %s\n", why.substr(why.find(' ') + 1).c_str());
        } catch (const Error& e) {
            std::printf("GPU device: none (%s)\n", e.what());
        }
        selectComputeDevice(Device::Auto, &why);
        std::printf("--device auto: %s\n", why.c_str());
    });
}

} // namespace sdfgen::cli
