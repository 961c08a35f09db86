// sdfgen command line: a thin front end over the core library. With no command, or `view`, it
// opens the viewer window; `sdfgen MESH...` (what a file manager's "open with" runs) opens it on
// those meshes.
#include "app/viewer.hpp"
#include "cli/commands.hpp"
#include "sdfgen/error.hpp"

#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    CLI::App app{"sdfgen: signed distance fields from triangle meshes. With no command, opens the viewer."};
    app.require_subcommand(0, 1);
    sdfgen::cli::addBakeCommand(app);
    sdfgen::cli::addBenchCommand(app);
    sdfgen::cli::addCompareCommand(app);
    sdfgen::cli::addRenderCommand(app);
    std::vector<std::string> viewMeshes;
    CLI::App* view = app.add_subcommand("view", "Open the viewer window (the default when no command is given)");
    view->add_option("mesh", viewMeshes, "Meshes to open (Wavefront OBJ); several make one scene");
    // Words that are not a command are meshes to view. CLI11 matches command names first, so
    // `sdfgen bake ...` still runs bake.
    std::vector<std::string> meshes;
    app.add_option("mesh", meshes, "Meshes to open in the viewer (like `sdfgen view MESH...`)");
    try {
        app.parse(argc, argv);
        if (view->parsed()) return sdfgen::app::runViewer(viewMeshes);
        if (app.get_subcommands().empty()) return sdfgen::app::runViewer(meshes);
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
