// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the model parser (plant/model/model_parser.hpp) on any text. Bad input must end in
// flexloop::InputError (file:line and what is wrong); any other exception, a crash or a sanitizer
// report is a finding (tools/fuzz; the corpus replays in every test run).
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/input_error.hpp"
#include "plant/model/model_parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    flexloop::plant::model::parse_model(text, "fuzz.toml");
  } catch (const flexloop::common::InputError&) {
  }
  return 0;
}
