// The HDF5 chunk decoder (libdeflate): zlib's output on every kind of stream zlib's deflate
// writes, and never a wrong answer on a broken one.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "hdf5_chunks.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "zlib_chunk.hpp"

namespace owval {
namespace {

using Bytes = std::vector<unsigned char>;

// One zlib stream of `data`; `flush_at` > 0 also flushes there (an empty stored block for
// Z_SYNC_FLUSH and Z_FULL_FLUSH, a partial block for Z_PARTIAL_FLUSH).
Bytes Compress(const Bytes& data, int level, int strategy, std::size_t flush_at = 0,
               int flush = Z_SYNC_FLUSH) {
  z_stream z{};
  EXPECT_EQ(deflateInit2(&z, level, Z_DEFLATED, 15, 8, strategy), Z_OK);
  Bytes out(deflateBound(&z, uLong(data.size())) + 64);
  z.next_out = out.data();
  z.avail_out = uInt(out.size());
  z.next_in = const_cast<unsigned char*>(data.data());
  if (flush_at > 0 && flush_at < data.size()) {
    z.avail_in = uInt(flush_at);
    EXPECT_EQ(deflate(&z, flush), Z_OK);
    z.avail_in = uInt(data.size() - flush_at);
  } else {
    z.avail_in = uInt(data.size());
  }
  EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

// zlib's answer: the output when the stream inflates to exactly `size` bytes, else nothing.
std::optional<Bytes> ZlibInflate(const Bytes& stream, std::size_t size) {
  Bytes out(size + 1);
  uLongf length = uLongf(out.size());
  if (uncompress(out.data(), &length, stream.data(), uLong(stream.size())) != Z_OK ||
      length != size)
    return std::nullopt;
  out.resize(size);
  return out;
}

// owval's chunk decoder (libdeflate). The output buffer is exactly `size` bytes, so ASan sees
// any write past it.
bool Inflate(const Bytes& stream, std::size_t size, Bytes* out) {
  static internal::ZlibChunkDecoder decoder;
  out->assign(size, 0xee);
  return decoder.Decode(stream.data(), stream.size(), out->data(), size);
}

// Inputs of every texture: incompressible, few symbols, text, short-distance runs, and the byte
// planes of shuffled, slowly moving float32 positions (what owval's chunks hold).
std::vector<Bytes> Samples(std::size_t size, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Bytes> samples(5, Bytes(size));
  for (auto& b : samples[0]) b = static_cast<unsigned char>(rng());
  for (auto& b : samples[1]) b = static_cast<unsigned char>(rng() % 4);
  const std::string words[] = {"worm ", "muscle ", "particle ", "elastic ", "liquid\n"};
  for (std::size_t i = 0; i < size;)
    for (char c : words[rng() % 5])
      if (i < size) samples[2][i++] = static_cast<unsigned char>(c);
  for (std::size_t i = 0; i < size;) {  // runs repeating 1..9-byte patterns
    const std::size_t period = 1 + rng() % 9, run = 3 + rng() % 300;
    for (std::size_t k = 0; k < run && i < size; ++k, ++i)
      samples[3][i] = k < period ? static_cast<unsigned char>(rng()) : samples[3][i - period];
  }
  const std::size_t n = size / 4;
  std::vector<float> x(n);
  std::uniform_real_distribution<float> jitter(-1e-3f, 1e-3f);
  for (std::size_t e = 0; e < n; ++e)
    x[e] = 10.0f + float(e % 3072) * 0.02f + float(e / 3072) * 0.01f + jitter(rng);
  for (std::size_t e = 0; e < n; ++e)
    for (int k = 0; k < 4; ++k)
      samples[4][std::size_t(k) * n + e] = reinterpret_cast<const unsigned char*>(&x[e])[k];
  return samples;
}

TEST(ZlibChunk, EqualsZlibOnEveryLevelAndStrategy) {
  const int strategies[] = {Z_DEFAULT_STRATEGY, Z_FILTERED, Z_HUFFMAN_ONLY, Z_RLE, Z_FIXED};
  Bytes out;
  for (std::size_t size : {0u, 1u, 7u, 300u, 4096u, 65549u, 196608u}) {
    const auto samples = Samples(size, std::uint32_t(size));
    for (std::size_t s = 0; s < samples.size(); ++s) {
      for (int level = 0; level <= 9; ++level) {
        for (int strategy : strategies) {
          if (size > 70000 && level % 3 != 1) continue;  // keep the test quick
          const Bytes stream = Compress(samples[s], level, strategy);
          ASSERT_TRUE(Inflate(stream, size, &out))
              << "size " << size << " sample " << s << " level " << level << " strategy "
              << strategy;
          ASSERT_EQ(out, samples[s]) << size << " " << s << " " << level << " " << strategy;
        }
      }
    }
  }
}

TEST(ZlibChunk, EqualsZlibAcrossFlushedBlocks) {
  Bytes out;
  for (int flush : {Z_SYNC_FLUSH, Z_FULL_FLUSH, Z_PARTIAL_FLUSH, Z_BLOCK}) {
    for (const Bytes& sample : Samples(50000, 3)) {
      for (std::size_t at : {1u, 13u, 32768u, 49999u}) {
        const Bytes stream = Compress(sample, 6, Z_DEFAULT_STRATEGY, at, flush);
        ASSERT_TRUE(Inflate(stream, sample.size(), &out)) << flush << " at " << at;
        ASSERT_EQ(out, sample) << flush << " at " << at;
      }
    }
  }
}

TEST(ZlibChunk, RefusesAnyOtherSizeAndTruncatedStreams) {
  const Bytes sample = Samples(20000, 5)[4];
  const Bytes stream = Compress(sample, 4, Z_DEFAULT_STRATEGY);
  Bytes out;
  EXPECT_FALSE(Inflate(stream, sample.size() - 1, &out));
  EXPECT_FALSE(Inflate(stream, sample.size() + 1, &out));
  for (std::size_t keep = 0; keep < stream.size(); ++keep) {
    const Bytes cut(stream.begin(), stream.begin() + std::ptrdiff_t(keep));
    EXPECT_FALSE(Inflate(cut, sample.size(), &out)) << "kept " << keep << " bytes";
  }
  Bytes longer = stream;  // bytes after the checksum are ignored, as zlib does
  longer.insert(longer.end(), {1, 2, 3});
  EXPECT_TRUE(Inflate(longer, sample.size(), &out));
  EXPECT_EQ(out, sample);
}

// Corrupt streams: whatever the chunk decoder accepts, zlib decodes to the same bytes.
TEST(ZlibChunk, NeverAcceptsWhatZlibDecodesOtherwise) {
  std::mt19937 rng(11);
  Bytes out;
  int accepted = 0;
  for (const Bytes& sample : Samples(6000, 9)) {
    for (int level : {1, 6}) {
      const Bytes stream = Compress(sample, level, level == 1 ? Z_FIXED : Z_DEFAULT_STRATEGY);
      for (int trial = 0; trial < 400; ++trial) {
        Bytes broken = stream;
        const int flips = 1 + int(rng() % 3);
        for (int f = 0; f < flips; ++f)
          broken[2 + rng() % (broken.size() - 2)] ^= static_cast<unsigned char>(1u << (rng() % 8));
        if (!Inflate(broken, sample.size(), &out)) continue;
        ++accepted;
        const auto reference = ZlibInflate(broken, sample.size());
        ASSERT_TRUE(reference.has_value()) << "accepted a stream zlib refuses, trial " << trial;
        ASSERT_EQ(out, *reference) << "trial " << trial;
      }
    }
  }
  // A flip in unused code space can pass; a flip in the data cannot get past the Adler-32.
  EXPECT_LT(accepted, 200);
}

// A hand-made stream: one dynamic block whose distance code is a single code of length 1. It is
// valid (zlib and libdeflate accept incomplete codes of that shape) but zlib's deflate never
// writes one.
Bytes IncompleteDistanceCodeStream(std::size_t size) {
  Bytes out = {0x78, 0x9c};
  std::uint64_t bits = 0;
  int count = 0;
  auto put = [&](unsigned value, int n) {  // least significant bit first
    bits |= std::uint64_t(value) << count;
    count += n;
    while (count >= 8) {
      out.push_back(static_cast<unsigned char>(bits));
      bits >>= 8;
      count -= 8;
    }
  };
  put(1, 1);   // final block
  put(2, 2);   // dynamic Huffman codes
  put(0, 5);   // 257 literal/length codes
  put(0, 5);   // 1 distance code
  put(15, 4);  // 19 code length codes, in RFC 1951's order 16 17 18 0 8 7 9 6 10 5 11 4 12 ...
  const int order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
  for (int symbol : order) put(symbol == 1 || symbol == 18 ? 1 : 0, 3);
  // Code length code: 1 -> bit 0, 18 -> bit 1. Lengths: 'a' (97) and end-of-block 1, distance
  // code 0 length 1, the rest 0 (runs of 18: 11 + 7 bits).
  put(1, 1), put(97 - 11, 7);                        // 97 zeros
  put(0, 1);                                         // 'a': 1
  put(1, 1), put(138 - 11, 7);                       // 138 zeros
  put(1, 1), put(256 - 98 - 138 - 11, 7);            // 20 zeros
  put(0, 1);                                         // end of block: 1
  put(0, 1);                                         // distance code 0: 1
  for (std::size_t i = 0; i < size; ++i) put(0, 1);  // 'a' is code 0, end of block code 1
  put(1, 1);
  if (count > 0) put(0, 8 - count);
  const Bytes data(size, 'a');
  const std::uint32_t adler =
      std::uint32_t(adler32(adler32(0, nullptr, 0), data.data(), uInt(data.size())));
  for (int shift : {24, 16, 8, 0}) out.push_back(static_cast<unsigned char>(adler >> shift));
  return out;
}

TEST(ZlibChunk, DecodesTheIncompleteCodesZlibAccepts) {
  const Bytes stream = IncompleteDistanceCodeStream(96);
  const auto reference = ZlibInflate(stream, 96);
  ASSERT_TRUE(reference.has_value()) << "the hand-made stream is not valid deflate";
  EXPECT_EQ(*reference, Bytes(96, 'a'));
  Bytes out;
  ASSERT_TRUE(Inflate(stream, 96, &out));
  EXPECT_EQ(out, *reference);
}

TEST(ZlibChunk, RefusesAWrongChecksumAndAWrongHeader) {
  const Bytes sample = Samples(5000, 8)[2];
  const Bytes stream = Compress(sample, 6, Z_DEFAULT_STRATEGY);
  Bytes out;
  ASSERT_TRUE(Inflate(stream, sample.size(), &out));
  for (std::size_t k = 1; k <= 4; ++k) {
    Bytes broken = stream;
    broken[broken.size() - k] ^= 0x10;
    EXPECT_FALSE(Inflate(broken, sample.size(), &out)) << "checksum byte " << k;
  }
  Bytes header = stream;
  header[0] = 0x79;  // compression method 9: not deflate
  EXPECT_FALSE(Inflate(header, sample.size(), &out));
}

// Hand-made chunks with unusual (valid) codes come out of the parallel reader equal to HDF5's own
// pipeline.
TEST(ZlibChunk, HandMadeChunksReadInParallelEqualToHdf5sPipeline) {
  namespace fs = std::filesystem;
  const fs::path path = owval::testing::TestScratch() / "inflate.h5";
  const hsize_t dims[3] = {4, 4, 3}, chunk[3] = {2, 4, 3};
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t space = H5Screate_simple(3, dims, nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(dcpl, 3, chunk);
  H5Pset_shuffle(dcpl);
  H5Pset_deflate(dcpl, 4);
  const hid_t set =
      H5Dcreate2(file, "positions", H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  const Bytes stream = IncompleteDistanceCodeStream(2 * 4 * 3 * sizeof(float));
  for (hsize_t frame : {0u, 2u}) {
    const hsize_t origin[3] = {frame, 0, 0};
    ASSERT_GE(H5Dwrite_chunk(set, H5P_DEFAULT, 0, origin, stream.size(), stream.data()), 0);
  }
  H5Fflush(file, H5F_SCOPE_LOCAL);
  std::vector<float> fast(4 * 4 * 3, -1.0f), pipeline(4 * 4 * 3, -2.0f);
  internal::FileBytes bytes(path.string());
  ASSERT_TRUE(internal::ReadDeflatedChunksInParallel(file, set, &bytes, {4, 4, 3}, fast.data()));
  ASSERT_GE(H5Dread(set, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, pipeline.data()), 0);
  float a;
  std::memcpy(&a, "aaaa", 4);
  EXPECT_EQ(fast, std::vector<float>(4 * 4 * 3, a));
  EXPECT_EQ(fast, pipeline);
  H5Dclose(set);
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Fclose(file);
  fs::remove(path);
}

}  // namespace
}  // namespace owval
