#pragma once
// Writing an artefact so that a reader never sees half of it (doc/design.md §10): the text goes to
// a hidden temporary file in the target's directory (so rename() is atomic, never across file
// systems), which is flushed, made readable (0644) and renamed over the target; the directory is
// then synced so the rename is durable. On any failure the temporary file is removed and the
// target is left as it was.
#include <filesystem>
#include <string>

namespace flexloop::common {

/// @throws std::runtime_error "cannot write <file>: <step>: <system error>".
void write_text_atomically(const std::filesystem::path& file, const std::string& text);

/// Before a run whose results go to `file`: makes its directory and checks that a file can be
/// created there (creates and removes a hidden temporary one), so that a long run does not end
/// in a file it cannot write. The target itself is not touched.
/// @throws flexloop::InputError "<file>: cannot be written: <system error>" (exit 2).
void require_writable(const std::filesystem::path& file);

}  // namespace flexloop::common
