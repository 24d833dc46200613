// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Drives a PlantStation and a ControllerStation by hand, on a synthetic clock (sample k due at
// k T, answered 100 us later, received 150 us later), with every message going through its LCM
// encoding and the receiving inbox, as over the wire -- no sockets, no real time.
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "offline/scene/loop_input.hpp"
#include "online/loop/controller_station.hpp"
#include "online/loop/loop_controller.hpp"
#include "online/loop/plant_station.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/effects/white_floor.hpp"
#include "plant/runtime/simulated_hardware.hpp"
#include "tests/support/metrology.hpp"

namespace flexloop::test {

using HilPlant = plant::runtime::DensePlant<double, 12, 12, 12, 6>;  // holds the actuator forces
using HilFloor = plant::runtime::effects::WhiteFloor<double, 6>;
/// The metrology plant with a white floor and no other effect.
using HilHardware = plant::runtime::SimulatedHardware<HilPlant, 6, 6, HilFloor>;

inline const artefact::LoopArtefact& hil_scene() {
  static const artefact::LoopArtefact s = scene::load_loop(
      metrology_scene_path(), {.rate_hz = 1000, .form = std::nullopt, .duration_s = 0});
  return s;
}

using HilController = controller::runtime::PiController<double, 6>;
using ChannelVector = Eigen::Matrix<double, 6, 1>;  // one value per strut

/// The metrology frame's PI on its compiled six channels.
inline HilController hil_controller(const artefact::LoopArtefact& a = hil_scene()) {
  return HilController::from_parameters(a.pi);
}

inline HilPlant hil_plant() {
  const auto& d = hil_scene().plant;
  return HilPlant::from_matrices(d.A, d.B, d.C, d.D);
}

inline constexpr double kFloorRms = 1e-3;  // m/s^2 per channel
inline constexpr std::uint64_t kFloorSeed = 1;

inline HilHardware hil_hardware(double floor_rms = kFloorRms) {
  return HilHardware(hil_plant(), HilFloor::from_parameters(floor_rms, kFloorSeed));
}

inline constexpr std::int64_t kPeriod = 1'000'000;
inline constexpr std::int64_t kAnswerAfter = 100'000, kTransit = 50'000;

/// Encodes `m` and offers it to `inbox` as received at received_ns.
template <class Msg>
auto deliver(rt::MessageInbox<Msg>& inbox, const Msg& m, std::int64_t received_ns) {
  std::vector<std::uint8_t> buffer;
  return rt::offer_encoded(inbox, m, received_ns, buffer);
}

/// The metrology plant's station and a controller's (the compiled PI unless given).
template <class Controller = HilController>
struct BasicStationPair {
  loop::PlantStation<HilHardware> plant;
  loop::ControllerStation<Controller> controller;
  std::int64_t k = 0;  // next cycle

  /// safe_ramp_periods 0: the safe command is zero at once.
  explicit BasicStationPair(int safe_after = 5, std::int64_t epoch = 7,
                            std::int64_t safe_ramp_periods = 0, Controller c = hil_controller())
      : plant(hil_hardware(), {.safe_after = safe_after,
                               .epoch = epoch,
                               .period_ns = kPeriod,
                               .command_limit = std::numeric_limits<double>::infinity(),
                               .safe_ramp_periods = safe_ramp_periods}),
        controller(std::move(c), safe_after) {}

  /// One cycle; the controller answers when `answer` (returns where the settled command came from);
  /// a `late` answer reaches the plant after the next deadline (it is never applied).
  loop::CommandSource cycle(bool answer = true, bool late = false) {
    const std::int64_t due = k * kPeriod;
    const loop::CommandSource source = plant.settle(due);
    const auto& s = plant.sample(due);
    deliver(controller.samples(), s, due + kTransit);
    if (const auto* got = controller.samples().take(); got && answer) {
      auto& cmd = controller.answer(*got);
      cmd.t_ns = due + kAnswerAfter;
      deliver(plant.commands(), cmd, due + kAnswerAfter + kTransit + (late ? kPeriod : 0));
    }
    ++k;
    return source;
  }
};
using StationPair = BasicStationPair<>;

}  // namespace flexloop::test
