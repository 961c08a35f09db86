// sdfgen command line: a thin front end over the core library.
#include "cli/commands.hpp"
#include "core/error.hpp"

#include <cstdio>

int main(int argc, char** argv) {
    CLI::App app{"sdfgen: signed distance fields from triangle meshes"};
    app.require_subcommand(1);
    sdfgen::cli::addBakeCommand(app);
    sdfgen::cli::addBenchCommand(app);
    sdfgen::cli::addCompareCommand(app);
    sdfgen::cli::addRenderCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "sdfgen: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sdfgen: internal error: %s\n", e.what());
        return 2;
    }
    return 0;
}
