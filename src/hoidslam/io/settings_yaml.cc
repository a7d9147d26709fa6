#include "hoidslam/io/settings_yaml.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::io::yaml {
namespace {

namespace fs = std::filesystem;
using core::InputError;

// Matrices nest one level below a key; far deeper nesting is a broken file, and the bound keeps the recursion
// shallow whatever the input.
constexpr int kMaxDepth = 16;

Value OfKind(Value::Kind kind, std::size_t line = 0) {
  Value value;
  value.kind = kind;
  value.line = line;
  return value;
}

// A line with content: not blank, not only a comment.
struct Line {
  std::size_t number = 0;  // counting from 1
  std::size_t indent = 0;  // leading spaces
  std::string_view text;   // after the indentation, without the line break
};

std::string_view TrimLeft(std::string_view text) {
  const std::size_t begin = text.find_first_not_of(" \t");
  return begin == std::string_view::npos ? std::string_view() : text.substr(begin);
}

std::string_view TrimRight(std::string_view text) {
  const std::size_t end = text.find_last_not_of(" \t");
  return end == std::string_view::npos ? std::string_view() : text.substr(0, end + 1);
}

// Nothing but spaces and perhaps a comment.
bool IsBlank(std::string_view text) {
  text = TrimLeft(text);
  return text.empty() || text.front() == '#';
}

bool IsListItem(std::string_view text) { return text == "-" || text.starts_with("- ") || text.starts_with("-\t"); }

// A comment begins at `i`: a '#' at the start or after a space.
bool CommentAt(std::string_view text, std::size_t i) {
  return text[i] == '#' && (i == 0 || text[i - 1] == ' ' || text[i - 1] == '\t');
}

// Where a comment begins, or the end of `text`.
std::size_t CommentStart(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (CommentAt(text, i)) return i;
  }
  return text.size();
}

// Where a plain element of a [list] ends: at ',', ']' or a comment, found in one pass.
std::size_t FlowPlainEnd(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == ',' || text[i] == ']' || CommentAt(text, i)) return i;
  }
  return text.size();
}

// A ':' followed by a space, a tab or the end of the line, which would make a plain value a mapping.
std::size_t MappingColon(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == ':' && (i + 1 == text.size() || text[i + 1] == ' ' || text[i + 1] == '\t')) return i;
  }
  return std::string_view::npos;
}

class Parser {
 public:
  Parser(std::string_view text, const fs::path& path) : path_(path) { SplitLines(text); }

  Value Document() {
    if (next_ == lines_.size()) return OfKind(Value::Kind::kMapping, 1);
    if (IsListItem(lines_[next_].text)) {
      Fail(lines_[next_].number, "not a settings file: expected 'key: value' lines at the top level, found a list");
    }
    Value root = Mapping(lines_[next_].indent, 0);
    if (next_ < lines_.size()) {
      Fail(lines_[next_].number, "YAML syntax error: this line is indented less than the keys above it");
    }
    return root;
  }

 private:
  [[noreturn]] void Fail(std::size_t line, const std::string& what) const {
    throw InputError::AtLine(path_, line, what);
  }

