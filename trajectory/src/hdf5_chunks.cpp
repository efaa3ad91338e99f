#include "hdf5_chunks.hpp"

#include "zlib_chunk.hpp"

#include <fcntl.h>
#include <omp.h>
#include <sys/stat.h>
#include <unistd.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>

#include "owval/base/errors.hpp"
#include "owval/base/mapped_file.hpp"

namespace owval::internal {

// One thread's decoder and buffers: a chunk's stored bytes (when read, not mapped) and its
// inflation. Allocated before a parallel region: an exception must not leave one.
struct ChunkScratch {
  ZlibChunkDecoder decoder;
  std::vector<unsigned char> stored, inflated;
};

namespace {

struct Chunk {
  hsize_t origin[3] = {0, 0, 0};
  haddr_t address = HADDR_UNDEF;  // HADDR_UNDEF: never written, holds the fill value 0
  hsize_t stored_bytes = 0;
  unsigned skipped_filters = 0;  // bit 0: shuffle, bit 1: deflate
};

// A chunk never written holds the dataset's fill value, which owval's readers write as 0: true
// when that is right (no fill value set, or +0 set). Another tool's file may set another.
bool FillsWithZero(hid_t dcpl) {
  H5D_fill_value_t defined = H5D_FILL_VALUE_ERROR;
  if (H5Pfill_value_defined(dcpl, &defined) < 0) return false;
  if (defined != H5D_FILL_VALUE_USER_DEFINED) return defined != H5D_FILL_VALUE_ERROR;
  float fill = 1;
  return H5Pget_fill_value(dcpl, H5T_NATIVE_FLOAT, &fill) >= 0 && fill == 0 && !std::signbit(fill);
}

// The dataset's chunk shape when it is chunked float32 with exactly [shuffle, deflate] and a
// fill value of 0.
std::optional<std::vector<hsize_t>> ShuffleDeflateChunkShape(hid_t file, hid_t set, int rank) {
  const hid_t dcpl = H5Dget_create_plist(set), type = H5Dget_type(set),
              fcpl = H5Fget_create_plist(file);
  std::optional<std::vector<hsize_t>> shape;
  hsize_t userblock = 1;
  std::vector<hsize_t> chunk(static_cast<std::size_t>(rank));
  if (dcpl >= 0 && type >= 0 && fcpl >= 0 && H5Pget_layout(dcpl) == H5D_CHUNKED &&
      H5Pget_chunk(dcpl, rank, chunk.data()) == rank && H5Tequal(type, H5T_IEEE_F32LE) > 0 &&
      H5Pget_userblock(fcpl, &userblock) >= 0 && userblock == 0 && H5Pget_nfilters(dcpl) == 2) {
    unsigned flags = 0, config = 0;
    std::size_t values = 0;
    const H5Z_filter_t first =
        H5Pget_filter2(dcpl, 0, &flags, &values, nullptr, 0, nullptr, &config);
    values = 0;
    const H5Z_filter_t second =
        H5Pget_filter2(dcpl, 1, &flags, &values, nullptr, 0, nullptr, &config);
    if (first == H5Z_FILTER_SHUFFLE && second == H5Z_FILTER_DEFLATE && FillsWithZero(dcpl))
      shape = chunk;
  }
  if (dcpl >= 0) H5Pclose(dcpl);
  if (type >= 0) H5Tclose(type);
  if (fcpl >= 0) H5Pclose(fcpl);
  return shape;
}

// The chunks whose frame origins lie in [first_frame, end_frame), in file order of their origins.
std::vector<Chunk> ListChunks(hid_t set, const std::vector<hsize_t>& dims,
                              const std::vector<hsize_t>& shape, const std::string& path,
                              hsize_t first_frame, hsize_t end_frame) {
  std::vector<Chunk> chunks;
  const std::size_t rank = dims.size();
  hsize_t origin[3] = {first_frame, 0, 0};
  while (origin[0] < end_frame) {
    Chunk c;
    std::copy(origin, origin + rank, c.origin);
    if (H5Dget_chunk_info_by_coord(set, c.origin, &c.skipped_filters, &c.address, &c.stored_bytes) <
        0)
      throw InputError(path, 0, "HDF5: cannot locate a chunk (corrupt chunk index?)");
    chunks.push_back(c);
    std::size_t axis = rank;  // odometer over chunk origins, last axis fastest
    while (axis > 0) {
      --axis;
      origin[axis] += shape[axis];
      if (axis == 0 || origin[axis] < dims[axis]) break;
      origin[axis] = 0;
    }
  }
  return chunks;
}

// Where a decoded chunk's rows go: `rows` rows of `row_values` floats, row r of the chunk to
// out + r·stride (rows past the dataset's end are dropped).
struct Placement {
  float* out;
  std::size_t stride, rows, row_values, chunk_row_values;
};

// `out` holds the dataset from frame `out_first_frame` on.
Placement PlacementOf(const Chunk& c, const std::vector<hsize_t>& dims,
                      const std::vector<hsize_t>& shape, float* out, hsize_t out_first_frame = 0) {
  const hsize_t components = dims.size() == 3 ? dims[2] : 1;
  const hsize_t frames = std::min(shape[0], dims[0] - c.origin[0]);
  const hsize_t particles = std::min(shape[1], dims[1] - c.origin[1]);
  return {out + ((c.origin[0] - out_first_frame) * dims[1] + c.origin[1]) * components,
          dims[1] * components, frames, particles * components, shape[1] * components};
}

// Interleaves 16 elements' bytes from the four byte planes into 64 output bytes.
void Interleave16(const unsigned char* p0, const unsigned char* p1, const unsigned char* p2,
                  const unsigned char* p3, unsigned char* out) {
#if defined(__SSE2__)
  const __m128i b0 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p0));
  const __m128i b1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p1));
  const __m128i b2 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p2));
  const __m128i b3 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p3));
  const __m128i low01 = _mm_unpacklo_epi8(b0, b1), high01 = _mm_unpackhi_epi8(b0, b1);
  const __m128i low23 = _mm_unpacklo_epi8(b2, b3), high23 = _mm_unpackhi_epi8(b2, b3);
  auto* o = reinterpret_cast<__m128i*>(out);
  _mm_storeu_si128(o + 0, _mm_unpacklo_epi16(low01, low23));
  _mm_storeu_si128(o + 1, _mm_unpackhi_epi16(low01, low23));
  _mm_storeu_si128(o + 2, _mm_unpacklo_epi16(high01, high23));
  _mm_storeu_si128(o + 3, _mm_unpackhi_epi16(high01, high23));
