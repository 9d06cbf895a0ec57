// BrickMemory: where decompressed bricks live. Blocks of one size are carved from chunks of 32 MiB that the
// kernel may back with transparent huge pages (madvise MADV_HUGEPAGE; Linux's "madvise" mode, the default of
// many distributions, gives them only to memory that asks): filling a cold CPU cache then takes a page fault
// per 2 MiB rather than one per 4 KiB. A freed block is kept for the next brick of its size, and a size's
// chunks go back to the system when its last block is freed: while bricks of a size live, the memory held for
// them is the most they took at once.
// Blocks under kMinBlockBytes (the bricks of small test volumes) come from operator new. Under
// AddressSanitizer every block does, so that it still sees a brick used after it was freed.
//
// Thread-safe: the I/O workers allocate, the render thread frees (or whichever thread drops a brick last).
#pragma once

#include <cstddef>

#if defined(__SANITIZE_ADDRESS__)
#define ROPECAST_BRICKS_FROM_OPERATOR_NEW 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ROPECAST_BRICKS_FROM_OPERATOR_NEW 1
#endif
#endif

namespace ropecast::brick_memory {

inline constexpr size_t kMinBlockBytes = size_t(16) << 10;
#ifdef ROPECAST_BRICKS_FROM_OPERATOR_NEW
inline constexpr bool kChunked = false;  // AddressSanitizer: every block from operator new
#else
inline constexpr bool kChunked = true;
#endif

// At least `bytes`, aligned to 64 bytes. Throws std::bad_alloc when the system has no memory left.
void* allocate(size_t bytes);
// `bytes` as given to the allocate() that returned `block`.
void deallocate(void* block, size_t bytes) noexcept;

// Chunks mapped now (for tests).
size_t mappedChunks();

}  // namespace ropecast::brick_memory
