// SPDX-License-Identifier: BSD-3-Clause
// The plant and controller stations of the real-time loop (online/loop/plant_station.hpp,
// controller_station.hpp) driven message by message on a synthetic clock: answered in time they
// reproduce the in-process loop bit for bit; a silent controller makes the plant hold, then apply
// the safe command after N misses and resume bumplessly; a plant restart resynchronises the
// controller.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <tuple>

#include "tests/hil/station_fixture.hpp"

using namespace flexloop;
using namespace flexloop::test;
using loop::CommandSource;

TEST_CASE("hil stations: answers in time reproduce the in-process closed loop exactly") {
  StationPair pair;
  // The in-process loop of online/sim (same convention, written out here).
  HilPlant plant = hil_plant();
  auto controller = hil_controller();
  auto noise = plant::runtime::effects::GaussianNoise<double, 6>::from_seed(kFloorSeed);
  HilPlant::Input in = HilPlant::Input::Zero();
  double largest = 0;
  for (int k = 0; k < 3000; ++k) {
    in.head<6>() = kFloorRms * noise.sample();
    const HilPlant::Output y = plant.output(in.head<6>());
    const ChannelVector u = controller.step(y.tail<6>());
    in.tail<6>() = u;
    plant.advance(in);

    REQUIRE(pair.cycle() == (k == 0 ? CommandSource::kNone : CommandSource::kAnswer));
    const auto& s = pair.plant.last_sample();
    REQUIRE(ChannelVector(Eigen::Map<const ChannelVector>(s.sensors.data())) == y.tail<6>());
    REQUIRE(ChannelVector(Eigen::Map<const ChannelVector>(s.performance.data())) == y.head<6>());
    largest = std::max(largest, u.cwiseAbs().maxCoeff());
  }
  CHECK(largest > 0);  // the controller did act
  CHECK(pair.plant.deadline_misses() == 0);
  CHECK(pair.plant.commands().drops().total() == 0);
  CHECK(pair.controller.samples().drops().total() == 0);
}

TEST_CASE(
    "hil stations: a silent controller -> held command, safe command after N misses, "
    "bumpless resume") {
  constexpr int kSafeAfter = 5;
  StationPair pair(kSafeAfter);
  for (int k = 0; k < 500; ++k) pair.cycle();
  // The controller stops answering. This cycle still applies the answer to the sample before.
  CHECK(pair.cycle(false) == CommandSource::kAnswer);
  const ChannelVector before = pair.plant.command();
  REQUIRE(before.cwiseAbs().maxCoeff() > 0);
  // The first misses hold the last command ...
  for (int miss = 1; miss < kSafeAfter; ++miss) {
    CHECK(pair.cycle(false) == CommandSource::kHeld);
    CHECK(pair.plant.command() == before);
  }
  // ... the N-th consecutive miss applies zero force, and so on while it stays silent.
  for (int k = 0; k < 20; ++k) {
    CHECK(pair.cycle(false) == CommandSource::kSafe);
    CHECK(pair.plant.command() == ChannelVector::Zero());
  }
  CHECK(pair.plant.safe_command_cycles() == 20);
  CHECK(pair.plant.deadline_misses() == kSafeAfter - 1 + 20);

  // It answers again. This cycle settles the last unanswered sample (safe once more) ...
  CHECK(pair.cycle(true) == CommandSource::kSafe);
  CHECK(pair.plant.safe_command_cycles() == 21);
  // ... then its first answer is the zero force the plant holds (bumpless start) ...
  CHECK(pair.cycle(true) == CommandSource::kAnswer);
  CHECK(pair.plant.command().cwiseAbs().maxCoeff() < 1e-12 * before.cwiseAbs().maxCoeff());
  CHECK(pair.controller.resumes() == 1);
  // ... and the loop goes on answering in time.
  for (int k = 0; k < 200; ++k) REQUIRE(pair.cycle(true) == CommandSource::kAnswer);
  CHECK(pair.plant.safe_command_cycles() == 21);
}

