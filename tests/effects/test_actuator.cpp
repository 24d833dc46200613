// SPDX-License-Identifier: BSD-3-Clause
// Piezo actuator: gain and force limits exact, saturation flags for the anti-windup, NaN and inf
// commands handled; the first-order lag equals the analytic step response at the sample instants
// and its sample means equal the analytic integrals, and for a random held input it matches an
// independent fine RK4 integration of τ f' = -f + v.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "plant/runtime/effects/piezo_actuator.hpp"

using namespace flexloop::plant::runtime::effects;

namespace {

PiezoActuatorParameters<3> limits() {
  PiezoActuatorParameters<3> p;
  p.gain << 2.0, 0.5, -1.0;
  p.force_min << -10.0, -4.0, 0.0;
  p.force_max << 20.0, 4.0, 8.0;
  return p;
}

}  // namespace

TEST_CASE("piezo actuator: gain and saturation are exact, flags say which channel clipped") {
  auto act = PiezoActuator<double, 3>::from_parameters(limits(), 1e-3);
  using V = ChannelVector<double, 3>;
  struct Case {
    V command, force;
    bool sat[3];
  };
  const Case cases[] = {
      {V(1.0, 2.0, -3.0), V(2.0, 1.0, 3.0), {false, false, false}},
      {V(10.0, 8.0, -8.0), V(20.0, 4.0, 8.0), {false, false, false}},  // exactly at the limits
      {V(10.5, 8.5, -8.5), V(20.0, 4.0, 8.0), {true, true, true}},
      {V(-6.0, -9.0, 0.25), V(-10.0, -4.0, 0.0), {true, true, true}},
      {V(-5.0, -7.75, -0.125), V(-10.0, -3.875, 0.125), {false, false, false}},
  };
  for (const auto& c : cases) {
    const V f = act.step(c.command);
    INFO("command " << c.command.transpose());
    CHECK(f == c.force);
    CHECK(act.limited_force() == c.force);
    CHECK(act.unsaturated_force() == V(2.0 * c.command(0), 0.5 * c.command(1), -c.command(2)));
    for (int i = 0; i < 3; ++i) CHECK(act.saturated()(i) == c.sat[i]);
  }
}

TEST_CASE("piezo actuator: NaN command gives zero force and counts as saturated, inf clips") {
  auto act = PiezoActuator<double, 3>::from_parameters(limits(), 1e-3);
  const double inf = std::numeric_limits<double>::infinity();
  const auto f = act.step({std::nan(""), inf, inf});
  CHECK(f == ChannelVector<double, 3>(0.0, 4.0, 0.0));  // channel 2 has gain -1: -inf -> min 0
  CHECK(act.saturated().all());
  CHECK(std::isnan(act.unsaturated_force()(0)));
}

namespace {
// The actuator's definition channel by channel (header of piezo_actuator.hpp), for any count and
// every SIMD position: random commands with NaN, ±inf and ±0 among them, ranges on both sides of
// zero and ranges that do not contain it (a NaN then gives the limit nearest zero).
template <int N>
void check_against_definition(Eigen::Index n) {
  std::mt19937_64 rng(11 + n);
  std::uniform_real_distribution<double> u(-2, 2);
  PiezoActuatorParameters<N> p(n);
  for (Eigen::Index c = 0; c < n; ++c) {
    p.gain(c) = c % 3 == 2 ? -1.5 : 0.75;
    p.force_min(c) = c % 4 == 3 ? 0.5 : -1.0 - 0.1 * c;
    p.force_max(c) = c % 5 == 4 ? -0.25 : 1.0 + 0.1 * c;
    if (p.force_min(c) >= p.force_max(c)) p.force_min(c) = -2.0;
  }
  auto act = PiezoActuator<double, N>::from_parameters(p, 1e-3);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  const double specials[] = {nan, inf, -inf, 0.0, -0.0};
  for (int k = 0; k < 400; ++k) {
    ChannelVector<double, N> command(n);
    for (Eigen::Index c = 0; c < n; ++c)
      command(c) = (k + c) % 3 == 0 ? specials[(k + c) % 5] : u(rng);
    const ChannelVector<double, N> f = act.step(command);
    for (Eigen::Index c = 0; c < n; ++c) {
      INFO(n << " channels, channel " << c << ", command " << command(c));
      const double commanded = p.gain(c) * command(c);
      const double finite = std::isnan(commanded) ? 0.0 : commanded;
      const double limited = std::clamp(finite, p.force_min(c), p.force_max(c));
      CHECK(f(c) == limited);
      CHECK(act.limited_force()(c) == limited);
      CHECK((act.unsaturated_force()(c) == commanded || std::isnan(commanded)));
      CHECK(act.saturated()(c) == (std::isnan(commanded) || limited != finite));
    }
  }
}
}  // namespace

