// SPDX-License-Identifier: BSD-3-Clause
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

/// The same, for a file too large to hold in memory first: written in pieces (each handed to the
/// kernel as it comes, its write-back to the disk started at once so that commit() waits only
/// for the last ones), then committed. Destroyed uncommitted (an error on the way), it removes
/// its temporary file and leaves the target as it was. Same errors as write_text_atomically().
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::filesystem::path file);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  void write(const char* data, std::size_t size);
  /// Flushed to the disk, readable (0644), renamed over the target, the rename made durable.
  void commit();

 private:
  [[noreturn]] void fail(const std::string& step);
  std::filesystem::path file_;
  std::string tmp_;
  int fd_ = -1;
};

/// Before a run whose results go to `file`: makes its directory and checks that a file can be
/// created there (creates and removes a hidden temporary one), so that a long run does not end
/// in a file it cannot write. The target itself is not touched; a folder in its place is refused.
/// @throws flexloop::InputError "<file>: cannot be written: <system error>" (exit 2).
void require_writable(const std::filesystem::path& file);

/// The same check without a trace on disk, for a command that may still refuse its input after
/// it (a refused command leaves nothing behind) or whose writer makes no folders: a folder in the
/// file's place is refused, and the nearest existing folder on the way must be writable.
/// @throws flexloop::InputError "<file>: cannot be written: <why>" (exit 2).
void require_creatable(const std::filesystem::path& file);

}  // namespace flexloop::common