#else
  for (int e = 0; e < 16; ++e) {
    out[4 * e + 0] = p0[e];
    out[4 * e + 1] = p1[e];
    out[4 * e + 2] = p2[e];
    out[4 * e + 3] = p3[e];
  }
#endif
}

// Inverse of HDF5's shuffle filter for 4-byte elements (byte b of element e sits at b·n + e),
// written straight to the chunk's place in the output.
void UnshuffleInto(const unsigned char* in, std::size_t n, const Placement& p) {
  const unsigned char *p0 = in, *p1 = in + n, *p2 = in + 2 * n, *p3 = in + 3 * n;
  for (std::size_t r = 0; r < p.rows; ++r) {
    auto* row = reinterpret_cast<unsigned char*>(p.out + r * p.stride);
    const std::size_t first = r * p.chunk_row_values;
    std::size_t v = 0;
    for (; v + 16 <= p.row_values; v += 16) {
      const std::size_t e = first + v;
      Interleave16(p0 + e, p1 + e, p2 + e, p3 + e, row + 4 * v);
    }
    for (; v < p.row_values; ++v) {
      const std::size_t e = first + v;
      row[4 * v + 0] = p0[e];
      row[4 * v + 1] = p1[e];
      row[4 * v + 2] = p2[e];
      row[4 * v + 3] = p3[e];
    }
  }
}

void CopyInto(const unsigned char* in, const Placement& p) {
  for (std::size_t r = 0; r < p.rows; ++r)
    std::memcpy(p.out + r * p.stride, in + r * p.chunk_row_values * sizeof(float),
                p.row_values * sizeof(float));
}

void FillZero(const Placement& place) {
  for (std::size_t r = 0; r < place.rows; ++r)
    std::fill(place.out + r * place.stride, place.out + r * place.stride + place.row_values, 0.0f);
}

