// SPDX-License-Identifier: BSD-3-Clause
// A controller FMU's archive is data until proven otherwise (issue 46, doc/controllers.md
// "Refusals: the archive and its description"): each archive here is the PI fixture's parts with
// one bad entry added, written by the test with libzip into a private folder. Each refusal is a
// flexloop::InputError (exit 2 on the command line) naming the FMU file and the entry, nothing is
// written outside the unpack folder, and the private TMPDIR the loader unpacks into is empty
// afterwards.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "artefact/loop_artefact.hpp"
#include "common/input_error.hpp"
#include "controller/fmu/fmu_archive.hpp"
#include "offline/scene/loop_input.hpp"
#include "tests/fmu/fmu_archive_fixture.hpp"

namespace fs = std::filesystem;
using flexloop::controller::fmu::FmuArchiveLimits;
using flexloop::controller::fmu::FmuDirectory;
using flexloop::test::PrivateTmpdir;
using flexloop::test::TestZipEntry;

namespace {

// The archive `name` in the test's inputs: the PI fixture and `more`.
std::string archive_with(const PrivateTmpdir& t, const std::string& name,
                         const std::vector<TestZipEntry>& more) {
  const fs::path f = t.inputs / name;
  flexloop::test::write_test_zip(f, flexloop::test::pi_fixture_and(more));
  return f.string();
}

// Unpacks `fmu`; the InputError's message, or "" when it unpacked.
std::string unpack_refusal(const std::string& fmu, const FmuArchiveLimits& limits = {}) {
  return flexloop::test::input_error_of([&] { const FmuDirectory d(fmu, limits); });
}

// Flips the first byte of `marker` in `file` (the stored data of an entry that holds it).
void flip_byte_of(const fs::path& file, const std::string& marker) {
  std::string bytes = flexloop::test::read_bytes(file);
  const auto at = bytes.find(marker);
  REQUIRE(at != std::string::npos);
  REQUIRE(bytes.find(marker, at + 1) == std::string::npos);
  bytes[at] ^= 0x20;
  std::ofstream(file, std::ios::binary) << bytes;
}

// Sets the uncompressed size the local and the central header declare for the one entry of
// `size` bytes named `name` (zip APPNOTE 4.3.7, 4.3.12: at offset 22 and 24, little-endian).
void declare_size(const fs::path& file, const std::string& name, std::uint32_t size,
                  std::uint32_t declared) {
  std::string bytes = flexloop::test::read_bytes(file);
  const auto put = [&](std::size_t at) {
    std::uint32_t old = 0;
    for (int k = 0; k < 4; ++k)
      old |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + k])) << (8 * k);
    REQUIRE(old == size);
    for (int k = 0; k < 4; ++k) bytes[at + k] = static_cast<char>((declared >> (8 * k)) & 0xff);
  };
  int patched = 0;
  for (const auto& [signature, size_at, name_at] :
       {std::tuple{std::string("PK\x03\x04", 4), 22, 30},
        std::tuple{std::string("PK\x01\x02", 4), 24, 46}})
    for (auto at = bytes.find(signature); at != std::string::npos;
         at = bytes.find(signature, at + 1))
      if (bytes.compare(at + name_at, name.size(), name) == 0) {
        put(at + size_at);
        ++patched;
      }
  REQUIRE(patched == 2);
  std::ofstream(file, std::ios::binary) << bytes;
}

}  // namespace

TEST_CASE("An entry that climbs out of the archive is refused and nothing is written",
          "[fmu][archive]") {
  PrivateTmpdir t;
  for (const std::string name : {"../escaped.txt", "resources/../../escaped.txt"}) {
    const auto f = archive_with(t, "climbs.fmu", {{name, "outside\n"}});
    CHECK(unpack_refusal(f) ==
          f + ": entry '" + name + "' climbs out of the archive ('..' in its path)");
    CHECK_FALSE(fs::exists(t.tmp / "escaped.txt"));
    CHECK_FALSE(fs::exists(t.root.path / "escaped.txt"));
    CHECK(t.left_behind().empty());
  }
}

