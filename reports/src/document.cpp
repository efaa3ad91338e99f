#include "owval/reports/document.hpp"

#include <sstream>

namespace owval::reports {

std::string HtmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void Document::Heading(const std::string& text) {
  blocks_.push_back({Kind::kHeading, text, "", {}});
}
void Document::Paragraph(const std::string& text) {
  blocks_.push_back({Kind::kParagraph, text, "", {}});
}
void Document::Table(const std::vector<std::vector<std::string>>& rows) {
  blocks_.push_back({Kind::kTable, "", "", rows});
}
void Document::Plot(const std::string& svg, const std::string& caption) {
  blocks_.push_back({Kind::kPlot, svg, caption, {}});
}
void Document::Video(const std::string& path, const std::string& caption) {
  blocks_.push_back({Kind::kVideo, path, caption, {}});
}
void Document::Image(const std::string& path, const std::string& caption) {
  blocks_.push_back({Kind::kImage, path, caption, {}});
}

std::string Document::Markdown() const {
  std::ostringstream s;
  s << "# " << title_ << "\n\n";
  for (const Block& b : blocks_) {
    switch (b.kind) {
      case Kind::kHeading:
        s << "## " << b.text << "\n\n";
        break;
      case Kind::kParagraph:
        s << b.text << "\n\n";
        break;
      case Kind::kTable:
        for (std::size_t r = 0; r < b.rows.size(); ++r) {
          s << "|";
          for (const std::string& cell : b.rows[r]) s << " " << cell << " |";
          s << "\n";
          if (r == 0) {
            s << "|";
            for (std::size_t c = 0; c < b.rows[0].size(); ++c) s << "---|";
            s << "\n";
          }
        }
        s << "\n";
        break;
      case Kind::kPlot:
        s << "*" << b.extra << "* (plot in index.html)\n\n";
        break;
      case Kind::kVideo:
        s << "[" << b.extra << "](" << b.text << ")\n\n";
        break;
      case Kind::kImage:
        s << "![" << b.extra << "](" << b.text << ")\n\n";
        break;
    }
  }
  return s.str();
}

std::string Document::Html() const {
  std::ostringstream s;
  s << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << HtmlEscape(title_)
    << "</title>\n"
    << "<style>body{font-family:sans-serif;max-width:1300px;margin:2em auto;padding:0 1em}"
       "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px 8px;text-align:left}"
       "figure{margin:1em 0}img,video{max-width:100%}</style></head><body>\n";
  s << "<h1>" << HtmlEscape(title_) << "</h1>\n";
  for (const Block& b : blocks_) {
    switch (b.kind) {
      case Kind::kHeading:
        s << "<h2>" << HtmlEscape(b.text) << "</h2>\n";
        break;
      case Kind::kParagraph:
        s << "<p>" << HtmlEscape(b.text) << "</p>\n";
        break;
      case Kind::kTable:
        s << "<table>\n";
        for (std::size_t r = 0; r < b.rows.size(); ++r) {
          s << "<tr>";
          for (const std::string& cell : b.rows[r])
            s << (r ? "<td>" : "<th>") << HtmlEscape(cell) << (r ? "</td>" : "</th>");
          s << "</tr>\n";
        }
        s << "</table>\n";
        break;
      case Kind::kPlot:
        s << "<figure>" << b.text << "<figcaption>" << HtmlEscape(b.extra)
          << "</figcaption></figure>\n";
        break;
      case Kind::kVideo:
        s << "<figure><video controls src=\"" << HtmlEscape(b.text) << "\"></video><figcaption>"
          << HtmlEscape(b.extra) << "</figcaption></figure>\n";
        break;
      case Kind::kImage:
        s << "<figure><img src=\"" << HtmlEscape(b.text) << "\" alt=\"" << HtmlEscape(b.extra)
          << "\"><figcaption>" << HtmlEscape(b.extra) << "</figcaption></figure>\n";
        break;
    }
  }
  s << "</body></html>\n";
  return s.str();
}

}  // namespace owval::reports
