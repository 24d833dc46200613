// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/si_unit.hpp"

#include <cctype>
#include <stdexcept>
#include <vector>

namespace flexloop::pipeline {

namespace {

struct Symbol {
  const char* name;
  std::array<int, 8> exponents;  // kg m s A K mol cd rad
};

// The base units, rad, and the derived units a mechanical channel may carry (SI brochure, table 4).
constexpr Symbol kSymbols[] = {
    {"kg", {1, 0, 0, 0, 0, 0, 0, 0}},  {"m", {0, 1, 0, 0, 0, 0, 0, 0}},
    {"s", {0, 0, 1, 0, 0, 0, 0, 0}},   {"A", {0, 0, 0, 1, 0, 0, 0, 0}},
    {"K", {0, 0, 0, 0, 1, 0, 0, 0}},   {"mol", {0, 0, 0, 0, 0, 1, 0, 0}},
    {"cd", {0, 0, 0, 0, 0, 0, 1, 0}},  {"rad", {0, 0, 0, 0, 0, 0, 0, 1}},
    {"N", {1, 1, -2, 0, 0, 0, 0, 0}},  {"Pa", {1, -1, -2, 0, 0, 0, 0, 0}},
    {"J", {1, 2, -2, 0, 0, 0, 0, 0}},  {"W", {1, 2, -3, 0, 0, 0, 0, 0}},
    {"Hz", {0, 0, -1, 0, 0, 0, 0, 0}}, {"V", {1, 2, -3, -1, 0, 0, 0, 0}},
    {"1", {0, 0, 0, 0, 0, 0, 0, 0}},
};

struct Factor {
  const Symbol* symbol;
  int exponent;
};

// A recursive-descent reader of the grammar in si_unit.hpp.
class UnitReader {
 public:
  explicit UnitReader(const std::string& text) : text_(text) {}

  SiUnit read() {
    if (text_.empty()) fail("an empty unit");
    SiUnit u;
    const std::vector<Factor> numerator = product();
    add(u, numerator, +1, false);
    while (more() && text_[at_] == '/') {
      ++at_;
      std::vector<Factor> denominator;
      if (more() && text_[at_] == '(') {
        ++at_;
        denominator = product();
        if (!more() || text_[at_] != ')') fail("no ')' closing the '(' before position " + place());
        ++at_;
      } else {
        denominator.push_back(factor());
      }
      add(u, denominator, -1, true);
    }
    if (more()) fail("'" + std::string(1, text_[at_]) + "' at position " + place());
    return u;
  }

 private:
  bool more() const { return at_ < text_.size(); }
  std::string place() const { return std::to_string(at_ + 1); }

  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument(
        "unit \"" + text_ + "\" does not read: " + what +
        " (an SI unit without prefixes: kg m s A K mol cd rad N Pa J W Hz V or 1, joined by ' ', "
        "'.' or '*', divided by '/', powers as s^2, s2 or s^-2)");
  }

  std::vector<Factor> product() {
    std::vector<Factor> factors{factor()};
    while (more() && (text_[at_] == ' ' || text_[at_] == '.' || text_[at_] == '*')) {
      ++at_;
      factors.push_back(factor());
    }
    return factors;
  }

  Factor factor() {
    const std::size_t begin = at_;
    if (more() && text_[at_] == '1')
      ++at_;
    else
      while (more() && std::isalpha(static_cast<unsigned char>(text_[at_]))) ++at_;
    const std::string name = text_.substr(begin, at_ - begin);
    if (name.empty()) fail("no unit symbol at position " + std::to_string(begin + 1));
    const Symbol* symbol = nullptr;
    for (const auto& s : kSymbols)
      if (name == s.name) symbol = &s;
    if (!symbol) fail("unknown symbol \"" + name + "\"");
    return {symbol, exponent()};
  }

  // [ "^" ] [ "-" | "+" ] digits, or nothing: 1.
  int exponent() {
    const bool caret = more() && text_[at_] == '^';
    if (caret) ++at_;
    int sign = 1;
    if (more() && (text_[at_] == '-' || text_[at_] == '+')) sign = text_[at_++] == '-' ? -1 : 1;
    const std::size_t begin = at_;
    while (more() && std::isdigit(static_cast<unsigned char>(text_[at_])) && at_ - begin < 3) ++at_;
    if (at_ == begin) {
      if (caret || sign < 0) fail("no exponent digits at position " + place());
      return 1;
    }
    const int e = sign * std::stoi(text_.substr(begin, at_ - begin));
    if (e == 0) fail("exponent 0 at position " + std::to_string(begin + 1));
    return e;
  }

  // The factors' exponents into u (sign -1: a denominator) and their Modelica spelling.
  void add(SiUnit& u, const std::vector<Factor>& factors, int sign, bool denominator) {
    std::string spelled;
    for (const auto& f : factors) {
      if (f.symbol->name == std::string("1") && (f.exponent != 1 || factors.size() > 1))
        fail("\"1\" stands alone (a dimensionless signal, or \"1/s\")");
      for (std::size_t b = 0; b < u.exponents.size(); ++b)
        u.exponents[b] += sign * f.exponent * f.symbol->exponents[b];
      if (!spelled.empty()) spelled += '.';
      spelled += f.symbol->name;
      if (f.exponent != 1) spelled += std::to_string(f.exponent);
    }
    if (!denominator)
      u.name = spelled;
    else
      u.name += factors.size() > 1 ? "/(" + spelled + ")" : "/" + spelled;
  }

  const std::string& text_;
  std::size_t at_ = 0;
};

}  // namespace

SiUnit parse_si_unit(const std::string& unit) {
  return UnitReader(unit).read();
}

}  // namespace flexloop::pipeline
