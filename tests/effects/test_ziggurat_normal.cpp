// SPDX-License-Identifier: BSD-3-Clause
// The ziggurat normal source (plant/runtime/effects/ziggurat_normal.hpp): its table against the
// definition (equal layer areas, the exact tail area), its draws against the normal distribution
// (Kolmogorov-Smirnov, tail probabilities from erfc), and the side-by-side lanes against the same
// engines drawing alone, bit for bit, through the rare paths too.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "plant/runtime/effects/gaussian_noise.hpp"
#include "plant/runtime/effects/ziggurat_normal.hpp"

using namespace flexloop::plant::runtime::effects;
namespace zig = flexloop::plant::runtime::effects::ziggurat;

namespace {
double density(double x) {
  return std::exp(-0.5 * x * x);
}
// P(|X| > x) for a standard normal X.
double two_sided_tail(double x) {
  return std::erfc(x / std::numbers::sqrt2);
}
}  // namespace

TEST_CASE("ziggurat table: layers of equal area, the base strip holds the exact tail",
          "[effects][noise]") {
  using zig::kDensity, zig::kEdge, zig::kLayerArea, zig::kLayers, zig::kTailStart;
  CHECK(kEdge[1] == kTailStart);
  CHECK(kEdge[kLayers] == 0.0);
  for (int i = 0; i < kLayers; ++i) REQUIRE(kEdge[i + 1] < kEdge[i]);
  double worst_area = 0, worst_density = 0;
  for (int i = 0; i <= kLayers; ++i)
    worst_density = std::max(worst_density, std::abs(kDensity[i] - density(kEdge[i])));
  // Layer 0: [0, x_0] x [0, f(r)]; layer i: [0, x_i] x [f(x_i), f(x_{i+1})].
  worst_area = std::abs(kEdge[0] * kDensity[1] / kLayerArea - 1);
  for (int i = 1; i < kLayers; ++i)
    worst_area =
        std::max(worst_area, std::abs(kEdge[i] * (kDensity[i + 1] - kDensity[i]) / kLayerArea - 1));
  // The base strip beyond r is the tail: v - r f(r) = integral of f from r to infinity.
  const double tail = std::sqrt(std::numbers::pi / 2) * std::erfc(kTailStart / std::numbers::sqrt2);
  INFO("worst layer area error " << worst_area << ", worst density error " << worst_density);
  CHECK(worst_density <= 2e-16);
  // A layer's area x_i (f(x_{i+1}) - f(x_i)) loses digits to the difference of the top layers'
  // densities (near 1): relative 1e-16 / (f(x_{i+1}) - f(x_i)) there.
  CHECK(worst_area <= 1e-12);
  CHECK(std::abs((kLayerArea - kTailStart * kDensity[1]) / tail - 1) <= 1e-12);
  // The total is the half-normal's area sqrt(pi/2) plus the part of the base strip and layers
  // beyond the curve: each layer sticks out by less than its area.
  CHECK(kLayers * kLayerArea > std::sqrt(std::numbers::pi / 2));
}

TEST_CASE("ziggurat draws: the normal distribution, its tails and the usual path's share",
          "[effects][noise]") {
  constexpr int kDraws = 2'000'000;
  Xoshiro256PlusPlus engine(2026, 0);
  std::vector<double> x(kDraws);
  for (auto& v : x) v = zig::normal(engine);
  // The usual path's share: (1/L) sum of x_{i+1} / x_i, measured on fresh outputs.
  double expected_share = 0;
  for (int i = 0; i < zig::kLayers; ++i) expected_share += zig::kEdge[i + 1] / zig::kEdge[i];
  expected_share /= zig::kLayers;
  long usual = 0;
  Xoshiro256PlusPlus raw(7, 0);
  for (int k = 0; k < kDraws; ++k) {
    const auto bits = raw();
    const int i = zig::layer(bits);
    usual += zig::uniform(bits) * zig::kEdge[i] < zig::kEdge[i + 1];
  }
  const double share = static_cast<double>(usual) / kDraws;
  INFO("usual path: " << share << " of draws, expected " << expected_share);
  CHECK(expected_share > 0.995);
  CHECK(std::abs(share - expected_share) <=
        5 * std::sqrt(expected_share * (1 - expected_share) / kDraws));

  // Tail probabilities P(|X| > t), through the usual path, the wedges and the tail beyond r.
  for (const double t : {0.5, 1.0, 2.0, 3.0, zig::kTailStart, 4.5}) {
    const double p = two_sided_tail(t);
    const double measured = static_cast<double>(std::count_if(
                                x.begin(), x.end(), [&](double v) { return std::abs(v) > t; })) /
                            kDraws;
    INFO("P(|X| > " << t << "): " << measured << ", exact " << p);
    CHECK(std::abs(measured - p) <= 5 * std::sqrt(p * (1 - p) / kDraws) + 1.0 / kDraws);
  }
  // Kolmogorov-Smirnov: sup |F_n - Phi| below the 0.1 % critical value 1.95 / sqrt(n).
  std::sort(x.begin(), x.end());
  double d = 0;
  for (int k = 0; k < kDraws; ++k) {
    const double phi = 0.5 * std::erfc(-x[k] / std::numbers::sqrt2);
    d = std::max({d, std::abs(phi - static_cast<double>(k) / kDraws),
                  std::abs(phi - static_cast<double>(k + 1) / kDraws)});
  }
  INFO("Kolmogorov-Smirnov D = " << d << ", sqrt(n) D = " << d * std::sqrt(double{kDraws}));
  CHECK(d * std::sqrt(double{kDraws}) < 1.95);
}