// Why a written chunk's stored bytes cannot be where the index says, or empty.
std::string StoredBytesError(const Chunk& c, std::uintmax_t file_bytes) {
  if (c.address > file_bytes || c.stored_bytes > file_bytes - c.address)
    return "HDF5: a chunk lies beyond the end of the file (truncated file)";
  return {};
}

// Decodes a written chunk's `stored` bytes into its place in the output; an error message, or
// empty.
std::string DecodeStoredChunk(const Chunk& c, const unsigned char* stored, std::size_t chunk_bytes,
                              ZlibChunkDecoder* decoder, std::vector<unsigned char>* inflated,
                              const Placement& place) {
  const unsigned char* bytes = stored;
  if (!(c.skipped_filters & 2u)) {
    if (chunk_bytes > c.stored_bytes * kMaxDeflateRatio)
      return "HDF5: a chunk is too small to inflate to its size (corrupt file)";
    inflated->resize(chunk_bytes);
    if (!decoder->Decode(stored, c.stored_bytes, inflated->data(), chunk_bytes))
      return "HDF5: a chunk does not inflate to its size (corrupt file)";
    bytes = inflated->data();
  } else if (c.stored_bytes != chunk_bytes) {
    return "HDF5: an unfiltered chunk has the wrong size (corrupt file)";
  }
  if (c.skipped_filters & 1u) {
    CopyInto(bytes, place);
  } else {
    UnshuffleInto(bytes, chunk_bytes / sizeof(float), place);
  }
  return {};
}

std::size_t ChunkBytes(const std::vector<hsize_t>& shape) {
  std::size_t bytes = sizeof(float);
  for (hsize_t d : shape) bytes *= d;
  return bytes;
}

// The chunk shape when ReadDeflatedChunksInParallel and DeflatedChunkRows can read the dataset:
// rank 2 or 3, shuffle and deflate, whole components per chunk (the placement a row copy).
std::optional<std::vector<hsize_t>> ReadableChunkShape(hid_t file, hid_t set,
                                                       const std::vector<hsize_t>& dims) {
  const int rank = int(dims.size());
  if (rank < 2 || rank > 3) return std::nullopt;
  auto shape = ShuffleDeflateChunkShape(file, set, rank);
  if (!shape || (rank == 3 && (*shape)[2] != dims[2])) return std::nullopt;
  return shape;
}

std::vector<std::unique_ptr<ChunkScratch>> ScratchPerThread() {
  std::vector<std::unique_ptr<ChunkScratch>> scratch(
      static_cast<std::size_t>(std::max(1, omp_get_max_threads())));
  for (auto& s : scratch) s = std::make_unique<ChunkScratch>();
  return scratch;
}

// Decodes `chunks` into their places (`place_of(chunk)`) on all cores, thread t with scratch[t]
// (no more threads than the caller allows now: owval run --threads). A chunk never written holds
// the fill value, 0; a written one's stored bytes are checked against the file's size, then
// `stored_of(chunk, scratch, &bytes)` points `bytes` at them or says why it cannot. Returns the
// first error, or empty.
template <typename PlaceOf, typename StoredOf>
std::string DecodeChunks(const std::vector<Chunk>& chunks, std::size_t chunk_bytes,
                         std::uintmax_t file_bytes,
                         const std::vector<std::unique_ptr<ChunkScratch>>& scratch,
                         const PlaceOf& place_of, const StoredOf& stored_of) {
  std::string error;
  const int threads = std::min(int(scratch.size()), omp_get_max_threads());
#pragma omp parallel num_threads(threads) if (chunks.size() > 1)
  {
    ChunkScratch& s = *scratch[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 1)
    for (std::size_t n = 0; n < chunks.size(); ++n) {
      const Chunk& c = chunks[n];
      const Placement place = place_of(c);
      std::string failure;
      const unsigned char* stored = nullptr;
      if (c.address == HADDR_UNDEF) {
        FillZero(place);
      } else if ((failure = StoredBytesError(c, file_bytes)).empty() &&
                 (failure = stored_of(c, s, &stored)).empty()) {
        failure = DecodeStoredChunk(c, stored, chunk_bytes, &s.decoder, &s.inflated, place);
      }
      if (!failure.empty()) {
#pragma omp critical(owval_hdf5_chunk_error)
        if (error.empty()) error = failure;
      }
    }
  }
  return error;
}

}  // namespace