TEST_CASE("An absolute entry is refused and nothing is written", "[fmu][archive]") {
  PrivateTmpdir t;
  const std::string name = (t.root.path / "absolute.txt").string();
  const auto f = archive_with(t, "absolute.fmu", {{name, "anywhere\n"}});
  CHECK(unpack_refusal(f) ==
        f + ": entry '" + name +
            "' is an absolute path: an FMU's entries are relative to the archive");
  CHECK_FALSE(fs::exists(name));
  CHECK(t.left_behind().empty());
}

TEST_CASE("A symbolic link or a special file in the archive is refused", "[fmu][archive]") {
  PrivateTmpdir t;
  // A link's entry holds its target: unpacked as a link it would lead out of the folder.
  const auto link = archive_with(t, "link.fmu", {{"resources/passwd", "/etc/passwd", S_IFLNK}});
  CHECK(unpack_refusal(link) == link +
                                    ": entry 'resources/passwd' is a symbolic link: flexloop "
                                    "unpacks regular files and folders only");
  const auto fifo = archive_with(t, "fifo.fmu", {{"resources/pipe", "", S_IFIFO}});
  CHECK_THAT(unpack_refusal(fifo),
             Catch::StartsWith(fifo + ": entry 'resources/pipe' is a special file"));
  // The same entries as regular files (the mode a Unix zip tool records) unpack.
  const auto regular =
      archive_with(t, "regular.fmu", {{"resources/passwd", "/etc/passwd", S_IFREG}});
  CHECK(unpack_refusal(regular).empty());
  CHECK(t.left_behind().empty());
}

TEST_CASE("Two entries that land on the same file are refused", "[fmu][archive]") {
  PrivateTmpdir t;
  const auto f = archive_with(t, "twice.fmu",
                              {{"resources/a.txt", "first\n"}, {"resources/./a.txt", "second\n"}});
  CHECK(unpack_refusal(f) == f + ": entry 'resources/./a.txt' appears twice in the archive");
  CHECK(t.left_behind().empty());
}

TEST_CASE("More entries than the cap are refused, naming the first beyond it", "[fmu][archive]") {
  PrivateTmpdir t;
  const auto cap = FmuArchiveLimits::kDefaultMaxEntries;  // 10 000
  std::vector<TestZipEntry> many;
  for (std::uint64_t i = 0; i < cap; ++i) many.push_back({"resources/" + std::to_string(i), ""});
  const auto f = archive_with(t, "many.fmu", many);  // 2 + 10 000 entries
  CHECK(unpack_refusal(f) == f + ": entry 'resources/9998' is entry 10001 of 10002: flexloop "
                                 "unpacks at most 10000 entries of an FMU");
  CHECK(t.left_behind().empty());
}

