// SPDX-License-Identifier: BSD-3-Clause
// Acceleration inputs get double-integrator states when the dynamics depend on the prescribed
// position through preload (Gbar_dr != 0; seed slide 24, doc/design.md §3). A taut string: mass m
// at the end of a truss of length l under tension T (a nodal force), the other end moved
// transversally with prescribed y1. Transverse motion (string theory, small amplitude):
//   m y2'' = -(T/l)(y2 - y1)   =>   y2/y1'' = (T/(m l)) / (s^2 (s^2 + T/(m l))).
#include <catch2/catch.hpp>
#include <complex>

#include "plant/lti/state_space_builder.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"

using namespace flexloop::plant;

namespace {
constexpr double kTension = 50.0, kLength = 2.0, kMass = 0.5;
const char* kString = R"(
[model]
dimension = 2
[[node]]
id = "1"
position = [0.0, 0.0]
[[node]]
id = "2"
position = [2.0, 0.0]
mass = 0.5
force = [50.0, 0.0]
[[element]]
id = "s"
type = "truss"
nodes = ["1", "2"]
stiffness = 1.0e5
[coordinates]
fixed = ["x.1"]
dynamic = ["e1.s", "y.2"]
prescribed = ["y.1"]
)";
}  // namespace

TEST_CASE(
    "preload: a taut string moved at one end needs integrator states for an acceleration input") {
  const auto m = model::parse_model(kString, "string.toml");
  const auto lin = model::linearise(m);
  // Geometric stiffness of the string: T/l on the transverse coordinates, coupling to y1.
  const int y2 = 1, y1 = 2;
  CHECK(lin.G(y2, y2) == Approx(kTension / kLength).epsilon(1e-9));
  CHECK(lin.G(y2, y1) == Approx(-kTension / kLength).epsilon(1e-9));

  const auto ss = lti::build_state_space(m, lin, {"acc:y.1"}, {"pos:y.2"});
  REQUIRE(ss.nx() == 6);  // (e, y2) positions and velocities, plus y1 and y1'
  CHECK(ss.states[4] == "vel:y.1");
  CHECK(ss.states[5] == "pos:y.1");
  const double w2 = kTension / (kMass * kLength);
  for (double w : {0.3, 4.0, 30.0}) {
    const std::complex<double> s(0.0, w);
    const Eigen::MatrixXcd sI_A =
        s * Eigen::MatrixXcd::Identity(6, 6) - ss.A.cast<std::complex<double>>();
    const std::complex<double> g =
        (ss.C.cast<std::complex<double>>() *
         sI_A.partialPivLu().solve(ss.B.cast<std::complex<double>>()))(0, 0) +
        ss.D(0, 0);
    const std::complex<double> expected = w2 / (s * s * (s * s + w2));
    CHECK(std::abs(g - expected) <= 1e-9 * std::abs(expected));
  }
  // With all three signals of y1 as inputs there are no integrator states.
  CHECK(lti::build_state_space(m, lin, {"acc:y.1", "vel:y.1", "pos:y.1"}, {"pos:y.2"}).nx() == 4);
}
