#pragma once
// Every allocation whose size comes from an input file (a header's particle count, an HDF5
// dataset's dimensions, a configuration's box) is checked against the input's size where the
// format bounds it, and against this budget where it does not (issue 18 item 7): a 2 KB file
// must be refused with a message, not answered with a 16 GB allocation or an OOM kill.
#include <cstddef>
#include <string>

namespace owval {

// The budget in bytes. Default: half of physical memory (a run may hold the trajectory it reads
// and one copy); SetMemoryBudgetBytes(0) restores the default. The CLI's --max-memory sets it.
std::size_t MemoryBudgetBytes();
void SetMemoryBudgetBytes(std::size_t bytes);

// Throws InputError("file: FIELD needs N bytes, more than the memory budget of M bytes ...")
// when bytes exceeds the budget.
void CheckAllocation(std::size_t bytes, const std::string& file, const std::string& field);

// "4096", "512K", "300M", "2G" (powers of 1024) -> bytes. InputError naming `flag` for anything
// else, for zero, and for a size that does not fit in 64 bits.
std::size_t ParseByteSize(const std::string& text, const std::string& flag);

// a * b, or SIZE_MAX when the product overflows (then any budget check refuses it).
std::size_t SaturatingProduct(std::size_t a, std::size_t b);

}  // namespace owval
