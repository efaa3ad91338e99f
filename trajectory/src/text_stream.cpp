// Sibernetic text read frame by frame: zlib's gz* functions read plain and gzip-compressed files
// alike, a block of whole lines at a time; the rows are parsed by the same TextCursor, under the
// same layout rules (text_cursor.hpp), as the whole-file reader's.
#include "text_stream.hpp"

#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "owval/base/errors.hpp"
#include "owval/base/input_file.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/base/progress.hpp"
#include "text_cursor.hpp"

namespace owval::internal {
namespace {

constexpr std::size_t kBlockBytes = 1u << 20;
constexpr std::size_t kMaxLineBytes = 64u << 20;
constexpr std::size_t kMaxDeflateRatio = 1032;

// Whole lines of a file, a block at a time: memory is the block, whatever the file's size.
class LineBlocks {
 public:
  explicit LineBlocks(const std::string& path) : name_(path) {
    file_ = gzopen(path.c_str(), "rb");
    if (!file_) throw InputError(path, 0, "cannot open file (missing or unreadable)");
    gzbuffer(file_, 1u << 18);
  }
  ~LineBlocks() { gzclose(file_); }
  LineBlocks(const LineBlocks&) = delete;
  LineBlocks& operator=(const LineBlocks&) = delete;

  // The next run of whole lines (each ending in '\n'); at the end of the file, the last line
  // when it has no newline (the caller refuses it), then an empty view.
  std::string_view Next() {
    buffer_.erase(0, consumed_);
    offset_ += consumed_;
    consumed_ = 0;
    while (true) {
      const void* last = buffer_.empty() ? nullptr : memrchr(buffer_.data(), '\n', buffer_.size());
      if (last) {
        consumed_ = std::size_t(static_cast<const char*>(last) - buffer_.data()) + 1;
        return {buffer_.data(), consumed_};
      }
      if (eof_ || !Read()) {
        consumed_ = buffer_.size();
        return {buffer_.data(), consumed_};
      }
    }
  }
  // Uncompressed offset of the block Next() returned last.
  std::uint64_t offset() const { return offset_; }
  // Whether the file is gzip-compressed (known once a block was read).
  bool compressed() const { return gzdirect(file_) == 0; }
  // Compressed bytes read so far (for progress).
  std::uint64_t raw_offset() const { return std::uint64_t(gzoffset(file_)); }
  // Continues at this uncompressed offset (a gzip file is decompressed again to go back).
  void Seek(std::uint64_t offset) {
    if (gzseek(file_, z_off_t(offset), SEEK_SET) < 0)
      throw InputError(name_, 0, "cannot seek to byte " + std::to_string(offset));
    buffer_.clear();
    consumed_ = 0;
    offset_ = offset;
    eof_ = false;
  }

 private:
  // Fills the buffer up to a block (more only for a line longer than that); false at the end of
  // the file.
  bool Read() {
    if (buffer_.size() >= kMaxLineBytes)
      throw InputError(name_, 0, "a line longer than 64 MiB: not a Sibernetic text trajectory");
    const std::size_t old = buffer_.size();
    const std::size_t room = old + (1u << 16) < kBlockBytes ? kBlockBytes - old : old;
    buffer_.resize(old + room);
    const int n = gzread(file_, buffer_.data() + old, unsigned(room));
    int error = Z_OK;
    gzerror(file_, &error);
    if (n < 0 || (error != Z_OK && error != Z_BUF_ERROR))
      throw InputError(name_, 0, "gzip: corrupt compressed data");
    buffer_.resize(old + std::size_t(n));
    if (n == 0) {
      if (error == Z_BUF_ERROR)
        throw InputError(name_, 0, "gzip: truncated file (the compressed stream ends early)");
      eof_ = true;
    }
    return n > 0;
  }

  std::string name_;
  gzFile file_ = nullptr;
  std::string buffer_;
  std::size_t consumed_ = 0;  // bytes of buffer_ handed out by the last Next()
  std::uint64_t offset_ = 0;  // uncompressed offset of buffer_[0]
  bool eof_ = false;
};

// Rows across blocks: a TextCursor over the current block, continued into the next.
class RowStream {
 public:
  RowStream(LineBlocks* blocks, const std::string& name) : blocks_(blocks), name_(name) {}

