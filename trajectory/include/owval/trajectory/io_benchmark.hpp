#pragma once
// `owval bench io`: text parse and HDF5 write/read throughput of one large generated trajectory
// (a demo1-like scene: 64,000 wandering particles and a wall of boundary particles, written in
// Sibernetic's OpenCL text layout with its 6 significant digits).
#include <filesystem>
#include <nlohmann/json.hpp>

#include "owval/trajectory/formats.hpp"

namespace owval {

struct IoBenchmarkOptions {
  double text_size_mb = 500;  // size of the generated position_buffer.txt
  // For both files; empty: a fresh directory under temp_directory_path() (removed with them, on
  // SIGINT too), or temp_directory_path() itself when the files are kept.
  std::filesystem::path directory;
  Hdf5WriteOptions hdf5;
  bool keep_files = false;  // leave the generated files for inspection
  bool quiet = false;       // no progress line while parsing
};

// Figures as JSON: {"benchmark": "io", "text_parse_mb_per_s", "hdf5_read_gb_per_s_uncompressed"
// (ReadHdf5, the whole file), "hdf5_stream_read_gb_per_s_uncompressed" (OpenFrameSource, frame
// by frame), ...}. The generated files are removed unless options.keep_files.
nlohmann::json RunIoBenchmark(const IoBenchmarkOptions& options);

}  // namespace owval
