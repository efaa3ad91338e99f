#include "owval/reports/document.hpp"

#include <gtest/gtest.h>

namespace owval::reports {
namespace {

TEST(Document, RendersTheSameContentAsMarkdownAndHtml) {
  Document d("one_sprig <report>");
  d.Heading("Parity");
  d.Table({{"quantity", "value"}, {"period", "0.7246 ms"}});
  d.Video("sxs.mp4", "reference left");
  d.Image("frames/frame_0.png", "frame 0");
  d.Plot("<svg></svg>", "tracked y");
  const std::string md = d.Markdown(), html = d.Html();
  EXPECT_NE(md.find("| quantity | value |\n|---|---|\n| period | 0.7246 ms |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("![frame 0](frames/frame_0.png)"), std::string::npos);
  EXPECT_NE(html.find("<video controls src=\"sxs.mp4\">"), std::string::npos);
  EXPECT_NE(html.find("<td>0.7246 ms</td>"), std::string::npos);
  EXPECT_NE(html.find("<svg></svg>"), std::string::npos);  // plots are inline
  EXPECT_NE(html.find("one_sprig &lt;report&gt;"), std::string::npos);
}

}  // namespace
}  // namespace owval::reports