TEST_CASE("hil stations: without the bumpless restart the first answer after the gap jumps") {
  // The same stop, but a controller that does not know the plant went safe (safe_after far
  // above the gap): its first answer is far from the zero force the plant holds.
  StationPair pair(5);
  loop::ControllerStation unaware(hil_controller(), 1'000'000);
  std::swap(pair.controller, unaware);
  for (int k = 0; k < 500; ++k) pair.cycle();
  pair.cycle(false);
  const ChannelVector before = pair.plant.command();
  for (int k = 0; k < 25; ++k) pair.cycle(false);
  pair.cycle(true);
  REQUIRE(pair.cycle(true) == CommandSource::kAnswer);
  CHECK(pair.plant.command().cwiseAbs().maxCoeff() > 0.1 * before.cwiseAbs().maxCoeff());
  CHECK(pair.controller.resumes() == 0);
}

TEST_CASE("hil stations: a restarted plant (new epoch) makes the controller resynchronise") {
  StationPair first(5, 11);
  auto& controller = first.controller;
  for (int k = 0; k < 200; ++k) first.cycle();
  REQUIRE(controller.controller().state().cwiseAbs().maxCoeff() > 0);

  // A new plant run (new epoch, seq from 1 again, later time) talks to the same controller.
  loop::PlantStation<HilHardware> restarted(hil_hardware(0.0),
                                            {.safe_after = 5, .epoch = 12, .period_ns = kPeriod});
  const std::int64_t t0 = 1000 * kPeriod;
  restarted.settle(t0);
  const auto& s = restarted.sample(t0);
  REQUIRE(s.seq == 1);
  REQUIRE_FALSE(deliver(controller.samples(), s, t0 + kTransit).has_value());
  const auto& cmd = controller.answer(*controller.samples().take());
  CHECK(controller.resyncs() == 1);
  CHECK(cmd.plant_epoch == 12);
  CHECK(cmd.answers_seq == 1);
  // Fresh start: with a plant at rest and no floor, the answer is zero and so is the state.
  CHECK(ChannelVector(Eigen::Map<const ChannelVector>(cmd.commands.data())) ==
        ChannelVector::Zero());
  CHECK(controller.controller().state() == ChannelVector::Zero());
  // The restarted plant accepts it (its own epoch, in time).
  auto answer = cmd;
  answer.t_ns = t0 + kAnswerAfter;
  REQUIRE_FALSE(deliver(restarted.commands(), answer, t0 + kAnswerAfter + kTransit).has_value());
  CHECK(restarted.settle(t0 + kPeriod) == CommandSource::kAnswer);
  // A straggler of the old plant run is stale for the controller now.
  auto old = first.plant.last_sample();
  old.seq += 1;
  CHECK(deliver(controller.samples(), old, t0 + kTransit) == rt::DropReason::kStale);
}

TEST_CASE("hil stations: the controller follows the command the plant held, not its own answer") {
  // From cycle 300 on, eight answers in a row reach the plant after their deadline: it holds the
  // last one it applied for four samples, then applies zero (safe_after 5). Each sample says so
  // (applied_seq), and the controller takes that command as the one the measurement contains.
  StationPair pair(5);
  for (int k = 0; k < 300; ++k) pair.cycle();
  pair.cycle(true, true);  // applies the answer to sample 300 (in time); its own answer is late
  REQUIRE(pair.plant.last_sample().applied_seq == 300);
  const ChannelVector held = pair.plant.command();
  REQUIRE(held.cwiseAbs().maxCoeff() > 0);
  for (int i = 1; i < 8; ++i) {
    pair.cycle(true, true);
    const bool safe = i >= 5;
    CAPTURE(i);
    CHECK(pair.plant.last_sample().applied_seq == (safe ? 0 : 300));
    CHECK(pair.plant.command() == (safe ? ChannelVector::Zero() : held));
  }
  CHECK(pair.controller.followed() == 7);
  pair.cycle();  // settles the last late answer: zero once more; its own answer is in time
  CHECK(pair.plant.last_sample().applied_seq == 0);
  CHECK(pair.controller.followed() == 8);
  pair.cycle();
  CHECK(pair.plant.last_sample().applied_seq == 309);
  CHECK(pair.controller.followed() == 8);
}

