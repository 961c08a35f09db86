#pragma once
// Out of memory, named: the entry points that read, write or bake a file run their work through
// this, so that an allocation that fails (what the up-front memory checks missed) gives one line
// naming the file, as every other error does, rather than a bare "out of memory".
#include "sdfgen/error.hpp"

#include <new>
#include <string>
#include <utility>

namespace sdfgen {

// work(); a std::bad_alloc from it becomes OutOfMemoryError("PATH: out of memory while DOING").
template <class Work>
decltype(auto) namingOutOfMemory(const std::string& path, const char* doing, Work&& work) {
    try {
        return std::forward<Work>(work)();
    } catch (const std::bad_alloc&) {
        throw OutOfMemoryError(path + ": out of memory while " + doing);
    }
}

} // namespace sdfgen
