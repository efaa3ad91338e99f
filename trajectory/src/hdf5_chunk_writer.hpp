#pragma once
// The writing twin of hdf5_chunks.hpp: frames of owval's float datasets (chunked, [shuffle,
// deflate]) shuffled and deflated here, on all cores, and stored with H5Dwrite_chunk. The stored
// bytes are what HDF5's own filter pipeline would decode (any HDF5 reader sees an ordinary
// dataset); HDF5 itself would deflate one chunk at a time, on one core, with zlib.
#include <hdf5.h>

#include <cstddef>
#include <memory>
#include <vector>

namespace owval::internal {

class ZlibChunkEncoder;

// One dataset [frames, particles(, components)] with chunks {frames_per_chunk,
// particles_per_chunk(, components)}, and the frames to store in it, frame after frame.
struct FloatFrames {
  hid_t set;
  const float* values;
  std::size_t particles, components;
};

class DeflatedChunkWriter {
 public:
  // threads: how many deflate chunks at once (0: OpenMP's maximum).
  DeflatedChunkWriter(std::size_t frames_per_chunk, std::size_t particles_per_chunk, int level,
                      int threads);
  ~DeflatedChunkWriter();

  // Stores `frames` frames (at most frames_per_chunk) at frame `first_frame` (a multiple of
  // frames_per_chunk) of each dataset, already extended to hold them; chunk cells past the
  // dataset's end are written as 0, the fill value. Chunks are stored in dataset and particle
  // order by the calling thread (the file's bytes do not depend on the threads). Each thread's
  // encoder and buffers are kept from call to call: a run's memory does not grow with its flushes.
  // False when HDF5 refuses a chunk.
  bool Write(const std::vector<FloatFrames>& sets, hsize_t first_frame, std::size_t frames);

 private:
  struct Thread {
    std::unique_ptr<ZlibChunkEncoder> encoder;
    std::vector<unsigned char> shuffled, stored;
  };
  std::size_t frames_per_chunk_, particles_per_chunk_;
  std::vector<Thread> threads_;
};

}  // namespace owval::internal
