// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the archive and description refusal tests share (tests/fmu/test_fmu_archive.cpp,
// test_fmu_description.cpp): a private TMPDIR for the loader to unpack into, so that a test can
// see that a refusal left nothing there, and zip archives written entry by entry (compression,
// Unix file type), from the PI fixture's parts or made up.
#include <sys/stat.h>
#include <zip.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "tests/fmu/fmu_fixture.hpp"

namespace flexloop::test {

/// TMPDIR set to an empty folder of its own for the scope (std::filesystem::temp_directory_path,
/// where the loader unpacks, reads it), with a folder beside it for the test's inputs.
struct PrivateTmpdir {
  TemporaryDirectory root;  // made under the TMPDIR the test started with
  std::filesystem::path tmp = root.path / "tmp", inputs = root.path / "inputs";
  std::optional<std::string> previous;

  PrivateTmpdir() {
    std::filesystem::create_directory(tmp);
    std::filesystem::create_directory(inputs);
    if (const char* t = std::getenv("TMPDIR")) previous = t;
    setenv("TMPDIR", tmp.c_str(), 1);
  }
  ~PrivateTmpdir() {
    if (previous)
      setenv("TMPDIR", previous->c_str(), 1);
    else
      unsetenv("TMPDIR");
  }
  PrivateTmpdir(const PrivateTmpdir&) = delete;
  PrivateTmpdir& operator=(const PrivateTmpdir&) = delete;

  /// The names in the private TMPDIR: empty once every unpacked folder has gone.
  std::vector<std::string> left_behind() const {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(tmp))
      names.push_back(e.path().filename().string());
    return names;
  }
};

/// The message of the flexloop::InputError `f` throws (exit 2 on the command line); "" when it
/// returns. Any other exception goes on: the test fails on it.
template <class F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "";
}

/// One entry of a test archive: `unix_type` (S_IFLNK, S_IFREG, ...; 0: none recorded) goes to the
/// high 16 bits of the external attributes as a Unix zip tool writes it; `stored`: no compression.
struct TestZipEntry {
  std::string name, bytes;
  std::uint32_t unix_type = 0;
  bool stored = false;
};

/// Writes `entries` in this order to `path` (libzip, as a user's tool would).
inline void write_test_zip(const std::filesystem::path& path,
                           const std::vector<TestZipEntry>& entries) {
  int code = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &code);
  if (!z) throw std::runtime_error("write_test_zip: cannot create " + path.string());
  const auto fail = [&](const std::string& why) {
    zip_discard(z);
    throw std::runtime_error("write_test_zip: " + why);
  };
  for (const auto& e : entries) {
    zip_source_t* src = zip_source_buffer(z, e.bytes.data(), e.bytes.size(), 0);
    const zip_int64_t i = src ? zip_file_add(z, e.name.c_str(), src, 0) : -1;
    if (i < 0) {
      zip_source_free(src);
      fail("cannot add " + e.name);
    }
    const auto index = static_cast<zip_uint64_t>(i);
    if (e.stored && zip_set_file_compression(z, index, ZIP_CM_STORE, 0) != 0)
      fail("cannot store " + e.name);
    if (e.unix_type && zip_file_set_external_attributes(z, index, 0, ZIP_OPSYS_UNIX,
                                                        (e.unix_type | 0777u) << 16) != 0)
      fail("cannot set the attributes of " + e.name);
  }
  if (zip_close(z) != 0) throw std::runtime_error("write_test_zip: cannot write " + path.string());
}

/// The PI fixture's entries (modelDescription.xml, its library) followed by `more`.
inline std::vector<TestZipEntry> pi_fixture_and(const std::vector<TestZipEntry>& more) {
  std::vector<TestZipEntry> entries;
  for (const auto& [name, bytes] : pi_fmu_entries()) entries.push_back({name, bytes});
  entries.insert(entries.end(), more.begin(), more.end());
  return entries;
}

}  // namespace flexloop::test
