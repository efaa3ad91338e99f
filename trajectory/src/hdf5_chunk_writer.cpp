#include "hdf5_chunk_writer.hpp"

#include <omp.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "zlib_chunk.hpp"

namespace owval::internal {
namespace {

struct ChunkJob {
  const FloatFrames* set;
  std::size_t first_particle;
  std::vector<unsigned char> stored;  // the deflated chunk
};

// HDF5's shuffle filter for 4-byte elements (byte b of element e at b·n + e) over the chunk's n
// elements, gathered from the frames: element (frame a, particle p, component c) of the chunk is
// (a·P + p)·C + c with P the chunk's particle extent; cells past the data are 0.
void ShuffleChunk(const ChunkJob& job, std::size_t frames, std::size_t frames_per_chunk,
                  std::size_t chunk_particles, std::vector<unsigned char>* out) {
  const FloatFrames& s = *job.set;
  const std::size_t row = chunk_particles * s.components;  // elements per chunk frame
  const std::size_t n = frames_per_chunk * row;
  out->assign(4 * n, 0);
  const std::size_t particles = std::min(chunk_particles, s.particles - job.first_particle);
  const std::size_t values = particles * s.components;
  for (std::size_t a = 0; a < frames; ++a) {
    const auto* in = reinterpret_cast<const unsigned char*>(
        s.values + a * s.particles * s.components + job.first_particle * s.components);
    const std::size_t e0 = a * row;
    for (std::size_t v = 0; v < values; ++v)
      for (std::size_t b = 0; b < 4; ++b) (*out)[b * n + e0 + v] = in[4 * v + b];
  }
}

}  // namespace

bool WriteDeflatedChunks(const std::vector<FloatFrames>& sets, hsize_t first_frame,
                         std::size_t frames, std::size_t frames_per_chunk,
                         std::size_t particles_per_chunk, int level) {
  std::vector<ChunkJob> jobs;
  for (const FloatFrames& s : sets)
    for (std::size_t p = 0; p < s.particles; p += particles_per_chunk) jobs.push_back({&s, p, {}});
  const std::size_t chunk_particles_max = particles_per_chunk;
  // Allocated here: an exception must not leave a parallel region.
  std::vector<std::unique_ptr<ZlibChunkEncoder>> encoders(
      static_cast<std::size_t>(omp_get_max_threads()));
  for (auto& e : encoders) e = std::make_unique<ZlibChunkEncoder>(level);
#pragma omp parallel if (jobs.size() > 1)
  {
    std::vector<unsigned char> shuffled;
    ZlibChunkEncoder& encoder = *encoders[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic)
    for (std::size_t j = 0; j < jobs.size(); ++j) {
      const std::size_t chunk_particles = std::min(chunk_particles_max, jobs[j].set->particles);
      ShuffleChunk(jobs[j], frames, frames_per_chunk, chunk_particles, &shuffled);
      encoder.Encode(shuffled.data(), shuffled.size(), &jobs[j].stored);
    }
  }
  for (const ChunkJob& job : jobs) {
    const hsize_t offset[3] = {first_frame, hsize_t(job.first_particle), 0};
    if (H5Dwrite_chunk(job.set->set, H5P_DEFAULT, 0, offset, job.stored.size(), job.stored.data()) <
        0)
      return false;
  }
  return true;
}

}  // namespace owval::internal
