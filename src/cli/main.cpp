// sdfgen command line: a thin front end over the core library. With no command, or `view`, it
// opens the viewer window.
#include "app/viewer.hpp"
#include "cli/commands.hpp"
#include "gpu/gl_device.hpp"
#include "sdfgen/error.hpp"

#include <cstdio>

int main(int argc, char** argv) {
    CLI::App app{"sdfgen: signed distance fields from triangle meshes. With no command, opens the viewer."};
    app.require_subcommand(0, 1);
    sdfgen::cli::addBakeCommand(app);
    sdfgen::cli::addBenchCommand(app);
    sdfgen::cli::addCompareCommand(app);
    sdfgen::cli::addRenderCommand(app);
    sdfgen::cli::addInfoCommand(app);
    sdfgen::gpu::registerGlDevice();
    std::string viewMesh;
    CLI::App* view = app.add_subcommand("view", "Open the viewer window (the default when no command is given)");
    view->add_option("mesh", viewMesh, "Mesh to open (Wavefront OBJ)");
    try {
        app.parse(argc, argv);
        if (app.get_subcommands().empty() || view->parsed()) return sdfgen::app::runViewer(viewMesh);
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
