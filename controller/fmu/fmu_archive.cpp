// SPDX-License-Identifier: BSD-3-Clause
#include "controller/fmu/fmu_archive.hpp"

#include <sys/stat.h>
#include <zip.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <system_error>
#include <vector>

#include "common/input_error.hpp"

namespace flexloop::controller::fmu {

namespace {

namespace fs = std::filesystem;

using Archive = std::unique_ptr<zip_t, decltype(&zip_discard)>;
using ArchiveFile = std::unique_ptr<zip_file_t, decltype(&zip_fclose)>;

// libzip's text for one of its error codes.
std::string zip_reason(int code) {
  zip_error_t e;
  zip_error_init_with_code(&e, code);
  std::string why = zip_error_strerror(&e);
  zip_error_fini(&e);
  return why;
}

[[noreturn]] void refuse(const std::string& fmu, const std::string& entry, const std::string& why) {
  throw common::InputError(fmu, "entry '" + entry + "' " + why);
}

// An entry the checks passed: where it goes and how much it holds.
struct Entry {
  zip_uint64_t index = 0;
  std::string name;
  fs::path relative;  // inside the directory: relative, no ".." component
  bool directory = false;
  zip_uint64_t size = 0;  // uncompressed, as the archive declares it
};

// The entry's name as a path inside the directory, or a refusal: an absolute name, or one with a
// ".." component, would write outside it (a "zip slip").
fs::path relative_path(const std::string& fmu, const std::string& name) {
  const fs::path p(name);
  if (name.empty()) refuse(fmu, name, "has an empty name");
  if (p.is_absolute() || p.has_root_name())
    refuse(fmu, name, "is an absolute path: an FMU's entries are relative to the archive");
  for (const auto& part : p)
    if (part == "..") refuse(fmu, name, "climbs out of the archive ('..' in its path)");
  return p.lexically_normal();
}

// A Unix-made zip keeps the file's st_mode in the high 16 bits of the external attributes:
// unpacking makes regular files and folders only, so a link or a special file is refused.
void check_type(zip_t* z, zip_uint64_t i, const std::string& fmu, const std::string& name) {
  zip_uint8_t system = 0;
  zip_uint32_t attributes = 0;
  if (zip_file_get_external_attributes(z, i, 0, &system, &attributes) != 0)
    refuse(fmu, name, "has unreadable attributes (" + std::string(zip_strerror(z)) + ")");
  if (system != ZIP_OPSYS_UNIX) return;
  const auto type = static_cast<mode_t>(attributes >> 16) & S_IFMT;
  if (type == S_IFLNK)
    refuse(fmu, name, "is a symbolic link: flexloop unpacks regular files and folders only");
  if (type != 0 && type != S_IFREG && type != S_IFDIR)
    refuse(fmu, name,
           "is a special file (device, pipe or socket): flexloop unpacks regular files and "
           "folders only");
}

// Every entry checked before anything is written: names, types, their number and declared size.
std::vector<Entry> checked_entries(zip_t* z, const std::string& fmu, const FmuArchiveLimits& cap) {
  const zip_int64_t n = zip_get_num_entries(z, 0);
  if (n < 0) throw common::InputError(fmu, "cannot list the archive's entries");
  const std::uint64_t cap_bytes = cap.max_unpacked_mb << 20;
  std::vector<Entry> entries;
  std::uint64_t total = 0;
  for (zip_uint64_t i = 0; i < static_cast<zip_uint64_t>(n); ++i) {
    const char* raw = zip_get_name(z, i, 0);
    if (!raw)
      throw common::InputError(fmu,
                               "entry " + std::to_string(i + 1) + " of the archive has no name");
    const std::string name(raw);
    if (i >= cap.max_entries)
      refuse(fmu, name,
             "is entry " + std::to_string(i + 1) + " of " + std::to_string(n) +
                 ": flexloop unpacks at most " + std::to_string(cap.max_entries) +
                 " entries of an FMU");
    Entry e{i, name, relative_path(fmu, name), name.ends_with('/'), 0};
    check_type(z, i, fmu, name);
    zip_stat_t st;
    if (zip_stat_index(z, i, 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
      refuse(fmu, name, "has no readable size (" + std::string(zip_strerror(z)) + ")");
    e.size = st.size;
    if (e.directory && e.size != 0) refuse(fmu, name, "is a folder that holds data");
    if (e.size > cap_bytes - total)
      refuse(fmu, name,
             "takes the unpacked size beyond the cap of " + std::to_string(cap.max_unpacked_mb) +
                 " MB (" + std::to_string(total) + " bytes before it, " + std::to_string(e.size) +
                 " in it; the scene's [controller] fmu_max_unpacked_mb raises the cap)");
    total += e.size;
    entries.push_back(std::move(e));
  }
  return entries;
}

// Copies one file entry to `target`: exactly its declared size, or a refusal. libzip checks the
// CRC when the data ends: zip_fread or zip_fclose then reports it.
void extract_file(zip_t* z, const Entry& e, const fs::path& target, const std::string& fmu) {
  if (fs::symlink_status(target).type() != fs::file_type::not_found)
    refuse(fmu, e.name, "appears twice in the archive");
  fs::create_directories(target.parent_path());
  ArchiveFile in(zip_fopen_index(z, e.index, 0), &zip_fclose);
  if (!in) refuse(fmu, e.name, "cannot be opened (" + std::string(zip_strerror(z)) + ")");
  std::ofstream out(target, std::ios::binary);
  if (!out) refuse(fmu, e.name, "cannot be written to " + target.string());
  std::vector<char> buffer(1 << 16);
  zip_uint64_t got = 0;
  for (;;) {
    // One byte beyond the declared size tells an entry that holds more.
    const zip_uint64_t want = std::min<zip_uint64_t>(buffer.size(), e.size + 1 - got);
    const zip_int64_t n = zip_fread(in.get(), buffer.data(), want);
    if (n < 0)
      refuse(fmu, e.name, "cannot be read (" + std::string(zip_file_strerror(in.get())) + ")");
    if (n == 0) break;
    got += static_cast<zip_uint64_t>(n);
    if (got > e.size)
      refuse(fmu, e.name,
             "holds more than the " + std::to_string(e.size) + " bytes the archive declares");
    out.write(buffer.data(), n);
  }
  if (got != e.size)
    refuse(fmu, e.name,
           "is truncated: " + std::to_string(got) + " of the " + std::to_string(e.size) +
               " bytes the archive declares");
  if (const int code = zip_fclose(in.release()); code != 0)
    refuse(fmu, e.name, "cannot be read (" + zip_reason(code) + ")");
  out.close();
  if (!out) refuse(fmu, e.name, "cannot be written to " + target.string() + " (disk full?)");
}

void extract(zip_t* z, const std::vector<Entry>& entries, const fs::path& dir,
             const std::string& fmu) {
  for (const Entry& e : entries) {
    const fs::path target = dir / e.relative;
    try {
      if (e.directory)
        fs::create_directories(target);
      else
        extract_file(z, e, target, fmu);
    } catch (const fs::filesystem_error& error) {
      refuse(fmu, e.name, "cannot be unpacked (" + error.code().message() + ")");
    }
  }
}

Archive open_archive(const std::string& fmu) {
  int code = 0;
  zip_t* z = zip_open(fmu.c_str(), ZIP_RDONLY, &code);
  if (!z)
    throw common::InputError(
        fmu, "not an FMU: cannot open it as a zip archive (" + zip_reason(code) + ")");
  return Archive(z, &zip_discard);
}

}  // namespace

FmuArchiveLimits fmu_archive_limits(std::optional<long> max_unpacked_mb) {
  FmuArchiveLimits limits;
  if (max_unpacked_mb) limits.max_unpacked_mb = static_cast<std::uint64_t>(*max_unpacked_mb);
  return limits;
}

FmuDirectory::PrivateFolder::PrivateFolder(const std::string& fmu) {
  std::string pattern = (fs::temp_directory_path() / "flexloop-fmu-XXXXXX").string();
  if (!mkdtemp(pattern.data()))
    throw common::InputError(fmu, "cannot create a temporary directory to unpack it into");
  path = pattern;
}

FmuDirectory::PrivateFolder::~PrivateFolder() {
  std::error_code ignored;  // nothing to do about a directory that will not go
  fs::remove_all(path, ignored);
}

FmuDirectory::FmuDirectory(const std::string& fmu, const FmuArchiveLimits& limits) : dir_(fmu) {
  const Archive archive = open_archive(fmu);
  extract(archive.get(), checked_entries(archive.get(), fmu, limits), dir_.path, fmu);
}

}  // namespace flexloop::controller::fmu
