// Save and load times of one field in every format (bench/formats.sh runs it on the Stanford
// bunny's res-256 field). Prints, per format, the best of --repeat runs: wall seconds, MB/s of
// float32 samples, CPU seconds of the process (all threads; steadier than wall time on a busy
// machine), and the file size; every load is checked against the saved field.
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"

#include <CLI/CLI.hpp>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>

int main(int argc, char** argv) {
    CLI::App app{"Save and load a field in every format (sdfgen's field formats benchmark)"};
    std::string input;
    int repeat = 2;
    double band = 3;
    app.add_option("field", input, "A field file in any format")->required();
    app.add_option("--repeat", repeat, "Runs per format; the best is printed")->check(CLI::Range(1, 100))->capture_default_str();
    app.add_option("--band", band, "Band of the extra banded .vdb row, in voxels")->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        using Clock = std::chrono::steady_clock;
        auto seconds = [](Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); };
        const sdfgen::Field field = sdfgen::loadField(input);
        const double megabytes = double(field.values.size()) * sizeof(float) / 1e6;
        std::printf("%s: %dx%dx%d samples (%.1f MB of float32), best of %d\n", input.c_str(), field.grid.dims.x,
                    field.grid.dims.y, field.grid.dims.z, megabytes, repeat);
        std::printf("%-12s %10s %10s %10s %10s %10s %10s %10s\n", "format", "save s", "save MB/s", "save cpu", "load s", "load MB/s",
                    "load cpu", "file MB");
        const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("sdfgen-bench-formats-" + std::to_string(getpid()));
        std::filesystem::create_directories(folder);
        std::vector<std::pair<std::string, sdfgen::SaveOptions>> rows;
        for (const std::string& extension : sdfgen::fieldFormatExtensions()) rows.push_back({extension, {}});
        sdfgen::SaveOptions banded;
        banded.band = band;
        rows.push_back({".vdb", banded});
        for (const auto& [extension, options] : rows) {
            const std::string path = (folder / ("field" + extension)).string();
            double save = 1e30, load = 1e30, saveCpu = 1e30, loadCpu = 1e30;
            for (int run = 0; run < repeat; ++run) {
                auto start = Clock::now();
                std::clock_t cpu = std::clock();
                sdfgen::saveField(field, path, options);
                save = std::min(save, seconds(start));
                saveCpu = std::min(saveCpu, double(std::clock() - cpu) / CLOCKS_PER_SEC);
                start = Clock::now();
                cpu = std::clock();
                const sdfgen::Field loaded = sdfgen::loadField(path);
                load = std::min(load, seconds(start));
                loadCpu = std::min(loadCpu, double(std::clock() - cpu) / CLOCKS_PER_SEC);
                const bool same = options.band > 0 ? loaded.values.size() == field.values.size()
                                                   : std::memcmp(loaded.values.data(), field.values.data(), field.values.size() * sizeof(float)) == 0;
                if (!same) throw sdfgen::Error(path + ": loaded values differ from the saved ones");
            }
            const std::string name = options.band > 0 ? extension + " band " + std::to_string(int(band)) : extension;
            std::printf("%-12s %10.3f %10.0f %10.3f %10.3f %10.0f %10.3f %10.1f\n", name.c_str(), save, megabytes / save, saveCpu, load,
                        megabytes / load, loadCpu, double(std::filesystem::file_size(path)) / 1e6);
        }
        std::filesystem::remove_all(folder);
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "bench_formats: %s\n", e.what());
        return 1;
    }
    return 0;
}