bool ReadDeflatedChunksInParallel(hid_t file, hid_t set, FileBytes* file_bytes,
                                  const std::vector<hsize_t>& dims, float* out) {
  const std::string& path = file_bytes->path();
  const auto shape = ReadableChunkShape(file, set, dims);
  if (!shape) return false;
  const std::vector<Chunk> chunks = ListChunks(set, dims, *shape, path, 0, dims[0]);
  if (!out) return true;  // a dry run: the chunk index walked, nothing decoded
  const std::string_view bytes = file_bytes->bytes();
  const std::string error = DecodeChunks(
      chunks, ChunkBytes(*shape), bytes.size(), ScratchPerThread(),
      [&](const Chunk& c) { return PlacementOf(c, dims, *shape, out); },
      [&](const Chunk& c, ChunkScratch&, const unsigned char** stored) {
        *stored = reinterpret_cast<const unsigned char*>(bytes.data() + c.address);
        return std::string();
      });
  if (!error.empty()) throw InputError(path, 0, error);
  return true;
}

std::unique_ptr<DeflatedChunkRows> DeflatedChunkRows::Open(hid_t file, hid_t set,
                                                           const std::string& path,
                                                           const std::vector<hsize_t>& dims) {
  std::optional<std::vector<hsize_t>> shape = ReadableChunkShape(file, set, dims);
  if (!shape) return nullptr;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  struct stat status {};
  if (fd < 0 || ::fstat(fd, &status) != 0) {
    if (fd >= 0) ::close(fd);
    throw InputError(path, 0, "cannot open the file to read its chunks");
  }
  return std::unique_ptr<DeflatedChunkRows>(new DeflatedChunkRows(
      set, path, dims, std::move(*shape), fd, std::uintmax_t(status.st_size)));
}

DeflatedChunkRows::DeflatedChunkRows(hid_t set, std::string path, std::vector<hsize_t> dims,
                                     std::vector<hsize_t> shape, int fd, std::uintmax_t file_bytes)
    : set_(set),
      path_(std::move(path)),
      dims_(std::move(dims)),
      shape_(std::move(shape)),
      fd_(fd),
      file_bytes_(file_bytes),
      scratch_(ScratchPerThread()) {}

DeflatedChunkRows::~DeflatedChunkRows() { ::close(fd_); }

namespace {

// Reads a written chunk's stored bytes (within the file) into `stored`; an error message, or
// empty. A chunk's zlib stream is at most a little longer than what it holds (deflate's stored
// blocks: 5 bytes a 64 KiB, 6 of zlib's own), so a larger stored size is refused before a buffer
// is sized from it.
std::string ReadStoredBytes(int fd, const Chunk& c, std::size_t chunk_bytes,
                            std::vector<unsigned char>* stored) {
  if (c.stored_bytes > chunk_bytes + chunk_bytes / 1024 + 64)
    return "HDF5: a chunk is stored in more bytes than it can take (corrupt file)";
  stored->resize(c.stored_bytes);
  std::size_t done = 0;
  while (done < c.stored_bytes) {
    const ssize_t got =
        ::pread(fd, stored->data() + done, c.stored_bytes - done, off_t(c.address + done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return "HDF5: cannot read a chunk's bytes (truncated file?)";
    done += std::size_t(got);
  }
  return {};
}

}  // namespace

void DeflatedChunkRows::Read(std::size_t first, float* out) {
  const std::vector<Chunk> chunks =
      ListChunks(set_, dims_, shape_, path_, first, std::min<hsize_t>(first + 1, dims_[0]));
  const std::size_t chunk_bytes = ChunkBytes(shape_);
  const std::string error = DecodeChunks(
      chunks, chunk_bytes, file_bytes_, scratch_,
      [&](const Chunk& c) { return PlacementOf(c, dims_, shape_, out, first); },
      [&](const Chunk& c, ChunkScratch& s, const unsigned char** stored) {
        std::string failure = ReadStoredBytes(fd_, c, chunk_bytes, &s.stored);
        *stored = s.stored.data();
        return failure;
      });
  if (error.empty()) return;
  const std::string_view reason =
      std::string_view(error).substr(error.rfind("HDF5: ", 0) == 0 ? 6 : 0);
  throw InputError(path_, 0,
                   "HDF5: cannot read frame " + std::to_string(first) + ": " + std::string(reason));
}

}  // namespace owval::internal
