// SPDX-License-Identifier: BSD-3-Clause
// A controller FMU in the controller process (online/loop/controller_station.hpp), driven message
// by message on the synthetic clock of tests/hil/station_fixture.hpp: it answers as the built-in
// PI does, and a failing fmi2DoStep is reported with its sample while the safe command follows.
#include <catch2/catch.hpp>

#include "controller/fmu/fmu_controller.hpp"
#include "tests/fmu/fmu_fixture.hpp"
#include "tests/hil/station_fixture.hpp"

using namespace flexloop;
using namespace flexloop::test;
using controller::fmu::FmuController;

namespace {

FmuController pi_fmu(double y_max = 0) {
  auto s = pi_fmu_settings(hil_scene().pi, pi_fmu_path());
  if (y_max > 0) s.parameters.emplace_back("y_max", y_max);
  return FmuController::from_settings(s);
}

}  // namespace

TEST_CASE("The controller process answers with the fixture FMU as with the built-in PI", "[fmu]") {
  StationPair builtin;
  BasicStationPair<FmuController> fmu(5, 7, 0, pi_fmu());
  double largest = 0, difference = 0;
  for (int k = 0; k < 3000; ++k) {
    REQUIRE(fmu.cycle() == builtin.cycle());
    const auto &a = builtin.plant.last_sample(), &b = fmu.plant.last_sample();
    const ChannelVector ya = Eigen::Map<const ChannelVector>(a.sensors.data()),
                        yb = Eigen::Map<const ChannelVector>(b.sensors.data());
    largest = std::max(largest, ya.cwiseAbs().maxCoeff());
    difference = std::max(difference, (yb - ya).cwiseAbs().maxCoeff());
  }
  CHECK(largest > 0);
  CHECK(difference <= 1e-12 * largest);
  CHECK(fmu.controller.answered() == builtin.controller.answered());
  CHECK(fmu.controller.controller().failure().empty());
  CHECK(fmu.plant.deadline_misses() == 0);
}

TEST_CASE(
    "A controller FMU's fmi2Error in the loop names the call and sample and zero force follows",
    "[fmu]") {
  // Half the largest force the floor drives into the sensors over the run: an overload on the way.
  StationPair builtin;
  double largest = 0;
  for (int k = 0; k < 2000; ++k) {
    builtin.cycle();
    largest = std::max(largest,
                       Eigen::Map<const ChannelVector>(builtin.plant.last_sample().sensors.data())
                           .cwiseAbs()
                           .maxCoeff());
  }
  BasicStationPair<FmuController> fmu(5, 7, 0, pi_fmu(0.5 * largest));
  bool failed = false;
  for (int k = 0; k < 2000; ++k) {
    fmu.cycle();
    const std::string failure = fmu.controller.controller().failure();
    if (!failure.empty() && !failed) {
      failed = true;
      CHECK_THAT(failure, Catch::Matches("fmi2DoStep returned fmi2Error at sample [0-9]+ \\(t = "
                                         "[0-9.e-]+ s\\)"));
    }
    if (failed) {
      const auto& cmd = fmu.controller.answer(fmu.plant.last_sample());
      CHECK(Eigen::Map<const ChannelVector>(cmd.commands.data()).isZero(0));
      break;
    }
  }
  CHECK(failed);
}
