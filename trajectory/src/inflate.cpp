#include "inflate.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>

#include "adler32.hpp"

namespace owval::internal {
namespace {

// A decode table entry: bits 0-3 the code's length in bits (for a subtable pointer, the main
// table's bits), bits 4-7 flags, bits 8-15 the extra bits that follow (for a pointer, the
// subtable's bits), bits 16-31 the value (literal byte, base length or distance, subtable start).
constexpr std::uint32_t kLiteral = 0x10, kEndOfBlock = 0x20, kSubtable = 0x40, kInvalid = 0x80;
constexpr int kLitBits = 11, kDistBits = 8, kPrecodeBits = 7;
// Main table plus the most its subtables can take: every subtable serves at least two codes and
// holds at most 2^(15 - bits) entries (288 litlen symbols: 144 x 16; 32 distances: 16 x 128).
constexpr int kLitTableSize = (1 << kLitBits) + 144 * 16;
constexpr int kDistTableSize = (1 << kDistBits) + 16 * 128;
constexpr int kPrecodeTableSize = 1 << kPrecodeBits;

constexpr std::uint16_t kLengthBase[29] = {3,  4,  5,  6,   7,   8,   9,   10,  11, 13,
                                           15, 17, 19, 23,  27,  31,  35,  43,  51, 59,
                                           67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr std::uint8_t kLengthExtra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                           2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
constexpr std::uint16_t kDistBase[30] = {
    1,   2,   3,   4,   5,   7,    9,    13,   17,   25,   33,   49,   65,    97,    129,
    193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
constexpr std::uint8_t kDistExtra[30] = {0, 0, 0, 0, 1, 1, 2, 2,  3,  3,  4,  4,  5,  5,  6,
                                         6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
constexpr std::uint8_t kPrecodeOrder[19] = {16, 17, 18, 0, 8,  7, 9,  6, 10, 5,
                                            11, 4,  12, 3, 13, 2, 14, 1, 15};

// What each symbol decodes to, less the code length.
struct SymbolEntries {
  std::array<std::uint32_t, 288> litlen{};
  std::array<std::uint32_t, 32> dist{};
  std::array<std::uint32_t, 19> precode{};
  SymbolEntries() {
    for (std::uint32_t s = 0; s < 256; ++s) litlen[s] = kLiteral | (s << 16);
    litlen[256] = kEndOfBlock;
    for (int s = 0; s < 29; ++s)
      litlen[257 + s] =
          (std::uint32_t(kLengthBase[s]) << 16) | (std::uint32_t(kLengthExtra[s]) << 8);
    litlen[286] = litlen[287] = kInvalid;
    for (int s = 0; s < 30; ++s)
      dist[s] = (std::uint32_t(kDistBase[s]) << 16) | (std::uint32_t(kDistExtra[s]) << 8);
    dist[30] = dist[31] = kInvalid;
    for (std::uint32_t s = 0; s < 19; ++s) precode[s] = s << 16;
  }
};
const SymbolEntries kEntries;

unsigned Reverse(unsigned code, int bits) {
  unsigned r = 0;
  for (int i = 0; i < bits; ++i, code >>= 1) r = (r << 1) | (code & 1);
  return r;
}

// Builds the decode table of a canonical Huffman code (RFC 1951 §3.2.2) with code lengths
// `lengths[0, count)`. Refuses over-subscribed and incomplete codes.
bool BuildTable(const std::uint8_t* lengths, int count, const std::uint32_t* entries, int bits,
                std::uint32_t* table, int capacity) {
  int per_length[16] = {};
  for (int s = 0; s < count; ++s) ++per_length[lengths[s]];
  per_length[0] = 0;
  int left = 1;
  for (int len = 1; len <= 15; ++len) {
    left = (left << 1) - per_length[len];
    if (left < 0) return false;
  }
  if (left != 0) return false;
  unsigned next[16] = {};
  for (int len = 1, code = 0; len <= 15; ++len) {
    code = (code + per_length[len - 1]) << 1;
    next[len] = unsigned(code);
  }
  int next_free = 1 << bits;
  unsigned codes[288];
  for (int s = 0; s < count; ++s) {
    const int len = lengths[s];
    if (len == 0) continue;
    codes[s] = next[len]++;
    if (len <= bits) {
      const std::uint32_t entry = entries[s] | std::uint32_t(len);
      for (unsigned i = Reverse(codes[s], len); i < (1u << bits); i += 1u << len) table[i] = entry;
    } else {
      table[Reverse(codes[s] >> (len - bits), bits)] = 0;  // sub-bits, set below
    }
  }
  for (int s = 0; s < count; ++s) {  // deepest code per prefix: the subtable's bits
    const int len = lengths[s];
    if (len <= bits) continue;
    std::uint32_t& main = table[Reverse(codes[s] >> (len - bits), bits)];
    main = std::max<std::uint32_t>(main, std::uint32_t(len - bits));
  }
  for (int s = 0; s < count; ++s) {
    const int len = lengths[s];
    if (len <= bits) continue;
    std::uint32_t& main = table[Reverse(codes[s] >> (len - bits), bits)];
    if (!(main & kSubtable)) {
      const std::uint32_t sub_bits = main;
      if (next_free + (1 << sub_bits) > capacity) return false;
      main = kSubtable | (std::uint32_t(next_free) << 16) | (sub_bits << 8) | std::uint32_t(bits);
      next_free += 1 << sub_bits;
    }
    const unsigned start = main >> 16, size = 1u << ((main >> 8) & 0xff);
    const int rest = len - bits;
    const std::uint32_t entry = entries[s] | std::uint32_t(rest);
    for (unsigned i = Reverse(codes[s] & ((1u << rest) - 1), rest); i < size; i += 1u << rest)
      table[start + i] = entry;
  }
  return true;
}

struct FixedTables {
  std::uint32_t litlen[kLitTableSize];
  std::uint32_t dist[kDistTableSize];
  bool ok;
  FixedTables() {
    std::uint8_t len[288];
    std::memset(len, 8, 144);
    std::memset(len + 144, 9, 112);
    std::memset(len + 256, 7, 24);
    std::memset(len + 280, 8, 8);
    std::uint8_t dlen[32];
    std::memset(dlen, 5, 32);
    ok = BuildTable(len, 288, kEntries.litlen.data(), kLitBits, litlen, kLitTableSize) &&
         BuildTable(dlen, 32, kEntries.dist.data(), kDistBits, dist, kDistTableSize);
  }
};
const FixedTables kFixed;

std::uint64_t Load64(const unsigned char* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  return v;  // little-endian hosts only (x86-64, AArch64): see the static_assert below
}
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "InflateZlib reads bits little-endian");

// Deflate's bit stream, least significant bit first. Bits of `buf` above `left` are either zero
// or the stream's next bits, so refills may OR whole words over them.
struct BitReader {
  const unsigned char *begin, *in, *end;
  std::uint64_t buf = 0;
  unsigned left = 0;
  unsigned past_end = 0;  // zero bytes supplied beyond `end`

  // At least 56 bits in `buf` afterwards.
  void Refill() {
    if (end - in >= 8) {
      buf |= Load64(in) << left;
      in += (63 - left) >> 3;
      left |= 56;
    } else {
      while (left < 56) {
        std::uint64_t byte = 0;
        if (in < end) {
          byte = *in++;
        } else {
          ++past_end;
        }
        buf |= byte << left;
        left += 8;
      }
    }
  }
  void Drop(unsigned n) {
    buf >>= n;
    left -= n;
  }
  unsigned Take(unsigned n) {
    const unsigned v = unsigned(buf & ((std::uint64_t(1) << n) - 1));
    Drop(n);
    return v;
  }
  // Offset of the first byte not yet consumed, after dropping to a byte boundary; negative past
  // the end of the input.
  std::ptrdiff_t ByteOffset() {
    Drop(left & 7);
    return (in - begin) + std::ptrdiff_t(past_end) - std::ptrdiff_t(left >> 3);
  }
  void Seek(std::ptrdiff_t offset) {
    in = begin + offset;
    buf = 0;
    left = 0;
    past_end = 0;
  }
};

// One symbol: needs 15 bits in the reader.
inline std::uint32_t Decode(BitReader& r, const std::uint32_t* table, int bits) {
  std::uint32_t e = table[r.buf & ((1u << bits) - 1)];
  if (e & kSubtable) {
    r.Drop(unsigned(bits));
    e = table[(e >> 16) + (r.buf & ((1u << ((e >> 8) & 0xff)) - 1))];
  }
  r.Drop(e & 0xf);
  return e;
}

struct DynamicTables {
  std::uint32_t litlen[kLitTableSize];
  std::uint32_t dist[kDistTableSize];
};

bool ReadDynamicHeader(BitReader& r, DynamicTables* t) {
  r.Refill();
  const int nlit = int(r.Take(5)) + 257, ndist = int(r.Take(5)) + 1, nprecode = int(r.Take(4)) + 4;
  if (nlit > 286 || ndist > 30) return false;
  std::uint8_t precode_len[19] = {};
  for (int i = 0; i < nprecode; ++i) {
    if (r.left < 3) r.Refill();
    precode_len[kPrecodeOrder[i]] = std::uint8_t(r.Take(3));
  }
  std::uint32_t precode[kPrecodeTableSize];
  if (!BuildTable(precode_len, 19, kEntries.precode.data(), kPrecodeBits, precode,
                  kPrecodeTableSize))
    return false;
  std::uint8_t len[286 + 30];
  const int total = nlit + ndist;
  for (int i = 0; i < total;) {
    if (r.left < 14) r.Refill();
    const unsigned sym = Decode(r, precode, kPrecodeBits) >> 16;
    if (sym < 16) {
      len[i++] = std::uint8_t(sym);
      continue;
    }
    std::uint8_t value = 0;
    int repeat;
    if (sym == 16) {
      if (i == 0) return false;
      value = len[i - 1];
      repeat = 3 + int(r.Take(2));
    } else if (sym == 17) {
      repeat = 3 + int(r.Take(3));
    } else {
      repeat = 11 + int(r.Take(7));
    }
    if (i + repeat > total) return false;
    std::memset(len + i, value, std::size_t(repeat));
    i += repeat;
  }
  if (len[256] == 0) return false;  // no end-of-block code
  return BuildTable(len, nlit, kEntries.litlen.data(), kLitBits, t->litlen, kLitTableSize) &&
         BuildTable(len + nlit, ndist, kEntries.dist.data(), kDistBits, t->dist, kDistTableSize);
}

// Literals and matches up to the end-of-block code.
bool DecodeBlock(BitReader& reader, const std::uint32_t* litlen, const std::uint32_t* dist,
                 unsigned char* begin, unsigned char*& out_ref, unsigned char* end) {
  // Local copies: the reader's state then stays in registers, which stores through `out` (a
  // char pointer, so it may alias anything not local) would otherwise force back to memory.
  BitReader r = reader;
  unsigned char* out = out_ref;
  const bool ok = [&] {
    for (;;) {
      r.Refill();
      std::uint32_t e = Decode(r, litlen, kLitBits);
      if (e & kLiteral) {  // up to three literals per refill (3 x 15 bits)
        if (out == end) return false;
        *out++ = static_cast<unsigned char>(e >> 16);
        e = Decode(r, litlen, kLitBits);
        if (e & kLiteral) {
          if (out == end) return false;
          *out++ = static_cast<unsigned char>(e >> 16);
          e = Decode(r, litlen, kLitBits);
          if (e & kLiteral) {
            if (out == end) return false;
            *out++ = static_cast<unsigned char>(e >> 16);
            continue;
          }
        }
      }
      if (e & kEndOfBlock) return true;
      if (e & kInvalid) return false;
      if (r.left < 5 + 15 + 13) r.Refill();
      const std::size_t length = (e >> 16) + r.Take((e >> 8) & 0xff);
      const std::uint32_t d = Decode(r, dist, kDistBits);
      if (d & kInvalid) return false;
      const std::size_t distance = (d >> 16) + r.Take((d >> 8) & 0xff);
      if (distance > std::size_t(out - begin) || length > std::size_t(end - out)) return false;
      unsigned char* to = out;
      const unsigned char* from = out - distance;
      out += length;
      if (distance >= 8 && end - out >= 8) {  // word copies, overshooting by up to 7 bytes
        do {
          std::memcpy(to, from, 8);
          to += 8;
          from += 8;
        } while (to < out);
      } else if (distance == 1) {
        std::memset(to, *from, length);
      } else {
        for (std::size_t i = 0; i < length; ++i) to[i] = from[i];
      }
    }
  }();
  reader = r;
  out_ref = out;
  return ok;
}

}  // namespace

bool InflateZlib(const unsigned char* in, std::size_t in_bytes, unsigned char* out,
                 std::size_t size) {
  if (!kFixed.ok || in_bytes < 6 || (in[0] & 0x0f) != 8 || (in[0] >> 4) > 7 ||
      ((in[0] << 8) | in[1]) % 31 != 0 || (in[1] & 0x20))
    return false;
  BitReader r{in, in + 2, in + in_bytes};
  unsigned char* o = out;
  unsigned char* const end = out + size;
  DynamicTables dynamic;
  for (bool last = false; !last;) {
    r.Refill();
    if (r.past_end > 8) return false;
    last = r.Take(1);
    const unsigned type = r.Take(2);
    if (type == 0) {  // stored
      const std::ptrdiff_t at = r.ByteOffset();
      if (at < 0 || std::size_t(at) + 4 > in_bytes) return false;
      const unsigned length = in[at] | (in[at + 1] << 8), check = in[at + 2] | (in[at + 3] << 8);
      if (length != (~check & 0xffffu) || std::size_t(at) + 4 + length > in_bytes ||
          length > std::size_t(end - o))
        return false;
      std::memcpy(o, in + at + 4, length);
      o += length;
      r.Seek(at + 4 + std::ptrdiff_t(length));
    } else if (type == 1) {
      if (!DecodeBlock(r, kFixed.litlen, kFixed.dist, out, o, end)) return false;
    } else if (type == 2) {
      if (!ReadDynamicHeader(r, &dynamic) ||
          !DecodeBlock(r, dynamic.litlen, dynamic.dist, out, o, end))
        return false;
    } else {
      return false;
    }
  }
  const std::ptrdiff_t at = r.ByteOffset();
  if (o != end || at < 0 || std::size_t(at) + 4 > in_bytes) return false;
  const std::uint32_t stored = (std::uint32_t(in[at]) << 24) | (std::uint32_t(in[at + 1]) << 16) |
                               (std::uint32_t(in[at + 2]) << 8) | std::uint32_t(in[at + 3]);
  return Adler32(1, out, size) == stored;
}

}  // namespace owval::internal