// An engine that counts its outputs: a draw that took more than one left the usual path.
struct CountingEngine {
  using result_type = Xoshiro256PlusPlus::result_type;
  Xoshiro256PlusPlus engine;
  long outputs = 0;
  result_type operator()() {
    ++outputs;
    return engine();
  }
};

TEST_CASE("ziggurat lanes: each lane draws exactly what its engine draws alone, rare paths too",
          "[effects][noise]") {
  constexpr int kSamples = 800'000 / zig::kLanes;  // 800000 draws whatever the lane width
  zig::EngineLanes lanes(42, 0);
  std::vector<CountingEngine> alone;
  for (int l = 0; l < zig::kLanes; ++l) alone.push_back({Xoshiro256PlusPlus(42, l)});
  long mismatches = 0, rare = 0, tails = 0;
  double x[zig::kLanes];
  for (int k = 0; k < kSamples; ++k) {
    lanes.normals(x, zig::kLanes);
    for (int l = 0; l < zig::kLanes; ++l) {
      const long before = alone[l].outputs;
      const double v = zig::normal(alone[l]);
      mismatches += v != x[l];
      rare += alone[l].outputs - before > 1;
      tails += std::abs(v) > zig::kTailStart;
    }
  }
  INFO(rare << " draws left the usual path, " << tails << " in the tail beyond r");
  CHECK(mismatches == 0);
  CHECK(rare > 1000);  // about 0.4 % of 800000
  CHECK(tails > 10);   // P(|X| > r) = 5.4e-5: about 43
  // Lanes past `active` still advance, and the active ones are unaffected by them.
  constexpr int kActive = std::min(3, zig::kLanes - 1);  // fewer than the build's lanes
  zig::EngineLanes partial(42, 0), full(42, 0);
  for (int k = 0; k < 10'000; ++k) {
    double a[zig::kLanes], b[zig::kLanes];
    partial.normals(a, kActive);
    full.normals(b, zig::kLanes);
    for (int l = 0; l < kActive; ++l) REQUIRE(a[l] == b[l]);
  }
}

TEST_CASE("gaussian noise: channel c of a seed is stream c through the ziggurat, for any count",
          "[effects][noise]") {
  auto wide = GaussianNoise<double, Eigen::Dynamic>::from_seed(11, flexloop::numeric::kMaxChannels);
  auto six = GaussianNoise<double, 6>::from_seed(11);
  std::vector<Xoshiro256PlusPlus> alone;
  for (int c = 0; c < flexloop::numeric::kMaxChannels; ++c) alone.emplace_back(11, c);
  long mismatches = 0;
  for (int k = 0; k < 5'000; ++k) {
    const auto w = wide.sample();
    const auto s = six.sample();
    for (int c = 0; c < flexloop::numeric::kMaxChannels; ++c) {
      const double v = zig::normal(alone[c]);
      mismatches += w(c) != v;
      if (c < 6) mismatches += s(c) != v;
    }
  }
  CHECK(mismatches == 0);
  // One channel drawn alone (the stationary floor start) continues the same sequence.
  auto a = GaussianNoise<double, 6>::from_seed(3), b = GaussianNoise<double, 6>::from_seed(3);
  for (int k = 0; k < 1000; ++k) {
    const auto v = a.sample();
    for (int c = 0; c < 6; ++c) REQUIRE(b.sample(c) == v(c));
  }
}