TEST_CASE(
    "hil stations: the safe command ramps the held answer to zero, and a resume mid-ramp "
    "is bumpless") {
  constexpr int kSafeAfter = 5;
  constexpr std::int64_t kRamp = 10;
  StationPair pair(kSafeAfter, 7, kRamp);
  for (int k = 0; k < 500; ++k) pair.cycle();
  CHECK(pair.cycle(false) == CommandSource::kAnswer);
  const ChannelVector before = pair.plant.command();
  const std::int64_t answered = pair.plant.last_sample().applied_seq;
  REQUIRE(before.cwiseAbs().maxCoeff() > 0);
  for (int miss = 1; miss < kSafeAfter; ++miss) pair.cycle(false);
  // Safe period j applies (1 - j / kRamp) x the held answer, and each sample says so.
  for (std::int64_t j = 1; j <= 6; ++j) {
    CHECK(pair.cycle(false) == CommandSource::kSafe);
    const double scale = 1.0 - static_cast<double>(j) / static_cast<double>(kRamp);
    CHECK(pair.plant.last_sample().applied_seq == answered);
    CHECK(pair.plant.last_sample().applied_scale == scale);
    CHECK(pair.plant.command() == ChannelVector(scale * before));
  }
  // It answers again mid-ramp: the first answer is the ramped command the plant holds.
  CHECK(pair.cycle(true) == CommandSource::kSafe);
  const ChannelVector ramped = pair.plant.command();
  CHECK(pair.cycle(true) == CommandSource::kAnswer);
  CHECK((pair.plant.command() - ramped).cwiseAbs().maxCoeff() <=
        1e-12 * before.cwiseAbs().maxCoeff());
  CHECK(pair.controller.resumes() == 1);

  // Silent for longer than the ramp: zero from period kRamp on, applied_seq 0.
  for (int k = 0; k < 200; ++k) pair.cycle();
  pair.cycle(false);
  for (int k = 1; k < kSafeAfter + kRamp + 3; ++k) pair.cycle(false);
  CHECK(pair.plant.command() == ChannelVector::Zero());
  CHECK(pair.plant.last_sample().applied_seq == 0);
  CHECK(pair.plant.last_sample().applied_scale == 0.0);
}

namespace {
// The metrology PI for 10 s at 1 kHz; from 1 s on, every 100th sample starts a burst of `burst`
// answers that reach the plant late (a stalled controller host). Largest RMS frame acceleration.
double rms_with_stalls(int burst, std::int64_t safe_ramp_periods) {
  StationPair pair(5, 7, safe_ramp_periods);
  for (int k = 0; k < 10'000; ++k) pair.cycle(true, k >= 1000 && k % 100 < burst);
  return pair.plant.rms_performance().maxCoeff();
}
}  // namespace

TEST_CASE(
    "hil stations: repeated stalls past safe_after keep the isolation with the ramped safe "
    "command, and pump the loop up with zero at once") {
  // Zero force at once returns in one period the strut stiffness force the PI cancels (~96 %):
  // a kick per stall, which the loop does not absorb before the next one. The ramp (500 periods
  // here, 0.5 s) makes the safe command no kick at all over a short stall.
  const double calm = rms_with_stalls(0, 0);
  const double held = rms_with_stalls(4, 0);  // stalls shorter than safe_after: held only
  const double ramped = rms_with_stalls(8, 500);
  const double zeroed = rms_with_stalls(8, 0);
  INFO("calm " << calm << ", held " << held << ", ramped " << ramped << ", zeroed " << zeroed);
  // Measured: held +3 %, ramped +11 %; zeroed runs away (x4e6 after 9 s).
  CHECK(held <= 1.1 * calm);
  CHECK(ramped <= 1.25 * calm);
  CHECK(zeroed >= 100 * calm);
}
