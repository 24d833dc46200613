// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What every TOML text passes before toml++ sees it. Debian's toml++ 3.3 reaches
// __builtin_unreachable (undefined behaviour) in is_non_ascii_horizontal_whitespace for common
// code points (U+00A1..U+0499: '°', 'µ', '²', 'Ä', Greek; U+2D3E..U+3137 but U+3000) wherever it
// asks "is this whitespace?" of a non-ASCII character: outside strings and comments, inside
// quoted keys, and after a backslash in a multi-line basic string (found by tests/fuzz). So the
// text must be valid UTF-8 (RFC 3629), and non-ASCII characters may stand only where TOML 1.0
// allows them and toml++ reads them safely: comments and string values. Outside them TOML allows
// none anyway; a quoted key with one is never one of ours; the backslash case is refused with
// the way around it (\uXXXX). Finding "outside a string" follows the document's structure
// (headers, keys, values, arrays, inline tables); where the text leaves it, it is invalid TOML
// and any non-ASCII character after that point is refused too. This checks, it reads nothing:
// toml++ stays the reader.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace flexloop::common {

/// Where the first invalid UTF-8 sequence starts: its 1-based line and its byte offset.
struct Utf8Error {
  std::size_t line = 1;
  std::size_t offset = 0;
};

/// The first invalid sequence of `text` (no overlong forms, no surrogates, nothing above
/// U+10FFFF, no truncated sequence), or nothing when the whole text is valid UTF-8.
std::optional<Utf8Error> first_invalid_utf8(std::string_view text) noexcept;

/// A problem found in a TOML text: its 1-based line and what is wrong.
struct TomlTextProblem {
  std::size_t line = 1;
  std::string what;
};

/// The first reason not to hand `text` to toml++ (see the header comment), or nothing.
std::optional<TomlTextProblem> toml_text_problem(std::string_view text);

}  // namespace flexloop::common