TEST_CASE("piezo actuator: every channel of any count follows the definition, NaN and inf too") {
  check_against_definition<1>(1);
  check_against_definition<5>(5);
  check_against_definition<6>(6);
  check_against_definition<7>(7);
  check_against_definition<12>(12);
  for (const Eigen::Index n : {1, 6, 9, 64}) check_against_definition<Eigen::Dynamic>(n);
}

TEST_CASE("first-order lag: unit step equals 1 - e^(-t/τ) at the instants and its integral mean") {
  const double dt = 1e-3;
  ChannelParameters<3> tau(5e-3, 1e-4, 2.0);  // T/τ = 0.2, 10, 5e-4
  auto lag = FirstOrderLag<double, 3>::from_parameters(tau, dt);
  double worst_state = 0, worst_mean = 0;
  for (int k = 0; k < 5000; ++k) {
    const auto mean = lag.step(ChannelVector<double, 3>::Ones());
    for (int c = 0; c < 3; ++c) {
      const double e0 = std::exp(-k * dt / tau(c)), e1 = std::exp(-(k + 1) * dt / tau(c));
      worst_state = std::max(worst_state, std::abs(lag.state()(c) - (1 - e1)));
      worst_mean = std::max(worst_mean, std::abs(mean(c) - (1 - tau(c) / dt * (e0 - e1))));
    }
  }
  INFO("state error " << worst_state << ", mean error " << worst_mean);
  CHECK(worst_state <= 1e-13);
  CHECK(worst_mean <= 1e-12);
}

TEST_CASE("first-order lag: random held input matches a fine RK4 integration") {
  const double dt = 1e-3, tau = 3e-3;
  auto lag = FirstOrderLag<double, 1>::from_parameters(ChannelParameters<1>::Constant(tau), dt);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n;
  double f = 0, worst = 0;
  constexpr int kSub = 200;
  const double h = dt / kSub;
  for (int k = 0; k < 2000; ++k) {
    const double v = n(rng);
    double integral = 0;  // Simpson over the RK4 substeps
    auto rhs = [&](double x) { return (v - x) / tau; };
    for (int s = 0; s < kSub; ++s) {
      const double k1 = rhs(f), k2 = rhs(f + h / 2 * k1), k3 = rhs(f + h / 2 * k2),
                   k4 = rhs(f + h * k3);
      const double mid = f + h / 2 * (k1 + k2) / 2;  // 2nd-order midpoint, ample for Simpson
      const double next = f + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      integral += h / 6 * (f + 4 * mid + next);
      f = next;
    }
    const double mean = lag.step(ChannelVector<double, 1>::Constant(v))(0);
    worst = std::max({worst, std::abs(lag.state()(0) - f), std::abs(mean - integral / dt)});
  }
  INFO("worst difference " << worst);
  CHECK(worst <= 1e-7);
}

TEST_CASE("piezo actuator with lag: limits before the lag, force stays within them") {
  auto p = limits();
  p.lag_time_constant = ChannelParameters<3>::Constant(2e-3);
  auto act = PiezoActuator<double, 3, true>::from_parameters(p, 1e-3);
  auto lag = FirstOrderLag<double, 3>::from_parameters(p.lag_time_constant, 1e-3);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-30, 30);
  for (int k = 0; k < 10000; ++k) {
    const ChannelVector<double, 3> cmd(u(rng), u(rng), u(rng));
    const auto f = act.step(cmd);
    REQUIRE(f == lag.step(act.limited_force()));
    REQUIRE((f.array() >= p.force_min.array()).all());
    REQUIRE((f.array() <= p.force_max.array()).all());
  }
}

TEST_CASE("piezo actuator: start-up rejects bad parameters with a message naming them") {
  CHECK_THROWS_WITH((PiezoActuator<double, 3>::from_parameters({}, 1e-3)),
                    Catch::Contains("force_min [N] of channel 0 is nan"));
  auto p = limits();
  p.gain(1) = 0;
  CHECK_THROWS_WITH((PiezoActuator<double, 3>::from_parameters(p, 1e-3)),
                    Catch::Contains("gain of channel 1"));
  p = limits();
  p.force_min(2) = 9;
  CHECK_THROWS_WITH((PiezoActuator<double, 3>::from_parameters(p, 1e-3)),
                    Catch::Contains("channel 2: force_min"));
  p = limits();
  p.lag_time_constant(0) = 1e-3;
  CHECK_THROWS_WITH((PiezoActuator<double, 3>::from_parameters(p, 1e-3)),
                    Catch::Contains("has no lag"));
  CHECK_THROWS_WITH((PiezoActuator<double, 3, true>::from_parameters(limits(), 1e-3)),
                    Catch::Contains("time constant [s] of channel 0 is 0"));
  p.lag_time_constant = ChannelParameters<3>::Constant(1e-3);
  CHECK_THROWS_WITH((PiezoActuator<double, 3, true>::from_parameters(p, 0)),
                    Catch::Contains("sample time"));
}
