// `sdfgen info`: the OpenGL driver the GPU device would use, and what --device auto would pick.
#include "cli/commands.hpp"
#include "sdfgen/device.hpp"
#include "sdfgen/error.hpp"

#include <cstdio>

namespace sdfgen::cli {

void addInfoCommand(CLI::App& app) {
    CLI::App* info = app.add_subcommand("info", "Print the OpenGL driver the GPU device uses and what --device auto picks");
    info->callback([] {
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
