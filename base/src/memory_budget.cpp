#include "owval/base/memory_budget.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>

#include "owval/base/errors.hpp"

namespace owval {
namespace {

std::atomic<std::size_t> budget_bytes{0};

std::size_t HalfOfPhysicalMemory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return std::size_t{4} << 30;  // unknown: 4 GiB
  return SaturatingProduct(static_cast<std::size_t>(pages), static_cast<std::size_t>(page)) / 2;
}

}  // namespace

std::size_t MemoryBudgetBytes() {
  const std::size_t set = budget_bytes.load(std::memory_order_relaxed);
  if (set) return set;
  static const std::size_t half = HalfOfPhysicalMemory();
  return half;
}

void SetMemoryBudgetBytes(std::size_t bytes) {
  budget_bytes.store(bytes, std::memory_order_relaxed);
}

void CheckAllocation(std::size_t bytes, const std::string& file, const std::string& field) {
  const std::size_t budget = MemoryBudgetBytes();
  if (bytes <= budget) return;
  const std::string need = bytes == std::numeric_limits<std::size_t>::max()
                               ? std::string("more than 2^64")
                               : std::to_string(bytes);
  throw InputError(file, 0,
                   field + " needs " + need + " bytes, more than the memory budget of " +
                       std::to_string(budget) + " bytes (--max-memory)");
}

std::size_t ParseByteSize(const std::string& text, const std::string& flag) {
  std::size_t digits = 0;
  while (digits < text.size() && text[digits] >= '0' && text[digits] <= '9') ++digits;
  const std::string suffix = text.substr(digits);
  const int shift = suffix.empty()  ? 0
                    : suffix == "K" ? 10
                    : suffix == "M" ? 20
                    : suffix == "G" ? 30
                                    : -1;
  std::size_t value = 0;
  bool fits = digits > 0 && digits <= 19 && shift >= 0;
  if (fits) {
    value = std::stoull(text.substr(0, digits));
    fits = value > 0 && value <= (std::numeric_limits<std::size_t>::max() >> shift);
  }
  if (!fits)
    throw InputError(flag + " " + text.substr(0, 40) +
                     ": expected a positive size in bytes, optionally with K, M or G (e.g. 512M)");
  return value << shift;
}

std::size_t SaturatingProduct(std::size_t a, std::size_t b) {
  std::size_t product = 0;
  if (__builtin_mul_overflow(a, b, &product)) return std::numeric_limits<std::size_t>::max();
  return product;
}

}  // namespace owval
