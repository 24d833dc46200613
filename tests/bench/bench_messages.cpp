// SPDX-License-Identifier: BSD-3-Clause
// Cost of encoding and decoding the per-cycle messages into preallocated buffers: a sample of the
// metrology frame's 6 + 6 channels (decoding into a message whose vectors already hold them, as
// the loop's inbox keeps them).
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <flexloop_msgs/sensor_sample_t.hpp>

#include "tests/support/messages.hpp"

static void BM_EncodeSensorSample(benchmark::State& state) {
  auto m = flexloop::test::sized_sample(6, 6);
  std::array<std::uint8_t, 256> buf{};
  for (auto _ : state) {
    ++m.seq;
    benchmark::DoNotOptimize(m.encode(buf.data(), 0, static_cast<int>(buf.size())));
  }
}
BENCHMARK(BM_EncodeSensorSample);

static void BM_DecodeSensorSample(benchmark::State& state) {
  auto m = flexloop::test::sized_sample(6, 6);
  std::array<std::uint8_t, 256> buf{};
  const int n = m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  for (auto _ : state) benchmark::DoNotOptimize(m.decode(buf.data(), 0, n));
}
BENCHMARK(BM_DecodeSensorSample);