  // Positions at the next row (or the end: false), skipping blank lines as ParseRows does.
  bool AtRow() {
    while (true) {
      if (in_) {
        in_->SkipEmptyTail();
        if (!in_->at_end()) return true;
      }
      if (!NextBlock()) return false;
    }
  }
  // The cursor on the next block (false at the end of the file), for the header.
  bool NextBlock() {
    const std::size_t line = this->line();
    block_ = blocks_->Next();
    if (block_.empty()) return false;
    // Every row ends with a newline; a file cut mid-row can still look like whole numbers
    // ("2.1" cut to "2"), so a missing final newline is how truncation shows.
    if (block_.back() != '\n')
      throw InputError(name_, line, "truncated file: the last line does not end with a newline");
    in_.emplace(block_, name_, line);
    return true;
  }
  TextCursor& cursor() { return *in_; }
  std::size_t line() const { return in_ ? in_->line() : first_line_; }
  // Uncompressed offset of the cursor (after AtRow: where the row starts).
  std::uint64_t offset() const { return blocks_->offset() + (in_ ? in_->offset(block_) : 0); }
  void Restart(std::uint64_t offset, std::size_t line) {
    blocks_->Seek(offset);
    in_.reset();
    block_ = {};
    first_line_ = line;
  }

 private:
  LineBlocks* blocks_;
  std::string name_;
  std::string_view block_;
  std::optional<TextCursor> in_;
  std::size_t first_line_ = 1;
};

struct Row {
  float x, y, z, type;
};

Row ParseRow(TextCursor& in) {
  Row r{};
  r.x = in.Coordinate("x"), r.y = in.Coordinate("y"), r.z = in.Coordinate("z");
  r.type = ReadTypeCode(in);
  in.EndOfLine("particle type");
  return r;
}

// The file's header: ParseHeader on the first block (the 11 lines are short). Its counts are
// bounded by the text's size, as in ReadSiberneticText: the file's size, or what deflate could
// expand it to when it is compressed (the scan then finds the rows missing).
Header ReadHeader(RowStream& rows, const LineBlocks& blocks, const std::string& name,
                  std::uint64_t file_bytes) {
  if (!rows.NextBlock())
    throw InputError(name, 0, "empty file: expected an 11-line header and particle rows");
  const std::uint64_t text_bytes =
      blocks.compressed() ? SaturatingProduct(file_bytes, kMaxDeflateRatio) : file_bytes;
  return ParseHeader(rows.cursor(), std::size_t(text_bytes));
}

class TextFrameSource : public FrameSource {
 public:
  TextFrameSource(const std::string& path, const TextReadOptions& options, TextReadReport* report,
                  bool partial)
      : name_(path), blocks_(path), rows_(&blocks_, path) {
    const std::uint64_t file_bytes = std::filesystem::file_size(path);
    header_text_ = ReadHeader(rows_, blocks_, name_, file_bytes);
    // Frame 0 and the frame handed out, 3 floats a particle each: sized by the header.
    CheckAllocation(SaturatingProduct(header_text_.particles(), 6 * sizeof(float)), name_,
                    "two frames' positions");
    Scan(options, file_bytes);
    const std::size_t frames = FrameCount(layout_, counts_.rows, header_text_);
    frame_offset_.resize(frames);
    frame_line_.resize(frames);
    FillHeader(partial);
    if (report) {
      report->detected = layout_;
      report->rows = counts_.rows;
      report->bytes = bytes_;
      report->description = DescribeText(layout_, frames, header_text_);
    }
  }

  const Trajectory& header() const override { return header_; }

  FrameRef Frame(std::size_t f) override {
    if (f >= header_.frame_count())
      throw std::out_of_range("text frame source: frame past the end");
    if (f == current_) return {frame_, 0};
    if (f != next_) rows_.Restart(frame_offset_[f], frame_line_[f]);
    current_ = next_ = SIZE_MAX;  // until the frame is read whole
    const Header& h = header_text_;
    const bool all_rows = f == 0 || layout_ == TextLayout::kNative;
    const std::size_t count = all_rows ? h.particles() : h.moving();
    float* xyz = frame_.positions.data();
    for (std::size_t i = 0; i < count; ++i) {
      if (!rows_.AtRow())
        throw InputError(name_, rows_.line(),
                         "the file ended early (changed since it was opened?)");
      const Row r = ParseRow(rows_.cursor());
      xyz[3 * i] = r.x, xyz[3 * i + 1] = r.y, xyz[3 * i + 2] = r.z;
    }
    if (!all_rows)  // boundary particles never move: frame 0's rows
      std::copy(first_.begin() + std::ptrdiff_t(3 * count), first_.end(), xyz + 3 * count);
    frame_.time_s[0] = header_.time_s[f];
    current_ = f;
    next_ = f + 1;
    return {frame_, 0};
  }

