#pragma once
// A table of results as people read it (Markdown) and as spreadsheets read it (CSV). Cells are text already
// formatted by whoever builds the table, so a "failed" or "–" sits beside numbers.

#include <string>
#include <vector>

namespace hoidslam::report {

struct Table {
  std::string title;                          // e.g. "ATE RMSE (m), median of 5 runs"
  std::string note;                           // one line under the table (how it was measured); may be empty
  std::vector<std::string> header;            // column names
  std::vector<std::vector<std::string>> rows;  // each as long as header

  // "### title", the pipe table, then the note in italics. Pipes inside cells are escaped.
  std::string ToMarkdown() const;
  // RFC 4180: the header line, then one line per row; cells with commas, quotes or newlines are quoted.
  std::string ToCsv() const;
};

}  // namespace hoidslam::report
