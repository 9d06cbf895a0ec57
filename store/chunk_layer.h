// ChunkLayer: the slices of a chunked source (Zarr, HDF5) held decoded, a layer of chunks at a time. The
// chunks whose z range reaches the layer are decoded on worker threads (runOnWorkers), each placing its box
// of samples into the layer, so that a slab costs one decode per chunk however thin it is. A layer deeper
// than the bytes allowed is held in bands of slices, its chunks decoded again for each band.
//
// Threads: read(), begin() and decodeLayer() from the source's reading thread; place() from the workers at
// once, each for boxes of its own.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include <glm/vec3.hpp>

#include "core/error.h"
#include "core/sample_type.h"

namespace ropecast {

class ChunkLayer {
 public:
  // A volume of `dims` samples of `type` whose chunks are `chunkDepth` slices deep; at most `maxBytes` of
  // slices held (one slice at least).
  ChunkLayer(glm::u32vec3 dims, SampleType type, uint64_t chunkDepth, uint64_t maxBytes);

  // Copies slices [z0, z0 + count) into `out` (count slices), calling `decode` whenever a slice is not held:
  // it is to begin() the slices from that one on and place() every chunk that reaches them.
  void read(uint32_t z0, uint32_t count, std::span<std::byte> out,
            const std::function<void(uint64_t z)>& decode);

  // Makes room for the slices from `z` on that one decode holds: the rest of z's chunk layer, or as much as
  // the bytes allowed hold. Returns the chunk layer's index.
  uint64_t begin(uint64_t z);
  // Forgets the slices held (a decode that failed).
  void clear() { begin_ = end_ = 0; }

  // Whether a box starting at slice `z`, `depth` slices deep, reaches into the slices held.
  bool reaches(uint64_t z, uint64_t depth) const { return z < end_ && z + depth > begin_; }

  // Decodes the slices from slice `z` on that one decode holds (begin(z)): task(layer, row, column, state)
  // for each chunk of z's chunk layer, chunks `chunkX` by `chunkY` samples, on worker threads (runOnWorkers,
  // below).
  template <typename State>
  void decodeLayer(uint64_t z, uint64_t chunkX, uint64_t chunkY,
                   const std::function<std::string(uint64_t, uint64_t, uint64_t, State&)>& task);

  // Copies a decoded box of samples whose first sample lies at `origin` of the volume (`stride`: samples
  // between neighbours along x, y and z within the box) into the slices held: its part inside the volume and
  // among them.
  void place(const std::byte* samples, glm::u64vec3 stride, glm::u64vec3 origin, glm::u64vec3 box);

 private:
  glm::u64vec3 dims_;
  size_t sampleBytes_, sliceBytes_;
  uint64_t chunkDepth_, fits_;
  uint64_t begin_ = 0, end_ = 0;  // the slices held in buffer_
  std::vector<std::byte> buffer_;
};

// Runs task(i, state) for i in [0, tasks) on one thread per core (at most one per task), each thread with a
// State of its own (buffers kept from task to task). A task returns its problem ("" for none); the first
// problem met, or an exception's message, is thrown as ropecast::Error once every thread has stopped.
template <typename State>
void runOnWorkers(uint64_t tasks, const std::function<std::string(uint64_t, State&)>& task) {
  if (tasks == 0) return;
  const unsigned workers = unsigned(std::clamp<uint64_t>(std::thread::hardware_concurrency(), 1, tasks));
  std::vector<std::string> problems(workers);
  {
    std::vector<std::jthread> threads;
    for (unsigned w = 0; w < workers; ++w)
      threads.emplace_back([&, w] {
        State state;
        try {
          for (uint64_t i = w; i < tasks && problems[w].empty(); i += workers) problems[w] = task(i, state);
        } catch (const std::exception& e) {  // out of memory: the reading thread hears of it
          problems[w] = e.what();
        }
      });
  }
  for (const std::string& problem : problems)
    if (!problem.empty()) throw Error(problem);
}

template <typename State>
void ChunkLayer::decodeLayer(uint64_t z, uint64_t chunkX, uint64_t chunkY,
                             const std::function<std::string(uint64_t, uint64_t, uint64_t, State&)>& task) {
  const uint64_t layer = begin(z);
  const uint64_t across = (dims_.x + chunkX - 1) / chunkX, down = (dims_.y + chunkY - 1) / chunkY;
  runOnWorkers<State>(across * down,
                      [&](uint64_t i, State& state) { return task(layer, i / across, i % across, state); });
}

}  // namespace ropecast
