#pragma once
// How much memory this process can have: what every front end checks before a large allocation
// (a bake, a field loaded, undo history) and quotes when it refuses one.
#include <cstdint>
#include <string>

namespace sdfgen {

// Bytes of physical memory on this machine (0 when unknown).
std::uint64_t physicalMemoryBytes();

// Bytes this process may use at most: the physical memory, or less under a cgroup limit (0 when
// nothing is known).
std::uint64_t usableMemoryBytes();

// Bytes this process can still take: MemAvailable from /proc/meminfo, lowered to the room left
// under its cgroups' memory limits; the physical memory when neither is readable (0 when nothing
// is known).
std::uint64_t availableMemoryBytes();

// "123 MiB", rounded, for messages.
std::string mebibytes(double bytes);

} // namespace sdfgen
