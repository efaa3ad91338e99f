// owval bench io: parse throughput of a large generated position_buffer.txt and HDF5 read
// throughput of the same trajectory (trajectory/io_benchmark.hpp). JSON on stdout.
#include <iostream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/trajectory/io_benchmark.hpp"

namespace owval::cli {
namespace {

void SetUp(CLI::App& app) {
  auto o = std::make_shared<IoBenchmarkOptions>();
  auto json_out = std::make_shared<std::string>();
  CLI::App* cmd = Bench(app).add_subcommand(
      "io", "Text parse and HDF5 read throughput on a large generated file");
  cmd->add_option("--size-mb", o->text_size_mb, "Size of the generated position_buffer.txt (MB)");
  cmd->add_option("--dir", o->directory, "Where to write the generated files");
  cmd->add_option("--json-out", *json_out, "Also write the JSON result here");
  cmd->add_option("--hdf5-level", o->hdf5.compression_level, "HDF5 deflate level (0-9)");
  cmd->add_option("--hdf5-chunk-frames", o->hdf5.frames_per_chunk, "HDF5 frames per chunk");
  cmd->add_flag("--keep", o->keep_files, "Keep the generated files");
  cmd->callback([o, json_out] {
    if (!json_out->empty()) CheckOutputPath(*json_out);
    o->quiet = Flags().quiet;
    const std::string result = RunIoBenchmark(*o).dump(2) + "\n";
    std::cout << result;
    if (!json_out->empty()) WriteFileAtomically(*json_out, result);
  });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
