// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the loop artefact reader (artefact/loop_artefact.hpp) on any JSON text: what the
// online programs read before anything else. Text that is not JSON stops at the parser (the file
// reader reports it as InputError); a JSON document must be accepted or end in
// flexloop::InputError naming the key. Any other exception, a crash or a sanitizer report is a
// finding (tools/fuzz; the corpus replays in every test run).
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>

#include "artefact/loop_artefact.hpp"
#include "common/input_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nlohmann::json j = nlohmann::json::parse(data, data + size, nullptr, false);
  if (j.is_discarded()) return 0;
  try {
    const flexloop::artefact::LoopArtefact a =
        flexloop::artefact::loop_artefact_from_json(j, "fuzz.json");
    // What was accepted writes back and reads again as the same loop.
    const flexloop::artefact::LoopArtefact b =
        flexloop::artefact::loop_artefact_from_json(flexloop::artefact::to_json(a), "again.json");
    const bool same_shape =
        b.plant.A.rows() == a.plant.A.rows() && b.plant.A.cols() == a.plant.A.cols();
    if (b.rate_hz != a.rate_hz || !same_shape || b.plant.A != a.plant.A) __builtin_trap();
  } catch (const flexloop::common::InputError&) {
  }
  return 0;
}
