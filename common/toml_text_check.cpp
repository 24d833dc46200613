// SPDX-License-Identifier: BSD-3-Clause
#include "common/toml_text_check.hpp"

namespace flexloop::common {
namespace {

/// Length of the valid UTF-8 sequence starting at text[i], or 0 when it is invalid.
std::size_t valid_sequence_length(std::string_view text, std::size_t i) noexcept {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b0 = byte(i);
  if (b0 < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    n = 2;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    n = 3;
    if (b0 == 0xE0) lo = 0xA0;  // overlong
    if (b0 == 0xED) hi = 0x9F;  // UTF-16 surrogates
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    n = 4;
    if (b0 == 0xF0) lo = 0x90;  // overlong
    if (b0 == 0xF4) hi = 0x8F;  // above U+10FFFF
  } else {
    return 0;  // continuation byte, C0/C1 (overlong) or F5..FF
  }
  if (i + n > text.size()) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
  return n;
}

// Follows the structure of a TOML document far enough to know which characters toml++ will test
// for whitespace: line by line, a table header or a key/value pair (keys bare or quoted and
// dotted), values that are strings (four kinds), arrays, inline tables or bare tokens (numbers,
// booleans; toml++ scans those up to a value terminator, asking of each character whether it is
// whitespace). Where the text leaves this grammar it is not valid TOML there, toml++ will stop at
// or after that point, and any non-ASCII character from there on is refused.
class Scanner {
 public:
  explicit Scanner(std::string_view t) : t_(t) {}

  std::optional<TomlTextProblem> run() {
    while (i_ < t_.size()) {
      skip_blanks();
      if (i_ >= t_.size()) break;
      const char c = t_[i_];
      bool fine = true;
      if (c == '\n' || c == '\r') {
        fine = line_break();
      } else if (c == '#') {
        comment();
      } else {
        fine = (c == '[' ? header() : key_value()) && end_of_line();
      }
      if (problem_) return problem_;
      if (!fine) return rest_after_leaving_the_grammar();
    }
    return std::nullopt;
  }

 private:
  static constexpr int kMaxDepth = 256;  // toml++ nests no deeper either

  static bool ascii(char c) { return static_cast<unsigned char>(c) < 0x80; }
  static bool blank(char c) { return c == ' ' || c == '\t'; }
  static bool bare_key_char(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  }
  // toml++'s is_value_terminator, for ASCII characters.
  static bool value_terminator(char c) {
    return c == ' ' || c == '\t' || (c >= '\n' && c <= '\r') || c == ']' || c == '}' || c == ',' ||
           c == '#';
  }

  bool at(std::string_view s) const { return t_.substr(i_, s.size()) == s; }
  bool at(char c) const { return i_ < t_.size() && t_[i_] == c; }
  void fail(std::size_t line, const std::string& what) {
    if (!problem_) problem_ = TomlTextProblem{line, what};
  }

  std::optional<TomlTextProblem> rest_after_leaving_the_grammar() {
    const std::size_t from_line = line_;
    for (; i_ < t_.size(); ++i_) {
      if (t_[i_] == '\n') ++line_;
      if (!ascii(t_[i_]))
        return TomlTextProblem{
            line_, "a non-ASCII character " +
                       (line_ == from_line ? std::string("on a line that is not valid TOML")
                                           : "after line " + std::to_string(from_line) +
                                                 ", where the text stops being valid TOML") +
                       " (outside a string or comment; the TOML library cannot read it safely "
                       "there)"};
    }
    return std::nullopt;
  }

  void skip_blanks() {
    while (i_ < t_.size() && blank(t_[i_])) ++i_;
  }
  bool line_break() {
    if (at('\r')) ++i_;
    if (!at('\n')) return false;
    ++i_;
    ++line_;
    return true;
  }
  void comment() {
    while (i_ < t_.size() && t_[i_] != '\n') ++i_;
  }
  // Blanks, comments and line breaks (inside an array).
  bool skip_blank_lines() {
    for (;;) {
      skip_blanks();
      if (at('#')) comment();
      if (!at('\n') && !at('\r')) return true;
      if (!line_break()) return false;
    }
  }
  bool end_of_line() {
    skip_blanks();
    if (at('#')) comment();
    return i_ >= t_.size() || line_break();
  }

  // [a.b] or [[a.b]]
  bool header() {
    const bool array = at("[[");
    i_ += array ? 2 : 1;
    skip_blanks();
    if (!key()) return false;
    skip_blanks();
    if (!at(array ? "]]" : "]")) return false;
    i_ += array ? 2 : 1;
    return true;
  }

  // A dotted key of bare and quoted parts; a quoted part must be ASCII (keys are ours, and toml++
  // tests each character of a key for whitespace).
  bool key() {
    for (;;) {
      skip_blanks();
      if (at('"') || at('\'')) {
        if (at("\"\"\"") || at("'''")) return false;
        const std::size_t line = line_;
        bool non_ascii = false;
        if (!single_line_string(non_ascii)) return false;
        if (non_ascii) {
          fail(line, "a key with non-ASCII characters (keys are ASCII names)");
          return false;
        }
      } else {
        const std::size_t begin = i_;
        while (i_ < t_.size() && bare_key_char(t_[i_])) ++i_;
        if (i_ == begin) return false;
      }
      skip_blanks();
      if (!at('.')) return true;
      ++i_;
    }
  }

