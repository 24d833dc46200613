// SPDX-License-Identifier: BSD-3-Clause
// Reaction outputs (equations of reaction, seed slides 8 and 12-13), against references that do
// not use the release-to-prescribed construction:
//  - a mass on a spring on the ground: the support force obeys Newton's law on the mass,
//    dR = m dy'' - df (and equals -(k de + d de'));
//  - the stress in a rigid link of a moving mechanism: the released model's linearised row
//    equals finite differences of the stress solved from the x(c) rows of J^T sigma = f - g_in.
#include <catch2/catch.hpp>
#include <functional>

#include "common/input_error.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"
#include "plant/model/released_model.hpp"

using namespace flexloop::plant;

namespace {

const char* kSpringOnGround = R"(
[model]
dimension = 2
gravity = [0.0, -9.81]
[[node]]
id = "1"
position = [0.0, 0.0]
[[node]]
id = "2"
position = [0.0, 1.0]
mass = 3.0
[[element]]
id = "s"
type = "truss"
nodes = ["1", "2"]
stiffness = 1200.0
damping = 7.0
[coordinates]
fixed = ["x.1", "y.1", "x.2"]
dynamic = ["e1.s"]
)";

Eigen::VectorXd fd(const std::function<double(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& v,
                   double h) {
  Eigen::VectorXd g(v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    Eigen::VectorXd p = v, m = v;
    p(i) += h;
    m(i) -= h;
    g(i) = (f(p) - f(m)) / (2 * h);
  }
  return g;
}

}  // namespace

TEST_CASE("reactions: the support force of a spring-mass obeys Newton's law on the mass") {
  constexpr double k = 1200.0, d = 7.0, mass = 3.0;
  const auto m = model::parse_model(kSpringOnGround, "spring.toml");
  const auto lin = model::linearise(m);
  const auto ss = lti::build_state_space(m, lin, {"force:y.2"}, {"reaction:y.1", "acc:y.2"});
  // Reaction on node 1 = -(spring tension) = -(k e + d e').
  CHECK(ss.C(0, 0) == Approx(-k).epsilon(1e-12));
  CHECK(ss.C(0, 1) == Approx(-d).epsilon(1e-12));
  CHECK(std::abs(ss.D(0, 0)) < 1e-12);
  // Newton: m y2'' = -sigma + f - m g  =>  dR = -dsigma = m dy2'' - df.
  CHECK((ss.C.row(0) - mass * ss.C.row(1)).norm() < 1e-10 * k);
  CHECK(ss.D(0, 0) == Approx(mass * ss.D(1, 0) - 1.0).margin(1e-12));
}

TEST_CASE(
    "reactions: the stress in a rigid link equals finite differences of the equations of "
    "reaction") {
  const auto m = model::load_model("tests/model/models/truss_mechanism.toml");
  const int k = m.deformation_index("e1.c");
  model::OperatingPoint op;
  op.q = model::reference_generalised(m) + Eigen::Vector3d(0.01, -0.02, 0.015);
  op.qd = Eigen::Vector3d(0.3, -0.2, 0.1);
  op.qdd = Eigen::Vector3d(1.5, 0.4, -2.0);
  // Reference: the rigid stress as solved by linearise() from the x(c) rows of the reactions.
  auto sigma = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                   const Eigen::VectorXd& qdd) {
    model::OperatingPoint o{q, qd, qdd, {}};
    return model::linearise(m, o).sigma(k);
  };
  const double h = 1e-6;
  const Eigen::VectorXd ds_dq =
      fd([&](const Eigen::VectorXd& v) { return sigma(v, op.qd, op.qdd); }, op.q, h);
  const Eigen::VectorXd ds_dqd =
      fd([&](const Eigen::VectorXd& v) { return sigma(op.q, v, op.qdd); }, op.qd, 1e-3);
  const Eigen::VectorXd ds_dqdd =
      fd([&](const Eigen::VectorXd& v) { return sigma(op.q, op.qd, v); }, op.qdd, 1e-3);

  // The released model's row, as the state-space builder uses it: sigma_c = -R_c.
  const auto released = model::release_to_prescribed(m, "e1.c");
  model::OperatingPoint ro;
  ro.q = model::reference_generalised(released);
  ro.q.head(3) = op.q;
  ro.qd = Eigen::VectorXd::Zero(4);
  ro.qdd = Eigen::VectorXd::Zero(4);
  ro.qd.head(3) = op.qd;
  ro.qdd.head(3) = op.qdd;
  const auto rl = model::linearise(released, ro);
  const Eigen::VectorXd row_q = -(rl.K + rl.N + rl.G).row(3).head(3).transpose();
  const Eigen::VectorXd row_qd = -(rl.C + rl.D).row(3).head(3).transpose();
  const Eigen::VectorXd row_qdd = -rl.M.row(3).head(3).transpose();
  CHECK((row_q - ds_dq).norm() <= 1e-6 * std::max(1.0, ds_dq.norm()));
  CHECK((row_qd - ds_dqd).norm() <= 1e-6 * std::max(1.0, ds_dqd.norm()));
  CHECK((row_qdd - ds_dqdd).norm() <= 1e-6 * std::max(1.0, ds_dqdd.norm()));
  CHECK(ds_dq.norm() > 1.0);  // the check is not vacuous

  // And the builder accepts it as an output at a stationary point.
  const auto ss = lti::build_state_space(m, model::linearise(m), {"force:x.2"}, {"stress:e1.c"});
  CHECK(ss.C.norm() > 0.0);
}

TEST_CASE("reactions: outputs that are not determined are refused with the reason") {
  const auto m = model::parse_model(kSpringOnGround, "spring.toml");
  const auto lin = model::linearise(m);
  CHECK_THROWS_WITH(lti::build_state_space(m, lin, {}, {"reaction:y.2"}),
                    Catch::Contains("not a fixed coordinate"));
  CHECK_THROWS_WITH(lti::build_state_space(m, lin, {}, {"reaction:q.7"}),
                    Catch::Contains("unknown"));
}
