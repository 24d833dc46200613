// SPDX-License-Identifier: BSD-3-Clause
// rt/roudi_process.hpp against the real iox-roudi of Debian's iceoryx 2.0: the config it writes
// is the TOML it means, RouDi is ready when the constructor returns (an iceoryx runtime registers
// and moves a loaned chunk of the sized mempool through it), a second RouDi, a missing program
// and one that ends at once are clear errors naming iox-roudi, and no daemon, /dev/shm segment,
// socket or lock file is left behind -- after a stop, after RouDi was killed, and after its
// owner died. iceoryx 2.0 has one RouDi per host: these cases run serialised (RESOURCE_LOCK).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <catch2/catch.hpp>

#include <toml++/toml.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iceoryx_hoofs/log/logmanager.hpp>
#include <iceoryx_hoofs/platform/platform_settings.hpp>
#include <iceoryx_posh/iceoryx_posh_types.hpp>
#include <iceoryx_posh/popo/untyped_publisher.hpp>
#include <iceoryx_posh/popo/untyped_subscriber.hpp>
#include <iceoryx_posh/runtime/posh_runtime.hpp>
#include <set>
#include <string>

#include "rt/monotonic_time.hpp"
#include "rt/reap_child.hpp"
#include "rt/roudi_process.hpp"
#include "tests/iceoryx/child_outcome.hpp"
#include "tests/support/dev_shm.hpp"

using namespace flexloop::rt;
using flexloop::test::dev_shm_entries;

namespace {

// The config folders RoudiProcess makes under $TMPDIR or /tmp.
std::set<std::string> flexloop_roudi_folders() {
  const char* tmp = std::getenv("TMPDIR");
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(tmp && *tmp ? tmp : "/tmp"))
    if (e.path().filename().string().rfind("flexloop-roudi-", 0) == 0)
      names.insert(e.path().filename().string());
  return names;
}

bool exists(const char* path) {
  return std::filesystem::exists(path);
}

// Nothing of a RouDi on this host: no lock holder, no socket, no lock files, no segment.
void check_nothing_left(const std::set<std::string>& shm_before) {
  CHECK_FALSE(running_roudi_pid().has_value());
  CHECK_FALSE(exists(kRoudiSocket));
  CHECK_FALSE(exists(kRoudiSocketLock));
  CHECK_FALSE(exists(kRoudiLockFile));
  CHECK(dev_shm_entries() == shm_before);
}

bool process_exists(pid_t pid) {
  return kill(pid, 0) == 0 || errno != ESRCH;
}

// Sends `bytes` bytes through a loaned chunk to a subscriber of the same process and compares
// them. 0: equal; 2: no subscriber matched; 3: no chunk; 4: nothing received; 5: bytes differ.
int send_through_roudi(std::uint32_t bytes) {
  const iox::capro::ServiceDescription service{"flexloop", "probe", "bytes"};
  iox::popo::UntypedSubscriber sub(service);
  iox::popo::UntypedPublisher pub(service);
  const std::int64_t give_up = monotonic_now_ns() + 3 * kNsPerSecond;
  while (!pub.hasSubscribers())
    if (monotonic_now_ns() > give_up) return 2;
  std::string sent(bytes, '\0');
  for (std::uint32_t i = 0; i < bytes; ++i) sent[i] = static_cast<char>(i * 7 + 1);
  void* chunk = nullptr;
  pub.loan(bytes).and_then([&](void* p) { chunk = p; });
  if (!chunk) return 3;
  std::memcpy(chunk, sent.data(), bytes);
  pub.publish(chunk);
  const void* got = nullptr;
  while (!got && monotonic_now_ns() < give_up) sub.take().and_then([&](const void* p) { got = p; });
  if (!got) return 4;
  const bool equal = std::memcmp(got, sent.data(), bytes) == 0;
  sub.release(got);
  return equal ? 0 : 5;
}

// In a child: register with RouDi and send_through_roudi().
int run_probe(std::uint32_t bytes) {
  return flexloop::test::outcome_in_child(
      [bytes] {
        iox::log::LogManager::GetLogManager().SetDefaultLogLevel(iox::log::LogLevel::kWarn);
        iox::runtime::PoshRuntime::initRuntime("flexloop_roudi_probe");
        return send_through_roudi(bytes);
      },
      15 * kNsPerSecond);
}

}  // namespace

TEST_CASE("roudi: the fixed names are iceoryx 2.0's own") {
  using namespace iox;
  CHECK(std::string(platform::IOX_LOCK_FILE_PATH_PREFIX) + roudi::ROUDI_LOCK_NAME + ".lock" ==
        kRoudiLockFile);
  CHECK(std::string(platform::IOX_UDS_SOCKET_PATH_PREFIX) + roudi::IPC_CHANNEL_ROUDI_NAME ==
        kRoudiSocket);
  CHECK(std::string(kRoudiSocket) + ".lock" == kRoudiSocketLock);
  CHECK(std::string(roudi::SHM_NAME) == kRoudiManagementSegment);
}

