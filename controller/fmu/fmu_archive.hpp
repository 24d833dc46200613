// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// An FMU's archive unpacked into a private temporary directory (mkdtemp: mode 0700, a name no
// one else holds), removed with everything in it when the object goes. Start-up only.
//
// The archive is a user's file: data until proven otherwise (doc/controllers.md, "Refusals: the
// archive and its description"). Every entry is checked before anything is written: its name
// relative, without a ".." component; no symbolic link or other special file (a Unix-made zip
// keeps st_mode in the high 16 bits of the external attributes); at most
// FmuArchiveLimits::max_entries entries and max_unpacked_bytes declared in all. Each entry is
// then read to exactly its declared size (a read error, a short or a long entry and a bad CRC are
// refused), and a name that appears twice is refused. A refusal leaves nothing in the temporary
// folder.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace flexloop::controller::fmu {

/// The caps on what an archive may unpack to: a zip bomb (a small archive of a large, highly
/// compressible content) must not fill the temporary folder, often a RAM-backed tmpfs.
struct FmuArchiveLimits {
  /// An FMU is a description, binaries for a few platforms and perhaps sources, documentation and
  /// resources: tens to a few thousand entries; 10 000 leaves room and bounds the inodes.
  static constexpr std::uint64_t kDefaultMaxEntries = 10'000;
  /// Exported models with their solver, tables and binaries for several platforms reach a few
  /// hundred MB; 1 GiB leaves room and stays well inside a tmpfs on a machine that runs loops.
  static constexpr std::uint64_t kDefaultMaxUnpackedMb = 1024;

  std::uint64_t max_entries = kDefaultMaxEntries;
  std::uint64_t max_unpacked_mb = kDefaultMaxUnpackedMb;  ///< MB = 2^20 bytes
};

/// The limits a loop artefact's (its scene's) `fmu_max_unpacked_mb` sets
/// (artefact::FmuParameters::max_unpacked_mb); none: the defaults.
FmuArchiveLimits fmu_archive_limits(std::optional<long> max_unpacked_mb);

class FmuDirectory {
 public:
  /// @throws flexloop::InputError naming `fmu` (and the entry) when it cannot be read, is not a
  /// zip archive, or an entry is refused (see the top) or cannot be extracted.
  explicit FmuDirectory(const std::string& fmu, const FmuArchiveLimits& limits = {});
  FmuDirectory(const FmuDirectory&) = delete;
  FmuDirectory& operator=(const FmuDirectory&) = delete;

  const std::filesystem::path& path() const { return dir_.path; }

 private:
  /// The directory mkdtemp made, removed with everything in it when this goes: also when the
  /// unpacking throws, as a member constructed before FmuDirectory's body runs.
  struct PrivateFolder {
    std::filesystem::path path;
    explicit PrivateFolder(const std::string& fmu);
    ~PrivateFolder();
    PrivateFolder(const PrivateFolder&) = delete;
    PrivateFolder& operator=(const PrivateFolder&) = delete;
  };
  PrivateFolder dir_;
};

}  // namespace flexloop::controller::fmu
