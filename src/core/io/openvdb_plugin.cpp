#include "core/io/openvdb_plugin.hpp"
#include "core/io/formats/format.hpp"
#include "core/runtime/plugin.hpp"
#include "sdfgen/error.hpp"

#include <mutex>

namespace sdfgen {

namespace {
// A build configured with SDFGEN_OPENVDB=OFF has no libsdfgen_openvdb.so to open.
const std::string kBuiltWithout = "this sdfgen was built without OpenVDB (configure with -DSDFGEN_OPENVDB=ON)";
} // namespace

const OpenVdbPlugin& openVdbPlugin() {
    if (!SDFGEN_HAS_OPENVDB) throw Error("iso-surfaces need OpenVDB, and " + kBuiltWithout);
    // Kept once opened; a failure is reported again by the next call, which tries again.
    static std::mutex mutex;
    static const OpenVdbPlugin* plugin = nullptr;
    const std::lock_guard<std::mutex> lock(mutex);
    if (!plugin) {
        plugin = reinterpret_cast<OpenVdbPluginEntry>(openPlugin("libsdfgen_openvdb.so", kOpenVdbPluginEntry, "OpenVDB support"))();
    }
    return *plugin;
}

namespace formats {

namespace {

void saveVdb(const Field& field, const std::string& path, const SaveOptions& options) {
    if (!SDFGEN_HAS_OPENVDB) throw Error(path + ": .vdb files need OpenVDB, and " + kBuiltWithout);
    openVdbPlugin().save(field, path, options);
}

AnyField loadVdb(const std::string& path, const RunControl& control) {
    if (!SDFGEN_HAS_OPENVDB) throw Error(path + ": .vdb files need OpenVDB, and " + kBuiltWithout);
    return openVdbPlugin().load(path, control);
}

void saveSparseVdb(const SparseField& field, const std::string& path) {
    if (!SDFGEN_HAS_OPENVDB) throw Error(path + ": .vdb files need OpenVDB, and " + kBuiltWithout);
    openVdbPlugin().saveSparse(field, path);
}

void saveSparseVdbGivenUp(SparseField&& field, const std::string& path) {
    if (!SDFGEN_HAS_OPENVDB) throw Error(path + ": .vdb files need OpenVDB, and " + kBuiltWithout);
    openVdbPlugin().saveSparseGivenUp(std::move(field), path);
}

} // namespace

FieldFormat vdbFormat() {
    return {".vdb", "OpenVDB FloatGrid 'surface', level set class, and any channels as grids of their names", true, saveVdb, loadVdb,
            saveSparseVdb, saveSparseVdbGivenUp};
}

} // namespace formats

} // namespace sdfgen
