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

DeflatedChunkWriter::DeflatedChunkWriter(std::size_t frames_per_chunk,
                                         std::size_t particles_per_chunk, int level, int threads)
    : frames_per_chunk_(frames_per_chunk),
      particles_per_chunk_(particles_per_chunk),
      threads_(static_cast<std::size_t>(threads > 0 ? threads : omp_get_max_threads())) {
  for (Thread& t : threads_) t.encoder = std::make_unique<ZlibChunkEncoder>(level);
}

DeflatedChunkWriter::~DeflatedChunkWriter() = default;

bool DeflatedChunkWriter::Write(const std::vector<FloatFrames>& sets, hsize_t first_frame,
                                std::size_t frames) {
  std::vector<ChunkJob> jobs;
  for (const FloatFrames& s : sets)
    for (std::size_t p = 0; p < s.particles; p += particles_per_chunk_) jobs.push_back({&s, p});
  // Rounds of one chunk per thread: deflated in parallel, stored in order by this thread
  // (libhdf5 is called from one thread only: its error reporting is not per thread).
  const std::size_t round = threads_.size();
  for (std::size_t first = 0; first < jobs.size(); first += round) {
    const std::size_t n = std::min(round, jobs.size() - first);
    const int team = static_cast<int>(n);
#pragma omp parallel for schedule(static, 1) num_threads(team) if (n > 1)
    for (std::size_t r = 0; r < n; ++r) {
      const ChunkJob& job = jobs[first + r];
      Thread& t = threads_[r];
      ShuffleChunk(job, frames, frames_per_chunk_,
                   std::min(particles_per_chunk_, job.set->particles), &t.shuffled);
      t.encoder->Encode(t.shuffled.data(), t.shuffled.size(), &t.stored);
    }
    for (std::size_t r = 0; r < n; ++r) {
      const hsize_t offset[3] = {first_frame, hsize_t(jobs[first + r].first_particle), 0};
      if (H5Dwrite_chunk(jobs[first + r].set->set, H5P_DEFAULT, 0, offset,
                         threads_[r].stored.size(), threads_[r].stored.data()) < 0)
        return false;
    }
  }
  return true;
}

}  // namespace owval::internal
