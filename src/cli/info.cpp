// `sdfgen info`: the SIMD path of the CPU kernel, the OpenGL driver the GPU device would use, and
// what --device auto would pick.
#include "cli/commands.hpp"
#include "core/simd/path.hpp"
#include "sdfgen/device.hpp"
#include "sdfgen/error.hpp"

#include <cctype>
#include <cstdio>
#include <string>
#include <vector>

namespace sdfgen::cli {

void addInfoCommand(CLI::App& app) {
    CLI::App* info = app.add_subcommand("info", "Print the CPU kernel's SIMD path, the OpenGL driver the GPU device uses and what --device auto picks");
    info->callback([] {
        auto available = [](SimdPath path) { return simdPathAvailable(path) ? "available" : "not available"; };
        std::printf("CPU kernel: %s (AVX2 %s, AVX-512 %s on this CPU; SDFGEN_SIMD=baseline, avx2 or avx512 forces a path)\n",
                    toString(simdPath()), available(SimdPath::Avx2), available(SimdPath::Avx512));
        // Each registered device (cpu and auto are the core's own), by its name in capitals: "GPU device: ...".
        const std::vector<Choice<std::string>> devices = deviceChoices();
        if (devices.size() == 2) std::printf("GPU device: none (this program was built without a GPU device)\n");
        for (std::size_t d = 1; d + 1 < devices.size(); ++d) {
            std::string label = devices[d].name;
            for (char& c : label) c = char(std::toupper(static_cast<unsigned char>(c)));
            try {
                std::printf("%s device: %s\n", label.c_str(), selectComputeDevice(devices[d].id)->description().c_str());
            } catch (const Error& e) {
                std::printf("%s device: none (%s)\n", label.c_str(), e.what());
            }
        }
        std::string why;
        selectComputeDevice("auto", &why);
        std::printf("--device auto: %s\n", why.c_str());
    });
}

} // namespace sdfgen::cli
