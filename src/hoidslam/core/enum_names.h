#pragma once
// Enumerations that users spell in settings, scenarios and flags: one table of (value, name) pairs per enum,
// and the two lookups every such enum needs, with the same error message everywhere.

#include <array>
#include <string>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::core {

template <typename Enum, std::size_t N>
using EnumNames = std::array<std::pair<Enum, std::string_view>, N>;

// The name of `value`, or "unknown" when the table lacks it.
template <typename Enum, std::size_t N>
std::string_view EnumName(const EnumNames<Enum, N>& names, Enum value) {
  for (const auto& [candidate, name] : names) {
    if (candidate == value) return name;
  }
  return "unknown";
}

// The value named `text`; otherwise throws InputError naming `parameter`:
// "unknown <what> '<text>' (expected a, b or c)".
template <typename Enum, std::size_t N>
Enum ParseEnumName(const EnumNames<Enum, N>& names, std::string_view text, const std::string& parameter,
                   std::string_view what) {
  std::string expected;
  for (std::size_t i = 0; i < N; ++i) {
    if (names[i].second == text) return names[i].first;
    expected += fmt::format("{}{}", i == 0 ? "" : (i + 1 == N ? " or " : ", "), names[i].second);
  }
  throw InputError::ForParameter(parameter, fmt::format("unknown {} '{}' (expected {})", what, text, expected));
}

}  // namespace hoidslam::core
