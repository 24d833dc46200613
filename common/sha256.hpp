// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// SHA-256 (OpenSSL EVP) of a file or a text, as lower-case hex: the provenance of what an artefact
// was built from (offline/scene), and the check that the controller FMU a loop runs is the one its
// artefact was built with (controller/fmu). Start-up only.
#include <string>
#include <string_view>

namespace flexloop::common {

/// @throws flexloop::InputError naming `path` when it cannot be opened.
std::string file_sha256(const std::string& path);
std::string text_sha256(std::string_view text);

}  // namespace flexloop::common
