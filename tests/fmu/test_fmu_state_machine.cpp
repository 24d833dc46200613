// SPDX-License-Identifier: BSD-3-Clause
// flexloop's calls keep to FMI 2.0's state machine when a controller FMU fails. The fixtures
// abort the process on a call the standard does not allow (tools/fmu/fixture_fmu.h), so each
// case passing shows none was made: after fmi2Fatal no call at all, not even at destruction;
// after fmi2Error only fmi2Reset / fmi2FreeInstance (never fmi2Terminate); a failed
// initialisation is freed without fmi2Terminate.
#include <Eigen/Core>
#include <catch2/catch.hpp>

#include "controller/fmu/fmu_controller.hpp"
#include "tests/fmu/fmu_fixture.hpp"
#include "tests/support/metrology.hpp"

namespace {

using flexloop::controller::fmu::FmuController;

// The fixture PI with a sensor range of 1 N: a 2 N measurement is an overload.
FmuController overloading_pi(bool fatal) {
  auto s = flexloop::test::pi_fmu_settings(flexloop::test::metrology_pi_parameters(),
                                           flexloop::test::pi_fmu_path());
  s.parameters.emplace_back("y_max", 1.0);
  s.parameters.emplace_back("fatal_on_overload", fatal ? 1.0 : 0.0);
  return FmuController::from_settings(s);
}

}  // namespace

TEST_CASE("After fmi2Fatal the FMU is not called again and the safe command stays", "[fmu]") {
  const Eigen::Matrix<double, 6, 1> quiet = Eigen::Matrix<double, 6, 1>::Constant(0.1),
                                    overload = Eigen::Matrix<double, 6, 1>::Constant(2.0);
  {
    auto c = overloading_pi(true);
    CHECK(c.step(quiet).cwiseAbs().maxCoeff() > 0);  // a working step first
    CHECK(c.step(overload).isZero());
    CHECK(c.failure() == "fmi2DoStep returned fmi2Fatal at sample 1 (t = 0.0001 s)");
    c.reset();  // no fmi2Reset after fmi2Fatal
    CHECK(c.step(quiet).isZero());
    CHECK(c.failure() == "fmi2DoStep returned fmi2Fatal at sample 1 (t = 0.0001 s)");
  }  // destroyed without fmi2Terminate or fmi2FreeInstance
  SUCCEED("no call after fmi2Fatal (the fixture would have aborted)");
}

TEST_CASE("After fmi2Error a reset recovers the FMU and the first failure stays reported",
          "[fmu]") {
  const Eigen::Matrix<double, 6, 1> quiet = Eigen::Matrix<double, 6, 1>::Constant(0.1),
                                    overload = Eigen::Matrix<double, 6, 1>::Constant(2.0);
  auto c = overloading_pi(false);
  const Eigen::Matrix<double, 6, 1> first = c.step(quiet);
  CHECK(c.step(overload).isZero());
  CHECK(c.step(quiet).isZero());  // no call in the error state: the safe command
  c.reset();                      // fmi2Reset, parameters, initialisation again
  CHECK(c.step(quiet) == first);  // from rest again: the same first answer
  CHECK(c.failure() == "fmi2DoStep returned fmi2Error at sample 1 (t = 0.0001 s)");
  CHECK_THROWS_WITH(c.check(), Catch::Contains("fmi2Error at sample 1"));
  {
    auto failing = overloading_pi(false);
    CHECK(failing.step(overload).isZero());
  }  // destroyed in the error state: fmi2FreeInstance without fmi2Terminate
}

TEST_CASE("An FMU whose initialisation fails is freed without fmi2Terminate", "[fmu]") {
  auto s = flexloop::test::pi_fmu_settings(flexloop::test::metrology_pi_parameters(),
                                           flexloop::test::pi_fmu_path());
  s.parameters.emplace_back("leak_rad_s", -1.0);  // refused at fmi2ExitInitializationMode
  CHECK_THROWS_WITH(FmuController::from_settings(s),
                    Catch::Contains("fmi2ExitInitializationMode returned fmi2Error"));
}
