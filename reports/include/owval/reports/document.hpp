#pragma once
// A report written once and rendered twice: as Markdown (for a PR or a terminal) and as a
// self-contained HTML page (plots inline as SVG; video and images by relative path).
#include <string>
#include <vector>

namespace owval::reports {

class Document {
 public:
  explicit Document(std::string title) : title_(std::move(title)) {}

  void Heading(const std::string& text);
  void Paragraph(const std::string& text);
  // The first row is the header.
  void Table(const std::vector<std::vector<std::string>>& rows);
  void Plot(const std::string& svg, const std::string& caption);  // Markdown links to caption only
  void Video(const std::string& relative_path, const std::string& caption);
  void Image(const std::string& relative_path, const std::string& caption);

  std::string Markdown() const;
  std::string Html() const;

 private:
  enum class Kind { kHeading, kParagraph, kTable, kPlot, kVideo, kImage };
  struct Block {
    Kind kind;
    std::string text, extra;
    std::vector<std::vector<std::string>> rows;
  };
  std::string title_;
  std::vector<Block> blocks_;
};

std::string HtmlEscape(const std::string& text);

}  // namespace owval::reports
