// Large blocks on transparent huge pages, for this executable's allocations (the library's
// included: operator new is the program's). Where the kernel gives huge pages only to memory that
// asks (transparent_hugepage "madvise", the default of many distributions), every 4 KiB page of a
// field, a tree or a band's bricks faults on its first touch, and on a virtual machine each fault
// is dear: 10-20% of a bake (docs/benchmarks.md). Blocks from kHugeFrom up (which glibc maps on
// their own: its mmap threshold is 32 MiB at most) are aligned to 2 MiB and marked
// MADV_HUGEPAGE before anything touches them: a 2 MiB page then faults once. Smaller blocks stay
// as they were: the sign's blocks of 4-32 MiB, reused from the heap, were slower as pages of
// their own. glibc's tunable glibc.malloc.hugetlb=1 does the like for every block, but only when
// set before the process starts. Left out under the sanitizers, which replace operator new.
#include <cstdlib> // defines __GLIBC__

// GCC names the sanitizers by macros, clang by __has_feature.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SDFGEN_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define SDFGEN_SANITIZED 1
#endif
#endif

#if !defined(SDFGEN_SANITIZED) && defined(__GLIBC__)
#include <sys/mman.h>

#include <cstddef>
#include <new>

namespace {

constexpr std::size_t kHugePage = std::size_t(2) << 20, kHugeFrom = 16 * kHugePage;

void* tryAllocate(std::size_t size, std::size_t alignment) {
    if (size < kHugeFrom) {
        // aligned_alloc wants a multiple of the alignment (operator new's default one: malloc's).
        return alignment <= alignof(std::max_align_t) ? std::malloc(size ? size : 1)
                                                       : std::aligned_alloc(alignment, (size + alignment - 1) & ~(alignment - 1));
    }
    // Whole huge pages from the block's first byte (free() takes what aligned_alloc gives).
    alignment = alignment > kHugePage ? alignment : kHugePage;
    const std::size_t rounded = (size + alignment - 1) & ~(alignment - 1);
    void* block = rounded >= size ? std::aligned_alloc(alignment, rounded) : nullptr;
    if (block) madvise(block, rounded, MADV_HUGEPAGE); // a hint: ignored where refused
    return block;
}

// As the standard's operator new: the new-handler, if any, is called until the block is found.
void* allocate(std::size_t size, std::size_t alignment) {
    for (;;) {
        if (void* block = tryAllocate(size, alignment)) return block;
        const std::new_handler handler = std::get_new_handler();
        if (!handler) throw std::bad_alloc();
        handler();
    }
}

} // namespace

// The plain and aligned forms (SIMD packets are over-aligned); libstdc++'s nothrow forms call
// these, and its operator delete frees what malloc and aligned_alloc gave.
void* operator new(std::size_t size) { return allocate(size, alignof(std::max_align_t)); }
void* operator new[](std::size_t size) { return allocate(size, alignof(std::max_align_t)); }
void* operator new(std::size_t size, std::align_val_t alignment) { return allocate(size, std::size_t(alignment)); }
void* operator new[](std::size_t size, std::align_val_t alignment) { return allocate(size, std::size_t(alignment)); }
#endif
