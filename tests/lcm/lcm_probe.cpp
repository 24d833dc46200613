// SPDX-License-Identifier: BSD-3-Clause
// lcm_probe: the two ends of the cross-process LCM test. It refuses to run outside the private
// loopback-only namespace (tools/netns-run), so test traffic can never reach a real interface.
//
//   lcm_probe listen N TIMEOUT_MS   receive N sensor samples, check their contents, exit 0
//   lcm_probe publish N             publish N sensor samples (seq 0..N-1)
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <string>
#include <thread>
#include <vector>

#include "rt/loopback_guard.hpp"
#include "tests/support/messages.hpp"

namespace {

constexpr const char* kChannel = "FLEXLOOP_PROBE";

double expected_force(std::int64_t seq, int i) {
  return 0.5 * static_cast<double>(seq) + i;
}

struct Listener {
  int received = 0;
  int wrong = 0;
  void on_sample(const lcm::ReceiveBuffer*, const std::string&,
                 const flexloop_msgs::sensor_sample_t* m) {
    for (int i = 0; i < 6; ++i)
      if (m->n_sensors != 6 || m->sensors[i] != expected_force(m->seq, i)) ++wrong;
    ++received;
  }
};

int listen(int n, int timeout_ms) {
  lcm::LCM lcm(flexloop::rt::kPrivateLoopbackLcmUrl);
  if (!lcm.good()) return std::fprintf(stderr, "lcm_probe: LCM init failed\n"), 1;
  Listener listener;
  lcm.subscribe(kChannel, &Listener::on_sample, &listener);
  std::printf("ready\n");
  std::fflush(stdout);
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (listener.received < n && std::chrono::steady_clock::now() < end) lcm.handleTimeout(50);
  std::printf("received %d of %d, %d wrong values\n", listener.received, n, listener.wrong);
  return listener.received == n && listener.wrong == 0 ? 0 : 1;
}

int publish(int n) {
  lcm::LCM lcm(flexloop::rt::kPrivateLoopbackLcmUrl);
  if (!lcm.good()) return std::fprintf(stderr, "lcm_probe: LCM init failed\n"), 1;
  flexloop_msgs::sensor_sample_t m = flexloop::test::sized_sample();
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  for (int k = 0; k < n; ++k) {
    m.seq = k;
    for (int i = 0; i < 6; ++i) m.sensors[i] = expected_force(k, i);
    m.encode(buf.data(), 0, static_cast<int>(buf.size()));
    if (lcm.publish(kChannel, buf.data(), static_cast<unsigned>(buf.size())) != 0) return 1;
    std::this_thread::sleep_for(
        std::chrono::milliseconds(2));  // stay below the receive queue limit
  }
  std::printf("published %d\n", n);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 3)
      return std::fprintf(stderr, "usage: lcm_probe listen N TIMEOUT_MS | publish N\n"), 2;
    flexloop::rt::require_private_loopback_namespace("lcm_probe");
    const std::string mode = argv[1];
    const int n = std::atoi(argv[2]);
    if (mode == "listen" && argc >= 4) return listen(n, std::atoi(argv[3]));
    if (mode == "publish") return publish(n);
    return std::fprintf(stderr, "usage: lcm_probe listen N TIMEOUT_MS | publish N\n"), 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 3;
  }
}