TEST_CASE("roudi: the config is one segment with the mempools asked for, bad pools refused") {
  const auto pools = mempools_for_messages(400, 16);
  REQUIRE(pools.size() == 1);
  CHECK(pools[0].chunk_bytes == 448);  // 400 rounded up to whole 64-byte lines
  CHECK(pools[0].count == 16);
  const toml::table t = toml::parse(roudi_config_toml({{64, 10}, {1024, 3}}));
  CHECK(t["general"]["version"].value<int>() == 1);
  const toml::array* seg = t["segment"].as_array();
  REQUIRE(seg);
  REQUIRE(seg->size() == 1);
  const toml::array* mp = (*seg->get_as<toml::table>(0))["mempool"].as_array();
  REQUIRE(mp);
  REQUIRE(mp->size() == 2);
  CHECK((*mp->get_as<toml::table>(1))["size"].value<int>() == 1024);
  CHECK((*mp->get_as<toml::table>(1))["count"].value<int>() == 3);
  CHECK_THROWS_AS(roudi_config_toml({}), std::invalid_argument);
  CHECK_THROWS_AS(roudi_config_toml({{100, 1}}), std::invalid_argument);  // not a multiple of 8
  CHECK_THROWS_AS(roudi_config_toml({{64, 0}}), std::invalid_argument);
}

TEST_CASE(
    "roudi: ready when started (a runtime moves a chunk), a second one refused, stop "
    "leaves nothing") {
  const auto shm_before = dev_shm_entries();
  REQUIRE_FALSE(running_roudi_pid().has_value());
  RoudiOptions o;
  o.mempools = mempools_for_messages(400, 16);
  RoudiProcess roudi(o);
  CHECK(roudi.alive());
  CHECK(running_roudi_pid() == roudi.pid());
  CHECK(getpgid(roudi.pid()) == roudi.pid());  // a process group of its own
  CHECK(dev_shm_entries().count(kRoudiManagementSegment) == 1);
  CHECK(run_probe(400) == 0);

  try {
    RoudiProcess second(o);
    FAIL("a second RouDi started");
  } catch (const RoudiError& e) {
    CHECK_THAT(e.what(), Catch::Contains("iox-roudi already runs") &&
                             Catch::Contains("pid " + std::to_string(roudi.pid())));
  }
  const pid_t pid = roudi.pid();
  roudi.stop();
  CHECK_FALSE(roudi.alive());
  CHECK_THAT(roudi.describe(), Catch::Contains("exited with status 0"));
  CHECK_FALSE(process_exists(pid));
  check_nothing_left(shm_before);
}

TEST_CASE("roudi: a missing program and one that ends at once are errors naming it") {
  const auto shm_before = dev_shm_entries();
  RoudiOptions o;
  o.executable = "/nonexistent/iox-roudi";
  CHECK_THROWS_WITH(RoudiProcess(o), Catch::Contains("iox-roudi") &&
                                         Catch::Contains("No such file or directory") &&
                                         Catch::Contains("package iceoryx"));
  o.executable = "false";  // starts, says nothing, exits 1
  CHECK_THROWS_WITH(
      RoudiProcess(o),
      Catch::Contains("iox-roudi") && Catch::Contains("exited with status 1 before it was ready"));
  check_nothing_left(shm_before);
}

TEST_CASE("roudi: killed from outside, it is reported so and its leftovers are removed") {
  const auto shm_before = dev_shm_entries();
  RoudiProcess roudi(RoudiOptions{});
  REQUIRE(kill(roudi.pid(), SIGKILL) == 0);
  const std::int64_t give_up = monotonic_now_ns() + 2 * kNsPerSecond;
  while (roudi.alive() && monotonic_now_ns() < give_up) usleep(1000);
  CHECK_FALSE(roudi.alive());
  CHECK_THAT(roudi.describe(), Catch::Contains("killed by signal 9"));
  CHECK(dev_shm_entries().count(kRoudiManagementSegment) == 1);  // what a killed RouDi leaves
  roudi.stop();
  check_nothing_left(shm_before);
}

TEST_CASE("roudi: when its owner dies without stopping it, RouDi ends and cleans up itself") {
  const auto shm_before = dev_shm_entries();
  const auto folders_before = flexloop_roudi_folders();
  int ready[2];
  REQUIRE(pipe(ready) == 0);
  const pid_t owner = fork();
  if (owner == 0) {
    RoudiProcess roudi(RoudiOptions{});
    const pid_t pid = roudi.pid();
    (void)!write(ready[1], &pid, sizeof pid);
    raise(SIGKILL);  // a crash: no destructor runs
  }
  close(ready[1]);
  pid_t roudi_pid = 0;
  REQUIRE(read(ready[0], &roudi_pid, sizeof roudi_pid) == sizeof roudi_pid);
  close(ready[0]);
  reap_child(owner, 5 * kNsPerSecond);
  const std::int64_t give_up = monotonic_now_ns() + 5 * kNsPerSecond;
  while (process_exists(roudi_pid) && monotonic_now_ns() < give_up) usleep(2000);
  CHECK_FALSE(process_exists(roudi_pid));
  check_nothing_left(shm_before);
  CHECK(flexloop_roudi_folders() == folders_before);  // its config and log went when ready
}
