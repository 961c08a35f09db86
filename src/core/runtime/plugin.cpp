#include "core/runtime/plugin.hpp"
#include "sdfgen/error.hpp"

#include <dlfcn.h>

namespace sdfgen {

void* openPlugin(const std::string& library, const char* entry, const std::string& what) {
    std::string beside;
    Dl_info self{};
    if (dladdr(reinterpret_cast<void*>(&openPlugin), &self) != 0 && self.dli_fname) {
        const std::string where = self.dli_fname;
        const std::size_t slash = where.rfind('/');
        if (slash != std::string::npos) beside = where.substr(0, slash + 1) + library;
    }
    void* handle = beside.empty() ? nullptr : dlopen(beside.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) handle = dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* why = dlerror();
        throw Error(what + " (" + library + ") cannot be loaded: " + (why ? why : "not found"));
    }
    void* symbol = dlsym(handle, entry);
    if (!symbol) throw Error(library + " has no entry point " + entry);
    return symbol;
}

} // namespace sdfgen
