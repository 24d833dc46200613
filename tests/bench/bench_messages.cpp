// Cost of encoding and decoding the per-cycle messages into preallocated buffers.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <flexloop_msgs/sensor_sample_t.hpp>

static void BM_EncodeSensorSample(benchmark::State& state) {
  flexloop_msgs::sensor_sample_t m{};
  std::array<std::uint8_t, 256> buf{};
  for (auto _ : state) {
    ++m.seq;
    benchmark::DoNotOptimize(m.encode(buf.data(), 0, static_cast<int>(buf.size())));
  }
}
BENCHMARK(BM_EncodeSensorSample);

static void BM_DecodeSensorSample(benchmark::State& state) {
  flexloop_msgs::sensor_sample_t m{};
  std::array<std::uint8_t, 256> buf{};
  const int n = m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  for (auto _ : state) benchmark::DoNotOptimize(m.decode(buf.data(), 0, n));
}
BENCHMARK(BM_DecodeSensorSample);
