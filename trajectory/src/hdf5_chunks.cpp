#include "hdf5_chunks.hpp"

#include "zlib_chunk.hpp"

#include <omp.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>

#include "owval/base/errors.hpp"
#include "owval/base/mapped_file.hpp"

namespace owval::internal {
namespace {

struct Chunk {
  hsize_t origin[3] = {0, 0, 0};
  haddr_t address = HADDR_UNDEF;  // HADDR_UNDEF: never written, holds the fill value 0
  hsize_t stored_bytes = 0;
  unsigned skipped_filters = 0;  // bit 0: shuffle, bit 1: deflate
};

// The dataset's chunk shape when it is chunked float32 with exactly [shuffle, deflate].
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
    if (first == H5Z_FILTER_SHUFFLE && second == H5Z_FILTER_DEFLATE) shape = chunk;
  }
  if (dcpl >= 0) H5Pclose(dcpl);
  if (type >= 0) H5Tclose(type);
  if (fcpl >= 0) H5Pclose(fcpl);
  return shape;
}

std::vector<Chunk> ListChunks(hid_t set, const std::vector<hsize_t>& dims,
                              const std::vector<hsize_t>& shape, const std::string& path) {
  std::vector<Chunk> chunks;
  const std::size_t rank = dims.size();
  hsize_t origin[3] = {0, 0, 0};
  while (true) {
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
      if (origin[axis] < dims[axis]) break;
      origin[axis] = 0;
      if (axis == 0) return chunks;
    }
  }
}

// Where a decoded chunk's rows go: `rows` rows of `row_values` floats, row r of the chunk to
// out + r·stride (rows past the dataset's end are dropped).
struct Placement {
  float* out;
  std::size_t stride, rows, row_values, chunk_row_values;
};

Placement PlacementOf(const Chunk& c, const std::vector<hsize_t>& dims,
                      const std::vector<hsize_t>& shape, float* out) {
  const hsize_t components = dims.size() == 3 ? dims[2] : 1;
  const hsize_t frames = std::min(shape[0], dims[0] - c.origin[0]);
  const hsize_t particles = std::min(shape[1], dims[1] - c.origin[1]);
  return {out + (c.origin[0] * dims[1] + c.origin[1]) * components, dims[1] * components, frames,
          particles * components, shape[1] * components};
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

// Decodes one chunk into its place in the output; an error message, or empty.
std::string DecodeChunk(const Chunk& c, std::string_view file, std::size_t chunk_bytes,
                        ZlibChunkDecoder* decoder, std::vector<unsigned char>* inflated,
                        const Placement& place) {
  if (c.address == HADDR_UNDEF) {  // never written: the fill value, 0
    for (std::size_t r = 0; r < place.rows; ++r)
      std::fill(place.out + r * place.stride, place.out + r * place.stride + place.row_values,
                0.0f);
    return {};
  }
  if (c.address > file.size() || c.stored_bytes > file.size() - c.address)
    return "HDF5: a chunk lies beyond the end of the file (truncated file)";
  const auto* stored = reinterpret_cast<const unsigned char*>(file.data() + c.address);
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

}  // namespace

bool ReadDeflatedChunksInParallel(hid_t file, hid_t set, FileBytes* file_bytes,
                                  const std::vector<hsize_t>& dims, float* out) {
  const std::string& path = file_bytes->path();
  const int rank = int(dims.size());
  if (rank < 2 || rank > 3) return false;
  const auto shape = ShuffleDeflateChunkShape(file, set, rank);
  // Whole components per chunk (as WriteHdf5 writes) keep the placement a row copy.
  if (!shape || (rank == 3 && (*shape)[2] != dims[2])) return false;
  const std::vector<Chunk> chunks = ListChunks(set, dims, *shape, path);
  if (!out) return true;  // a dry run: the chunk index walked, nothing decoded
  const std::string_view bytes = file_bytes->bytes();
  std::size_t chunk_bytes = sizeof(float);
  for (hsize_t d : *shape) chunk_bytes *= d;
  std::string error;
  // Allocated here: an exception must not leave a parallel region.
  std::vector<std::unique_ptr<ZlibChunkDecoder>> decoders(
      static_cast<std::size_t>(omp_get_max_threads()));
  for (auto& d : decoders) d = std::make_unique<ZlibChunkDecoder>();
#pragma omp parallel if (chunks.size() > 1)
  {
    std::vector<unsigned char> inflated;
    ZlibChunkDecoder& decoder = *decoders[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 4)
    for (std::size_t n = 0; n < chunks.size(); ++n) {
      const std::string failure = DecodeChunk(chunks[n], bytes, chunk_bytes, &decoder, &inflated,
                                              PlacementOf(chunks[n], dims, *shape, out));
      if (!failure.empty()) {
#pragma omp critical(owval_hdf5_chunk_error)
        if (error.empty()) error = failure;
      }
    }
  }
  if (!error.empty()) throw InputError(path, 0, error);
  return true;
}

}  // namespace owval::internal