  bool key_value() {
    if (!key()) return false;
    skip_blanks();
    if (!at('=')) return false;
    ++i_;
    skip_blanks();
    return value(0);
  }

  bool value(int depth) {
    if (i_ >= t_.size() || depth > kMaxDepth) return false;
    const char c = t_[i_];
    if (c == '"' || c == '\'') {
      if (at("\"\"\"") || at("'''")) return multi_line_string(c);
      bool non_ascii = false;
      return single_line_string(non_ascii);
    }
    if (c == '[') return array(depth);
    if (c == '{') return inline_table(depth);
    // A bare token (number, boolean, inf, nan): toml++ scans it to a value terminator.
    const std::size_t begin = i_;
    while (i_ < t_.size() && !value_terminator(t_[i_])) {
      if (!ascii(t_[i_])) {
        fail(line_,
             "a non-ASCII character outside a string or comment (TOML allows them only there)");
        return false;
      }
      ++i_;
    }
    return i_ > begin;
  }

  bool array(int depth) {
    ++i_;  // '['
    for (;;) {
      if (!skip_blank_lines()) return false;
      if (at(']')) {
        ++i_;
        return true;
      }
      if (!value(depth + 1) || !skip_blank_lines()) return false;
      if (at(',')) {
        ++i_;
        continue;
      }
      if (!at(']')) return false;
      ++i_;
      return true;
    }
  }

  bool inline_table(int depth) {
    ++i_;  // '{'
    skip_blanks();
    if (at('}')) {
      ++i_;
      return true;
    }
    for (;;) {
      if (!key()) return false;
      skip_blanks();
      if (!at('=')) return false;
      ++i_;
      skip_blanks();
      if (!value(depth + 1)) return false;
      skip_blanks();
      if (at(',')) {
        ++i_;
        continue;
      }
      if (!at('}')) return false;
      ++i_;
      return true;
    }
  }

  // "..." (escapes) or '...' on one line; non_ascii: whether it held a non-ASCII character.
  bool single_line_string(bool& non_ascii) {
    const char quote = t_[i_++];
    while (i_ < t_.size() && t_[i_] != quote) {
      if (t_[i_] == '\n') return false;
      non_ascii |= !ascii(t_[i_]);
      if (quote == '"' && t_[i_] == '\\') ++i_;
      ++i_;
    }
    if (i_ >= t_.size()) return false;
    ++i_;
    return true;
  }

  bool multi_line_string(char quote) {
    const std::string triple(3, quote);
    i_ += 3;
    while (i_ < t_.size()) {
      if (at(triple)) {
        i_ += 3;
        for (int extra = 0; extra < 2 && at(quote); ++extra) ++i_;
        return true;
      }
      if (t_[i_] == '\n') ++line_;
      if (quote == '"' && t_[i_] == '\\') {
        ++i_;
        if (!escape_in_multi_line_basic()) return false;
        continue;
      }
      ++i_;
    }
    return false;
  }

  // After a backslash: an escape, or a line-ending backslash that swallows the blanks and line
  // breaks after it. toml++ tests the character after the backslash, and the first one it does
  // not swallow, for being whitespace: those must be ASCII.
  bool escape_in_multi_line_basic() {
    const std::string advice =
        "a non-ASCII character right after a backslash in a multi-line string (the TOML library "
        "cannot read it there; write it as \\uXXXX)";
    if (i_ >= t_.size()) return false;
    const char c = t_[i_];
    if (!ascii(c)) {
      fail(line_, advice);
      return false;
    }
    if (!blank(c) && c != '\r' && c != '\n') {
      ++i_;  // an ordinary escape (its validity is toml++'s to judge)
      return true;
    }
    while (i_ < t_.size() && (blank(t_[i_]) || t_[i_] == '\r' || t_[i_] == '\n')) {
      if (t_[i_] == '\n') ++line_;
      ++i_;
    }
    if (i_ < t_.size() && !ascii(t_[i_])) {
      fail(line_, advice);
      return false;
    }
    return true;
  }

  std::string_view t_;
  std::size_t i_ = 0, line_ = 1;
  std::optional<TomlTextProblem> problem_;
};

}  // namespace

std::optional<Utf8Error> first_invalid_utf8(std::string_view text) noexcept {
  std::size_t line = 1;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = valid_sequence_length(text, i);
    if (n == 0) return Utf8Error{line, i};
    if (text[i] == '\n') ++line;
    i += n;
  }
  return std::nullopt;
}

std::optional<TomlTextProblem> toml_text_problem(std::string_view text) {
  if (const auto bad = first_invalid_utf8(text))
    return TomlTextProblem{bad->line, "not valid UTF-8 (byte " + std::to_string(bad->offset) +
                                          " of the file); save it as UTF-8"};
  return Scanner(text).run();
}

}  // namespace flexloop::common
