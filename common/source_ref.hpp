// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Where something was read: a file and a line (0: the file as a whole), as input errors print it.
#include <string>

namespace flexloop::common {

struct SourceRef {
  std::string file;
  int line = 0;
  std::string str() const { return line > 0 ? file + ":" + std::to_string(line) : file; }
};

}  // namespace flexloop::common