 private:
  // Every row once: the checks, frame 0, where each frame starts; the layout decided at the end.
  void Scan(const TextReadOptions& options, std::uint64_t file_bytes) {
    const Header& h = header_text_;
    const TextLayout requested = options.layout;
    counts_.first_row_line = rows_.line();
    counts_.expanded = StartsExpanded(h, requested);
    Progress progress("scan", file_bytes, options.quiet || file_bytes < (64u << 20));
    while (rows_.AtRow()) {
      const std::uint64_t offset = rows_.offset();
      const std::size_t line = rows_.line();
      const Row r = ParseRow(rows_.cursor());
      const bool boundary_row = r.type >= 3.0f && r.type < 4.0f;  // no cast: 1e30 is finite
      if (counts_.rows < h.particles()) {
        first_.insert(first_.end(), {r.x, r.y, r.z});
        type_.push_back(r.type);
      } else if (boundary_row) {
        ++counts_.boundary_rows_after_first_frame;
      }
      if (counts_.expanded && SwitchesToNative(counts_, h, boundary_row, requested))
        counts_.expanded = false;
      const std::size_t stride = counts_.expanded ? h.moving() : h.particles();
      if (counts_.rows == 0 ||
          (counts_.rows >= h.particles() && (counts_.rows - h.particles()) % stride == 0)) {
        frame_offset_.push_back(offset);
        frame_line_.push_back(line);
      }
      ++counts_.rows;
      if ((counts_.rows & 0xFFFFF) == 0) progress.Update(blocks_.raw_offset());
    }
    bytes_ = blocks_.offset();
    if (counts_.rows < h.particles())
      throw InputError(name_, rows_.line(),
                       "truncated first frame: expected " + std::to_string(h.particles()) +
                           " rows, found " + std::to_string(counts_.rows));
    layout_ = ResolveLayout(counts_, type_, h, requested, name_);
    if (layout_ == TextLayout::kOpenCL) CheckMovingFirst(type_, h, name_);
  }

  void FillHeader(bool partial) {
    const Header& h = header_text_;
    header_.box = frame_.box = h.box;
    header_.time_step_s = frame_.time_step_s = h.time_step_s;
    header_.log_step = frame_.log_step = h.log_step;
    header_.type = frame_.type = type_;
    const std::size_t frames = frame_offset_.size();
    header_.time_s = FrameTimes(h, frames, name_);
    header_.provenance["source_file"] = name_;
    header_.provenance["source_layout"] = LayoutName(layout_);
    if (partial) header_.provenance["partial"].assign(1, '1');
    frame_.provenance = header_.provenance;
    frame_.time_s.assign(1, 0.0);
    frame_.positions.assign(3 * h.particles(), 0.0f);
  }

  std::string name_;
  LineBlocks blocks_;
  RowStream rows_;
  Header header_text_;
  RowCounts counts_;
  TextLayout layout_ = TextLayout::kOpenCL;
  std::uint64_t bytes_ = 0;
  std::vector<float> type_, first_;          // frame 0's types and positions
  std::vector<std::uint64_t> frame_offset_;  // where each frame's first row starts
  std::vector<std::size_t> frame_line_;      // and its line number
  Trajectory header_, frame_;
  std::size_t current_ = SIZE_MAX, next_ = SIZE_MAX;  // frame in frame_; the one rows_ is at
};

// A plain file cut mid-row is refused before anything else, as ReadSiberneticText refuses it
// (a gzip file's last byte is known only once decompressed: the scan refuses it there).
void CheckEndsWithNewline(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) throw InputError(path, 0, "cannot open file (missing or unreadable)");
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> closer(file, &std::fclose);
  const int b0 = std::fgetc(file), b1 = std::fgetc(file);
  if (b0 == 0x1f && b1 == 0x8b) return;  // gzip
  if (b0 == EOF || std::fseek(file, -1, SEEK_END) != 0 || std::fgetc(file) == '\n') return;
  std::rewind(file);
  std::size_t lines = 1;
  char buffer[1 << 16];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, file)) > 0;)
    for (std::size_t i = 0; i < n; ++i) lines += buffer[i] == '\n';
  throw InputError(path, lines, "truncated file: the last line does not end with a newline");
}

}  // namespace

std::unique_ptr<FrameSource> OpenTextFrameSource(const std::string& path,
                                                 const TextReadOptions& options,
                                                 TextReadReport* report, bool partial) {
  RequireInputFile(path);  // before gzopen: a FIFO would block it
  CheckEndsWithNewline(path);
  return std::make_unique<TextFrameSource>(path, options, report, partial);
}

}  // namespace owval::internal
