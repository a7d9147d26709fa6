#include "hoidslam/report/table.h"

#include <sstream>

namespace hoidslam::report {
namespace {

std::string MarkdownCell(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '|') out += '\\';
    out += c == '\n' ? ' ' : c;
  }
  return out;
}

std::string CsvCell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + '"';
}

void MarkdownRow(std::ostringstream& out, const std::vector<std::string>& cells) {
  out << '|';
  for (const std::string& cell : cells) out << ' ' << MarkdownCell(cell) << " |";
  out << '\n';
}

}  // namespace

std::string Table::ToMarkdown() const {
  std::ostringstream out;
  if (!title.empty()) out << "### " << title << "\n\n";
  MarkdownRow(out, header);
  out << '|';
  for (std::size_t i = 0; i < header.size(); ++i) out << "---|";
  out << '\n';
  for (const auto& row : rows) MarkdownRow(out, row);
  if (!note.empty()) out << "\n*" << MarkdownCell(note) << "*\n";
  return out.str();
}

std::string Table::ToCsv() const {
  std::ostringstream out;
  const auto line = [&out](const std::vector<std::string>& cells) {
    for (std::size_t i = 0; i < cells.size(); ++i) out << (i ? "," : "") << CsvCell(cells[i]);
    out << "\r\n";
  };
  line(header);
  for (const auto& row : rows) line(row);
  return out.str();
}

}  // namespace hoidslam::report
