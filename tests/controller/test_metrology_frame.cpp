// SPDX-License-Identifier: BSD-3-Clause
// The reference machine (doc/design.md §4): the committed model file reproduces the paper's passive
// frequencies, its symmetric mode pairs are degenerate, and the gravity preload moves the modes
// only a little.
#include <catch2/catch.hpp>

#include <algorithm>

#include "offline/scene/scene_plant.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"
#include "plant/model/static_equilibrium.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;

namespace {}  // namespace

TEST_CASE("metrology frame: passive frequencies are the paper's within 0.05 Hz",
          "[controller][metrology]") {
  const auto p = scene::build_scene_plant(scene::load_scene(test::metrology_scene_path()));
  const double paper[6] = {13.9, 13.9, 20.0, 31.3, 31.3, 49.0};
  REQUIRE(p.natural_frequencies_hz.size() == 6);
  for (int i = 0; i < 6; ++i) {
    INFO("mode " << i + 1 << ": " << p.natural_frequencies_hz(i) << " Hz");
    CHECK(std::abs(p.natural_frequencies_hz(i) - paper[i]) <= 0.05);
  }
  // The three-fold symmetry makes the sway-tilt modes exact pairs.
  const auto& f = p.natural_frequencies_hz;
  CHECK(std::abs(f(0) - f(1)) <= 1e-9 * f(0));
  CHECK(std::abs(f(3) - f(4)) <= 1e-9 * f(3));
  // Channels as the seed numbers them: 6 floor + 6 actuator inputs, 6 frame + 6 force outputs,
  // and only the 12 suspension states (no integrators of the floor motion without preload).
  CHECK(p.plant.nx() == 12);
  CHECK(p.plant.nu() == 12);
  CHECK(p.plant.ny() == 12);
  CHECK(p.plant.inputs.front() == "acc:x.9");
  CHECK(p.plant.outputs.back() == "stress:e1.9");
}

TEST_CASE("metrology frame: equal struts give a diagonal stiffness in strut coordinates",
          "[controller][metrology]") {
  const auto p = scene::build_scene_plant(scene::load_scene(test::metrology_scene_path()));
  const Eigen::MatrixXd K = p.lin.K.topLeftCorner(6, 6);
  const double k = K(0, 0);
  CHECK((K - k * Eigen::MatrixXd::Identity(6, 6)).norm() <= 1e-12 * k);
}

TEST_CASE(
    "metrology frame: gravity preload finds the static equilibrium and shifts each mode "
    "by less than 1%",
    "[controller][metrology][preload]") {
  auto sc = scene::load_scene(test::metrology_scene_path());
  const auto unloaded = scene::build_scene_plant(sc);
  sc.gravity_preload = true;
  const auto loaded = scene::build_scene_plant(sc);
  // At the equilibrium the strut forces carry the weight: sum of vertical strut forces = m g.
  const auto& m = loaded.model;
  const Eigen::VectorXd R = plant::model::equations_of_motion_residual(
      m, loaded.lin.q, Eigen::VectorXd::Zero(m.nq()), Eigen::VectorXd::Zero(m.nq()));
  CHECK(R.head(m.nd()).norm() <= 1e-9 * 1000.0 * 9.80665);
  double weight_carried = 0;
  auto position = [&](const std::string& node) {
    return Eigen::Vector3d(loaded.lin.x(m.coordinate_index("x." + node)),
                           loaded.lin.x(m.coordinate_index("y." + node)),
                           loaded.lin.x(m.coordinate_index("z." + node)));
  };
  for (const auto& el : m.elements) {
    if (el.type != plant::model::ElementType::kTruss) continue;
    // Force of a strut on its mount node: -sigma along the unit vector floor -> mount, in the
    // deflected configuration.
    const Eigen::Vector3d u =
        (position(m.nodes[el.nodes[0]].id) - position(m.nodes[el.nodes[1]].id)).normalized();
    weight_carried += -loaded.lin.sigma(el.first_deformation) * u.z();
  }
  INFO("vertical strut force sum " << weight_carried << " N");
  CHECK(std::abs(weight_carried - 1000.0 * 9.80665) <= 1e-6 * 1000.0 * 9.80665);
  for (int i = 0; i < 6; ++i) {
    const double f0 = unloaded.natural_frequencies_hz(i), f1 = loaded.natural_frequencies_hz(i);
    INFO("mode " << i + 1 << ": " << f0 << " Hz unloaded, " << f1 << " Hz preloaded");
    CHECK(std::abs(f1 - f0) <= 0.01 * f0);
    CHECK(f1 != f0);  // the preload does enter (Gbar is not zero)
  }
  WARN("gravity preload shifts (Hz): "
       << (loaded.natural_frequencies_hz - unloaded.natural_frequencies_hz).transpose());
}
