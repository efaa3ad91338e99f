// Fuzz target: the OME-Zarr reader (trajectory/src/zarr_reader.cpp: each array's .zarray, the
// .zattrs units and scale, the 1-D time and type arrays, every chunk of positions), as
// `owval ci quick-test` and kinematics' CompareWithTrajectory read a store: OmeZarrReader, then
// every frame. A store is a directory, so the input is a small container of files, each section
// a header line then the file's bytes up to the next header:
//
//   @@ .zattrs\n{...}\n@@ body/positions/.zarray\n{...}\n@@ body/positions/0.0.0\n<bytes>...
//
// (the "\n" before "@@ " belongs to the separator, not to the file). A path of other characters
// than [A-Za-z0-9._/], with a ".." component, or over 64 characters is skipped (the scratch
// store must hold every file the input names); bytes before the first header are ignored.
#include <cctype>
#include <filesystem>
#include <string>
#include <string_view>

#include "fuzz_common.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kHeader = "@@ ";
constexpr std::size_t kMaxPathChars = 64, kMaxFiles = 64;

bool SafeRelativePath(std::string_view path) {
  if (path.empty() || path.size() > kMaxPathChars || path.front() == '/') return false;
  for (char c : path)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '/'))
      return false;
  for (const fs::path& part : fs::path(path))
    if (part == ".." || part == ".") return false;
  return true;
}

// The input's sections written under `store`.
void WriteStore(std::string_view input, const fs::path& store) {
  std::size_t at = 0;
  if (input.rfind(kHeader, 0) != 0) {
    at = input.find("\n@@ ");
    if (at != std::string_view::npos) ++at;  // the separator's "\n"
  }
  for (std::size_t files = 0; at != std::string_view::npos && files < kMaxFiles; ++files) {
    const std::size_t name_end = input.find('\n', at);
    if (name_end == std::string_view::npos) return;
    const std::string_view name = input.substr(at + kHeader.size(), name_end - at - kHeader.size());
    const std::size_t next = input.find("\n@@ ", name_end);
    const std::string_view bytes = next == std::string_view::npos
                                       ? input.substr(name_end + 1)
                                       : input.substr(name_end + 1, next - name_end - 1);
    if (SafeRelativePath(name)) {
      const fs::path file = store / name;
      std::error_code ec;
      fs::create_directories(file.parent_path(), ec);
      owval::fuzz::WriteInput(file, bytes);
    }
    at = next == std::string_view::npos ? next : next + 1;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  // Removed when the program exits (a crash keeps it, and the input that crashed is saved).
  static const owval::testing::ScratchDirectory scratch("fuzz_zarr");
  const fs::path store = scratch / "store.zarr";
  std::error_code ec;
  fs::remove_all(store, ec);
  fs::create_directories(store, ec);
  WriteStore(std::string_view(reinterpret_cast<const char*>(data), size), store);
  try {
    owval::OmeZarrReader reader(store);
    for (std::size_t f = 0; f < reader.frame_count(); ++f) reader.FrameMicrometres(f);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}
