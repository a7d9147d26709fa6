#pragma once
// For the report tests: is a piece of SVG or HTML well formed enough that a browser draws what we meant?
// Every element closed in order, no stray '<' in text; HTML void elements and the raw text of <style> and <script>
// allowed.

#include <algorithm>
#include <array>
#include <cctype>
#include <string>
#include <string_view>
#include <vector>

namespace hoidslam::report::testing {

// Empty when every tag is closed in order; else what is wrong, with the position.
inline std::string UnbalancedTags(std::string_view markup) {
  constexpr std::array<std::string_view, 5> kVoid = {"meta", "br", "img", "hr", "link"};
  std::vector<std::string> open;
  std::size_t pos = 0;
  while ((pos = markup.find('<', pos)) != std::string_view::npos) {
    const std::size_t end = markup.find('>', pos);
    if (end == std::string_view::npos) return "unterminated tag at " + std::to_string(pos);
    const std::string_view tag = markup.substr(pos + 1, end - pos - 1);
    if (tag.starts_with('!')) {  // <!DOCTYPE html>
      pos = end + 1;
      continue;
    }
    const bool closing = tag.starts_with('/');
    const std::string_view body = closing ? tag.substr(1) : tag;
    const std::string name(body.substr(0, body.find_first_of(" \n/")));
    const auto is_name_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; };
    if (name.empty() || !std::all_of(name.begin(), name.end(), is_name_char)) {
      return "stray '<' at " + std::to_string(pos) + ": " + std::string(markup.substr(pos, 20));
    }
    pos = end + 1;
    if (closing) {
      if (open.empty() || open.back() != name) {
        return "</" + name + "> at " + std::to_string(pos) + " closes <" + (open.empty() ? "" : open.back()) + ">";
      }
      open.pop_back();
    } else if (!tag.ends_with('/') && std::find(kVoid.begin(), kVoid.end(), name) == kVoid.end()) {
      open.push_back(name);
      if (name == "style" || name == "script") {  // raw text: CSS and JavaScript may hold '<' and '>'
        pos = markup.find("</" + name + ">", pos);
        if (pos == std::string_view::npos) return "unterminated <" + name + ">";
      }
    }
  }
  if (!open.empty()) return "<" + open.back() + "> is never closed";
  return "";
}

}  // namespace hoidslam::report::testing
