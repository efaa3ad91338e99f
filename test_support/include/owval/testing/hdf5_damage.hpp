#pragma once
// A damaged owval HDF5 file, as a disk error or a cut copy leaves one: readers must refuse it
// with the file's name (only programs that link HDF5 include this).
#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <fstream>

namespace owval::testing {

// Overwrites 16 bytes in the middle of the positions chunk that holds `frame`.
inline void CorruptPositionsChunk(const std::filesystem::path& path, hsize_t frame) {
  haddr_t address = 0;
  hsize_t stored = 0;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t set = H5Dopen2(file, "positions", H5P_DEFAULT);
  const hsize_t origin[3] = {frame, 0, 0};
  unsigned mask = 0;
  const herr_t found = H5Dget_chunk_info_by_coord(set, origin, &mask, &address, &stored);
  H5Dclose(set);
  H5Fclose(file);
  ASSERT_GE(found, 0);
  ASSERT_GT(stored, 64u);
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(std::streamoff(address + stored / 2));
  const char garbage[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  f.write(garbage, sizeof garbage);
}

}  // namespace owval::testing