TEST_CASE("A zip bomb beyond the scene's fmu_max_unpacked_mb is refused before it is written",
          "[fmu][archive]") {
  PrivateTmpdir t;
  // 4 MiB of zeros deflate to a few kB.
  const std::string zeros(4u << 20, '\0');
  const auto f = archive_with(t, "bomb.fmu", {{"resources/zeros.bin", zeros}});
  REQUIRE(fs::file_size(f) < 100'000);
  // The cart with the fixture as its controller and a cap of 1 MB, through the artefact's JSON.
  std::string scene = flexloop::test::read_bytes("tools/scenes/cart.toml");
  const auto controller = scene.find("[controller]"), after = scene.find("[discretisation]");
  REQUIRE((controller != std::string::npos && after != std::string::npos));
  scene.replace(controller, after - controller,
                "[controller]\ntype = \"fmu\"\nfile = \"bomb.fmu\"\nfmu_max_unpacked_mb = 1\n"
                "[controller.map.sensors]\n\"stress:e1.spring\" = \"y1\"\n"
                "[controller.map.actuators]\n\"stress:e1.spring\" = \"u1\"\n\n");
  const std::string model = "\"../models/cart_piezo.toml\"";
  scene.replace(scene.find(model), model.size(),
                "\"" + fs::absolute("tools/models/cart_piezo.toml").string() + "\"");
  std::ofstream(t.inputs / "cart_fmu.toml") << scene;
  const auto built = flexloop::scene::load_loop((t.inputs / "cart_fmu.toml").string());
  CHECK(built.fmu.max_unpacked_mb == 1);
  flexloop::artefact::write_loop_artefact(t.inputs / "cart_fmu.json", built);
  const auto read = flexloop::artefact::read_loop_artefact(t.inputs / "cart_fmu.json");
  REQUIRE(read.fmu.max_unpacked_mb == 1);
  const auto limits = flexloop::controller::fmu::fmu_archive_limits(read.fmu.max_unpacked_mb);
  std::uint64_t before = 0;  // the fixture's two entries come first
  for (const auto& [name, bytes] : flexloop::test::pi_fmu_entries()) before += bytes.size();
  CHECK(unpack_refusal(read.fmu.file, limits) ==
        f + ": entry 'resources/zeros.bin' takes the unpacked size beyond the cap of 1 MB (" +
            std::to_string(before) +
            " bytes before it, 4194304 in it; the scene's [controller] fmu_max_unpacked_mb raises "
            "the cap)");
  CHECK(t.left_behind().empty());
  // The artefact's reader keeps the cap in 1 .. 2^20 MB.
  std::string json = flexloop::test::read_bytes(t.inputs / "cart_fmu.json");
  const std::string cap_key = "\"max_unpacked_mb\": 1";
  REQUIRE(json.find(cap_key) != std::string::npos);
  json.replace(json.find(cap_key), cap_key.size(), "\"max_unpacked_mb\": 0");
  std::ofstream(t.inputs / "bad_cap.json") << json;
  CHECK_THAT(flexloop::test::input_error_of(
                 [&] { (void)flexloop::artefact::read_loop_artefact(t.inputs / "bad_cap.json"); }),
             Catch::StartsWith((t.inputs / "bad_cap.json").string()) &&
                 Catch::Contains("max_unpacked_mb"));
  // Under the default cap (1 GiB) the same archive unpacks, and its folder goes with it.
  CHECK(unpack_refusal(f).empty());
  CHECK(t.left_behind().empty());
  // A cap that is not a whole number of MB in 1 .. 2^20 is the scene's error, at its line.
  for (const std::string bad : {"0", "1.5", "1048577", "\"1\""}) {
    std::string text = scene;
    const std::string key = "fmu_max_unpacked_mb = 1";
    text.replace(text.find(key), key.size(), "fmu_max_unpacked_mb = " + bad);
    std::ofstream(t.inputs / "bad_cap.toml") << text;
    CHECK_THAT(flexloop::test::input_error_of(
                   [&] { (void)flexloop::scene::load_loop((t.inputs / "bad_cap.toml").string()); }),
               Catch::Contains("bad_cap.toml:") &&
                   Catch::EndsWith("[controller]: 'fmu_max_unpacked_mb' must be a whole "
                                   "number of MB, 1 .. 1048576"));
  }
}

TEST_CASE("An entry whose data does not read back is refused: CRC, short, long", "[fmu][archive]") {
  PrivateTmpdir t;
  const std::string data = "flexloop resource data, stored uncompressed\n";
  const TestZipEntry stored{"resources/data.txt", data, 0, true};
  SECTION("a flipped byte: the CRC differs") {
    const auto f = archive_with(t, "crc.fmu", {stored});
    flip_byte_of(f, "flexloop resource");
    CHECK(unpack_refusal(f) == f + ": entry 'resources/data.txt' cannot be read (CRC error)");
  }
  // libzip 1.7 finds the short entry itself ("Zip archive inconsistent"); the loader's own count
  // finds the long one.
  SECTION("the archive declares more bytes than the entry holds") {
    const auto f = archive_with(t, "short.fmu", {stored});
    declare_size(f, stored.name, static_cast<std::uint32_t>(data.size()),
                 static_cast<std::uint32_t>(data.size() + 100));
    CHECK_THAT(unpack_refusal(f),
               Catch::StartsWith(f + ": entry 'resources/data.txt' ") &&
                   (Catch::Contains("is truncated: 44 of the 144 bytes the archive declares") ||
                    Catch::Contains("cannot be read")));
  }
  SECTION("the archive declares fewer bytes than the entry holds") {
    const auto f = archive_with(t, "long.fmu", {stored});
    declare_size(f, stored.name, static_cast<std::uint32_t>(data.size()), 10);
    CHECK_THAT(unpack_refusal(f),
               Catch::StartsWith(f + ": entry 'resources/data.txt' ") &&
                   (Catch::Contains("holds more than the 10 bytes the archive declares") ||
                    Catch::Contains("cannot be read")));
  }
  CHECK(t.left_behind().empty());
}
