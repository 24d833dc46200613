// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// One table per enum gives both directions between values and their command-line / JSON names,
// so that the names of WaitMode, ReceiveMode, OverrunPolicy and DropReason are written once.
// enum_name() is noexcept and allocation-free; parse_enum() is for set-up (it throws).
#include <stdexcept>
#include <string>

namespace flexloop::rt {

template <class E>
struct EnumName {
  E value;
  const char* name;
};

/// The name of `value` in `table`, "?" when it has none.
template <class E, std::size_t N>
const char* enum_name(const EnumName<E> (&table)[N], E value) noexcept {
  for (const auto& entry : table)
    if (entry.value == value) return entry.name;
  return "?";
}

/// The value named `name`; std::invalid_argument "unknown <what> 'name' (a | b | c)" otherwise.
template <class E, std::size_t N>
E parse_enum(const EnumName<E> (&table)[N], const std::string& name, const char* what) {
  std::string choices;
  for (const auto& entry : table) {
    if (name == entry.name) return entry.value;
    choices += (choices.empty() ? "" : " | ") + std::string(entry.name);
  }
  throw std::invalid_argument("unknown " + std::string(what) + " '" + name + "' (" + choices + ")");
}

}  // namespace flexloop::rt
