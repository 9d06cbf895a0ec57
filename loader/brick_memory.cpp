#include "loader/brick_memory.h"

#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <new>
#include <unordered_map>
#include <vector>

namespace ropecast::brick_memory {

namespace {

constexpr size_t kChunkBytes = size_t(32) << 20;
constexpr size_t kHugePageBytes = size_t(2) << 20;
constexpr size_t kBlockAlignment = 64;

constexpr size_t roundUp(size_t value, size_t multiple) {
  return (value + multiple - 1) / multiple * multiple;
}

// `bytes` (a multiple of kHugePageBytes) of anonymous memory starting on a huge page boundary, advised to be
// backed by huge pages.
std::byte* mapChunk(size_t bytes) {
  const size_t mapped = bytes + kHugePageBytes;
  void* p = ::mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  const uintptr_t start = reinterpret_cast<uintptr_t>(p);
  const uintptr_t aligned = roundUp(start, kHugePageBytes);
  if (aligned > start) ::munmap(p, aligned - start);
  const uintptr_t end = start + mapped;
  if (end > aligned + bytes) ::munmap(reinterpret_cast<void*>(aligned + bytes), end - (aligned + bytes));
  std::byte* chunk = reinterpret_cast<std::byte*>(aligned);
#ifdef MADV_HUGEPAGE
  ::madvise(chunk, bytes, MADV_HUGEPAGE);  // a hint: without huge pages the chunk works all the same
#endif
  return chunk;
}

struct Chunk {
  std::byte* start = nullptr;
  size_t bytes = 0;
};

struct SizeClass {
  std::vector<void*> free;  // blocks given back, taken first
  std::byte* next = nullptr;
  std::byte* end = nullptr;  // the rest of the current chunk: [next, end)
  std::vector<Chunk> chunks;
  size_t live = 0;  // blocks handed out and not given back
};

class Blocks {
 public:
  void* allocate(size_t block) {
    std::lock_guard lock(mutex_);
    SizeClass& c = classes_[block];
    if (!c.free.empty()) {
      void* p = c.free.back();
      c.free.pop_back();
      ++c.live;
      return p;
    }
    if (size_t(c.end - c.next) < block) {
      const size_t bytes = std::max(kChunkBytes, roundUp(block, kHugePageBytes));
      c.chunks.reserve(c.chunks.size() + 1);  // before mapping: nothing to undo if this throws
      c.next = mapChunk(bytes);
      c.end = c.next + bytes;
      c.chunks.push_back({c.next, bytes});
      ++mapped_;
    }
    void* p = c.next;
    c.next += block;
    ++c.live;
    return p;
  }

  // The last block of a size given back returns that size's chunks to the system: a renderer that ends (a
  // regression case of `regress`) leaves no memory to sizes no later one may use.
  void deallocate(void* p, size_t block) noexcept {
    std::lock_guard lock(mutex_);
    const auto it = classes_.find(block);
    if (it == classes_.end()) return;  // not a block of ours: cannot happen
    SizeClass& c = it->second;
    if (--c.live == 0) {
      for (const Chunk& chunk : c.chunks) ::munmap(chunk.start, chunk.bytes);
      mapped_ -= c.chunks.size();
      classes_.erase(it);
      return;
    }
    try {
      c.free.push_back(p);
    } catch (...) {
      // No memory for the free list's growth: the block is lost to reuse until its chunks are returned.
    }
  }

  size_t mappedChunks() {
    std::lock_guard lock(mutex_);
    return mapped_;
  }

 private:
  std::mutex mutex_;
  std::unordered_map<size_t, SizeClass> classes_;
  size_t mapped_ = 0;
};

// Never destroyed: bricks may be freed by static destructors after any function-local static would be.
Blocks& blocks() {
  static Blocks* const instance = new Blocks();
  return *instance;
}

bool fromOperatorNew(size_t bytes) {
  return !kChunked || bytes < kMinBlockBytes;
}

}  // namespace

void* allocate(size_t bytes) {
  if (fromOperatorNew(bytes)) return ::operator new(bytes, std::align_val_t(kBlockAlignment));
  return blocks().allocate(roundUp(bytes, kBlockAlignment));
}

void deallocate(void* block, size_t bytes) noexcept {
  if (!block) return;
  if (fromOperatorNew(bytes)) {
    ::operator delete(block, std::align_val_t(kBlockAlignment));
    return;
  }
  blocks().deallocate(block, roundUp(bytes, kBlockAlignment));
}

size_t mappedChunks() {
  return blocks().mappedChunks();
}

}  // namespace ropecast::brick_memory
