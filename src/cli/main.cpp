// sdfgen command line: a thin front end over the core library. With no command, or `view`, it
// opens the viewer window (in builds with the viewer, SDFGEN_HAS_VIEWER); `sdfgen MESH...` (what a
// file manager's "open with" runs) opens it on those meshes.
#if SDFGEN_HAS_VIEWER
#include "app/viewer.hpp"
#include "gpu/devices.hpp"
#endif
#include "cli/commands.hpp"
#include "sdfgen/error.hpp"

#include <cstdio>
#include <new>
#include <string>
#include <vector>

int main(int argc, char** argv) {
#if SDFGEN_HAS_VIEWER
    sdfgen::gpu::registerDevices(); // first: the commands' options list them
#endif
    CLI::App app{"sdfgen: signed distance fields from triangle meshes. With no command, opens the viewer."};
    app.require_subcommand(0, 1);
    sdfgen::cli::addBakeCommand(app);
    sdfgen::cli::addBenchCommand(app);
    sdfgen::cli::addCompareCommand(app);
    sdfgen::cli::addSurfaceCommand(app);
    sdfgen::cli::addQueryCommand(app);
    sdfgen::cli::addSampleCommand(app);
    int exitCode = 0;
    sdfgen::cli::addBatchCommand(app, exitCode);
    sdfgen::cli::addInfoCommand(app);
#if SDFGEN_HAS_VIEWER
    sdfgen::cli::addRenderCommand(app);
    std::vector<std::string> viewMeshes;
    CLI::App* view = app.add_subcommand("view", "Open the viewer window (the default when no command is given)");
    view->add_option("mesh", viewMeshes, "Meshes (" + sdfgen::cli::meshFormatList() + ", ...; several make one scene) and fields (" + sdfgen::cli::fieldFormatList() + ") to open");
    // Words that are not a command are meshes to view. CLI11 matches command names first, so
    // `sdfgen bake ...` still runs bake.
    std::vector<std::string> meshes;
    app.add_option("mesh", meshes, "Meshes and fields to open in the viewer (like `sdfgen view FILE...`)");
#else
    app.footer("This sdfgen was built without the viewer (-DSDFGEN_VIEWER=OFF): no view or render command.");
#endif
    try {
        app.parse(argc, argv);
#if SDFGEN_HAS_VIEWER
        if (view->parsed()) return sdfgen::app::runViewer(viewMeshes);
        if (app.get_subcommands().empty()) return sdfgen::app::runViewer(meshes);
#else
        if (app.get_subcommands().empty()) {
            std::fputs(app.help().c_str(), stderr);
            return 1;
        }
#endif
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "sdfgen: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        // The bake checks its memory up front; this is the last resort for anything it missed.
        std::fprintf(stderr, "sdfgen: out of memory (try a lower --res, or free memory)\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sdfgen: internal error: %s\n", e.what());
        return 2;
    }
    return exitCode;
}