  // Keeps the lines with content, after checking the header and the document markers.
  void SplitLines(std::string_view text) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // a byte-order mark some editors write
    if (!(text.starts_with("%YAML:1.") || text.starts_with("%YAML 1."))) {
      throw InputError::InFile(path_,
                               "not a settings file: it must be YAML beginning with the line %YAML:1.0, as ORB-SLAM3 "
                               "settings files do");
    }
    bool ended = false;  // after a "..." line
    std::size_t number = 1;
    for (std::size_t begin = 0; begin <= text.size(); ++number) {
      const std::size_t end = std::min(text.find('\n', begin), text.size());
      std::string_view line = text.substr(begin, end - begin);
      begin = end + 1;
      if (line.find('\0') != std::string_view::npos) Fail(number, "a NUL byte: a settings file is text");
      if (line.ends_with('\r')) line.remove_suffix(1);  // files written on Windows
      if (line.find('\r') != std::string_view::npos) {
        Fail(number, "a carriage return inside a line: save the file with line breaks of Linux (LF) or Windows (CRLF)");
      }
      if (number == 1) {
        const std::string_view version = line.substr(std::string_view("%YAML:1.").size());
        if (!IsBlank(version.substr(std::min(version.find_first_not_of("0123456789"), version.size())))) {
          Fail(number, "YAML syntax error: the first line must be %YAML:1.0 alone");
        }
        continue;
      }
      if (IsBlank(line)) continue;
      const std::size_t indent = std::min(line.find_first_not_of(' '), line.size());
      if (line[indent] == '\t') Fail(number, "YAML syntax error: a tab in the indentation (YAML indents with spaces)");
      const std::string_view content = line.substr(indent);
      if (ended) Fail(number, "YAML syntax error: text after the end of the document (...)");
      if (indent == 0 && content.starts_with("---")) {
        if (!IsBlank(content.substr(3))) Fail(number, "the document marker --- must stand alone on its line");
        if (!lines_.empty()) Fail(number, "YAML syntax error: a second document (---): a settings file holds one");
        continue;
      }
      if (indent == 0 && content.starts_with("...") && IsBlank(content.substr(3))) {
        ended = true;
        continue;
      }
      if (indent == 0 && content.starts_with('%')) {
        Fail(number, "YAML syntax error: a directive (%) after the first line");
      }
      lines_.push_back(Line{number, indent, TrimRight(content)});
    }
  }

  // The `key: value` lines at `indent`, from the next line on.
  Value Mapping(std::size_t indent, int depth) {
    if (depth > kMaxDepth) Fail(lines_[next_].number, fmt::format("nested deeper than {} levels", kMaxDepth));
    Value mapping = OfKind(Value::Kind::kMapping, lines_[next_].number);
    std::unordered_map<std::string_view, std::size_t> first_lines;  // of the keys so far
    bool after_block = false;  // the previous key took the indented lines below it
    while (next_ < lines_.size() && lines_[next_].indent >= indent) {
      const Line& line = lines_[next_++];
      if (line.indent > indent) {
        Fail(line.number, after_block ? "YAML syntax error: this line is indented differently from the lines above it "
                                        "in its block"
                                      : "YAML syntax error: this line is indented under a key that already has a "
                                        "value (only [lists] run over several lines)");
      }
      if (IsListItem(line.text)) Fail(line.number, "YAML syntax error: a list element where 'key: value' belongs");
      // As in OpenCV, the first ':' ends the key, with or without a space after it ("Viewer.PointSize:2").
      const std::size_t colon = line.text.find(':');
      if (colon == std::string_view::npos) Fail(line.number, "YAML syntax error: expected 'key: value'");
      const std::string_view key = TrimRight(line.text.substr(0, colon));
      if (key.empty() || std::string_view("\"'[]{}!&*|>@`#%,?").find(key.front()) != std::string_view::npos) {
        Fail(line.number, fmt::format("YAML syntax error: '{}' is not a key (keys are plain text)", key));
      }
      if (CommentStart(key) != key.size()) {
        Fail(line.number, "YAML syntax error: expected 'key: value' (a comment begins before the ':')");
      }
      if (const auto [first, inserted] = first_lines.emplace(key, line.number); !inserted) {
        Fail(line.number, fmt::format("{} is given more than once (first on line {})", key, first->second));
      }
      const std::size_t next_before = next_;
      Value value = EntryValue(line.text.substr(colon + 1), line.number, indent, depth);
      after_block = value.kind == Value::Kind::kMapping && next_ != next_before;
      mapping.entries.push_back(Entry{std::string(key), std::move(value)});
    }
    return mapping;
  }

  // What follows `key:` on line `number`; without anything there, the indented block below.
  Value EntryValue(std::string_view rest, std::size_t number, std::size_t key_indent, int depth) {
    rest = TrimLeft(rest);
    // A tag (OpenCV's !!opencv-matrix) names the type of the block below; reading the block does not need it.
    if (rest.starts_with('!')) {
      const std::size_t end = std::min(rest.find_first_of(" \t"), rest.size());
      if (end == 1) Fail(number, "YAML syntax error: a tag without a name ('!')");
      rest = rest.substr(end);
      if (!IsBlank(rest)) {
        Fail(number, "YAML syntax error: a tag before a value is not supported; a tag may only open an indented "
                     "block, as !!opencv-matrix does");
      }
    }
    if (IsBlank(rest)) {
      if (next_ < lines_.size()) {
        const Line& below = lines_[next_];
        const bool list = IsListItem(below.text);
        if (below.indent > key_indent || (list && below.indent == key_indent)) {
          Value block = list ? BlockList(below.indent) : Mapping(below.indent, depth + 1);
          block.line = number;
          return block;
        }
      }
      return OfKind(Value::Kind::kNone, number);
    }
    return rest.starts_with('[') ? FlowList(rest.substr(1), number, key_indent) : LineValue(rest, number);
  }

  // "- value" lines at `indent`.
  Value BlockList(std::size_t indent) {
    Value list = OfKind(Value::Kind::kList);
    while (next_ < lines_.size() && lines_[next_].indent == indent && IsListItem(lines_[next_].text)) {
      const Line& line = lines_[next_++];
      const std::string_view rest = TrimLeft(line.text.substr(1));
      if (IsBlank(rest)) Fail(line.number, "YAML syntax error: a list element without a value");
      list.items.push_back(LineValue(rest, line.number));
    }
    return list;
  }

  // A quoted or plain value that ends its line (a comment may follow).
  Value LineValue(std::string_view rest, std::size_t number) {
    if (rest.starts_with('"') || rest.starts_with('\'')) {
      Value value = Quoted(rest, number);
      if (!IsBlank(rest)) Fail(number, fmt::format("YAML syntax error: '{}' after the quoted value", TrimLeft(rest)));
      return value;
    }
    return Plain(TrimRight(rest.substr(0, CommentStart(rest))), number);
  }

  // A list in brackets that opens on line `number` just before `rest`, after a key at `key_indent`; it may run
  // over the lines below that are indented more than the key.
  Value FlowList(std::string_view rest, std::size_t number, std::size_t key_indent) {
    Value list = OfKind(Value::Kind::kList, number);
    std::size_t line = number;
    bool expect_element = true;  // after '[' or ','
    while (true) {
      rest = TrimLeft(rest);
      if (IsBlank(rest)) {
        if (next_ == lines_.size() || lines_[next_].indent <= key_indent) {
          Fail(number, "YAML syntax error: the list is not closed with ] (the lines it runs over are indented more "
                       "than its key)");
        }
        line = lines_[next_].number;
        rest = lines_[next_++].text;
        continue;
      }
      if (rest.front() == ']') {
        rest.remove_prefix(1);
        break;
      }
      if (rest.front() == ',') {
        if (expect_element) Fail(line, "YAML syntax error: an empty element in the list");
        expect_element = true;
        rest.remove_prefix(1);
        continue;
      }
      if (!expect_element) Fail(line, "YAML syntax error: missing ',' between the elements of the list");
      Value element;
      if (rest.front() == '"' || rest.front() == '\'') {
        element = Quoted(rest, line);
      } else {
        const std::size_t end = FlowPlainEnd(rest);
        element = Plain(TrimRight(rest.substr(0, end)), line);
        rest.remove_prefix(end);
      }
      list.items.push_back(std::move(element));
      expect_element = false;
    }
    if (!IsBlank(rest)) Fail(line, fmt::format("YAML syntax error: '{}' after the list", TrimLeft(rest)));
    return list;
  }

  // The quoted text at the start of `rest`, which is left just after the closing quote.
  Value Quoted(std::string_view& rest, std::size_t number) {
    const char quote = rest.front();
    Value value = OfKind(Value::Kind::kText, number);
    for (std::size_t i = 1; i < rest.size(); ++i) {
      const char c = rest[i];
      if (c == quote && quote == '\'' && i + 1 < rest.size() && rest[i + 1] == '\'') {
        value.text += '\'';
        ++i;
      } else if (c == quote) {
        rest.remove_prefix(i + 1);
        return value;
      } else if (c == '\\' && quote == '"') {
        if (++i == rest.size()) break;
        switch (rest[i]) {
          case '\\': value.text += '\\'; break;
          case '"': value.text += '"'; break;
          case '/': value.text += '/'; break;
          case 'n': value.text += '\n'; break;
          case 'r': value.text += '\r'; break;
          case 't': value.text += '\t'; break;
          default: Fail(number, fmt::format("YAML syntax error: the escape \\{} is not supported", rest[i]));
        }
      } else {
        value.text += c;
      }
    }
    Fail(number, "YAML syntax error: the quoted value is not closed on its line");
  }

  // An unquoted value, already without its comment: a number, or text.
  Value Plain(std::string_view token, std::size_t number) {
    if (token.empty()) Fail(number, "YAML syntax error: a value is missing");
    const char first = token.front();
    if (std::string_view("&*|>!%@`{}[],?").find(first) != std::string_view::npos || IsListItem(token)) {
      Fail(number, fmt::format("YAML syntax error: a value beginning with '{}' is not supported in a settings file; "
                               "put it in quotes",
                               first));
    }
    if (MappingColon(token) != std::string_view::npos) {
      Fail(number, fmt::format("YAML syntax error: ':' in the value '{}'; put it in quotes", token));
    }
    if (auto value = Number(token, number)) return *value;
    Value text = OfKind(Value::Kind::kText, number);
    text.text = token;
    return text;
  }

  // The number a plain value spells, if it is one. Only digits, signs, '.' and exponents count (so "inf", "nan"
  // and "nan(1)" stay text), and YAML's .inf and .nan.
  std::optional<Value> Number(std::string_view token, std::size_t line) const {
    std::string_view unsigned_part = token;
    const bool negative = token.starts_with('-');
    if (token.starts_with('+') || negative) unsigned_part.remove_prefix(1);
    Value value = OfKind(Value::Kind::kReal, line);
    if (unsigned_part == ".inf" || unsigned_part == ".Inf" || unsigned_part == ".INF") {
      value.real = negative ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
      return value;
    }
    if (token == ".nan" || token == ".NaN" || token == ".NAN") {  // YAML has no signed NaN
      value.real = std::numeric_limits<double>::quiet_NaN();
      return value;
    }
    const bool numeric_characters = unsigned_part.find_first_not_of("0123456789.eE+-") == std::string_view::npos;
    if (!numeric_characters || unsigned_part.find_first_of("0123456789") == std::string_view::npos ||
        unsigned_part.starts_with('+') || unsigned_part.starts_with('-')) {
      return std::nullopt;
    }
    const bool whole = unsigned_part.find_first_not_of("0123456789") == std::string_view::npos;
    if (whole && unsigned_part.size() > 1 && unsigned_part.front() == '0') {
      Fail(line, fmt::format("YAML syntax error: the integer {} begins with 0, which ORB-SLAM3 (through OpenCV) reads "
                             "as octal; write it without the leading 0",
                             token));
    }
    // from_chars takes '-' but not '+': parse the magnitude and the sign apart.
    const char* const begin = unsigned_part.data();
    const char* const end = begin + unsigned_part.size();
    std::int64_t integer = 0;
    if (const auto [stop, error] = std::from_chars(begin, end, integer); stop == end && error == std::errc()) {
      value.kind = Value::Kind::kInteger;
      value.integer = negative ? -integer : integer;
      value.real = static_cast<double>(value.integer);
      return value;
    }
    double real = 0.0;
    const auto [stop, error] = std::from_chars(begin, end, real, std::chars_format::general);
    if (stop != end) return std::nullopt;
    if (error == std::errc::result_out_of_range) Fail(line, fmt::format("the number {} is out of range", token));
    value.real = negative ? -real : real;
    return value;
  }

  const fs::path& path_;
  std::vector<Line> lines_;  // the lines with content after the header, in order
  std::size_t next_ = 0;     // the next of lines_ to read
};

}  // namespace

const Value* Value::Find(std::string_view key) const {
  const auto entry = std::find_if(entries.begin(), entries.end(), [&](const Entry& e) { return e.key == key; });
  return entry == entries.end() ? nullptr : &entry->value;
}

Value Parse(std::string_view text, const std::filesystem::path& path) { return Parser(text, path).Document(); }

}  // namespace hoidslam::io::yaml
