// SPDX-License-Identifier: BSD-3-Clause
// The one step from a loop artefact to its runtime objects (issue 34):
// - plant/runtime/plant_from_artefact.hpp: the general plant in the artefact's form, the compiled
//   plant of a compiled loop, each stepping as the artefact's discrete plant;
// - controller/runtime/controller_from_artefact.hpp: the controller of each kind, compiled or
//   sized at start-up, in double or float, and the refusals (no controller; a PI without one
//   sensor per actuator; compiled counts for a kind sized at start-up).
#include <catch2/catch.hpp>

#include <stdexcept>
#include <type_traits>

#include "common/input_error.hpp"
#include "controller/runtime/controller_from_artefact.hpp"
#include "offline/scene/loop_input.hpp"
#include "plant/runtime/plant_from_artefact.hpp"

using namespace flexloop;
using Catch::Matchers::Contains;

namespace {

const char* const kFrame = "tools/scenes/metrology_frame.toml";

artefact::LoopArtefact frame(artefact::PlantForm form) {
  return scene::load_loop(kFrame, {.rate_hz = 0, .form = form, .duration_s = 0});
}

// The output after one step of every input at 1, from rest. NW: the disturbances, compiled or
// Eigen::Dynamic.
template <int NW, class Plant>
Eigen::VectorXd stepped_output(Plant plant, Eigen::Index nw) {
  using Input = typename Plant::Input;
  const Input u = Input::Ones(plant.inputs());
  plant.advance(u);
  return plant.output(u.template head<NW>(nw)).template cast<double>();
}

}  // namespace

TEST_CASE(
    "plant from artefact: the general plant has the artefact's form, the compiled one its "
    "loop's, and both step alike",
    "[sim][factory]") {
  for (const auto form : {artefact::PlantForm::kDense, artefact::PlantForm::kModal}) {
    const auto a = frame(form);
    const Eigen::Index nw = a.disturbances();
    const Eigen::VectorXd general = plant::runtime::with_general_plant<double>(a, [&](auto p) {
      using P = decltype(p);
      if (form == artefact::PlantForm::kModal)
        CHECK(std::is_same_v<P, plant::runtime::GeneralModalPlant<double>>);
      else
        CHECK(std::is_same_v<P, plant::runtime::GeneralDensePlant<double>>);
      CHECK(p.held_inputs() == a.actuators());
      return stepped_output<Eigen::Dynamic>(p, nw);
    });
    const bool compiled = plant::runtime::with_compiled_loop(
        plant::runtime::loop_counts(a),
        [&](auto loop) {
          using Loop = decltype(loop);
          CHECK(Loop::kForm == form);
          const Eigen::VectorXd y =
              stepped_output<Loop::NW>(plant::runtime::make_compiled_plant<Loop>(a), nw);
          CHECK((y - general).norm() <= 1e-12 * (1 + general.norm()));
          return true;
        },
        [] { return false; });
    CHECK(compiled);  // the metrology frame has a compiled loop in both forms
    const Eigen::VectorXd in_float = plant::runtime::with_general_plant<float>(
        a, [&](auto p) { return stepped_output<Eigen::Dynamic>(p, nw); });
    CHECK((in_float - general).norm() <= 1e-4 * (1 + general.norm()));
  }
}

TEST_CASE(
    "controller from artefact: each kind, compiled or sized at start-up, in double and "
    "float",
    "[sim][factory]") {
  namespace rt = controller::runtime;
  const auto pi = frame(artefact::PlantForm::kDense);
  REQUIRE(pi.controller == artefact::ControllerKind::kPiForceFeedback);
  CHECK(rt::has_compiled_kernels(pi.controller));
  rt::with_controller<double, 6>(pi, [](const auto& c) {
    CHECK(std::is_same_v<std::decay_t<decltype(c)>, rt::PiController<double, 6>>);
  });
  rt::with_controller<double>(pi, [](const auto& c) {
    CHECK(std::is_same_v<std::decay_t<decltype(c)>, rt::GeneralPiController<double>>);
    CHECK(c.actuators() == 6);
  });
  rt::with_controller<float>(pi, [](const auto& c) {
    CHECK(std::is_same_v<std::decay_t<decltype(c)>, rt::GeneralPiController<float>>);
  });

  const auto lqg = scene::load_loop("tools/scenes/metrology_frame_lqg.toml");
  REQUIRE(lqg.controller == artefact::ControllerKind::kStateSpace);
  CHECK_FALSE(rt::has_compiled_kernels(lqg.controller));
  rt::with_controller<double>(lqg, [](const auto& c) {
    CHECK(std::is_same_v<std::decay_t<decltype(c)>, rt::StateSpaceController<double>>);
  });
  rt::with_controller<float>(lqg, [](const auto& c) {
    CHECK(std::is_same_v<std::decay_t<decltype(c)>, rt::StateSpaceController<float>>);
  });
  // A kind sized at start-up asked for with compiled counts: the caller's dispatch is wrong.
  CHECK_THROWS_AS((rt::with_controller<double, 6>(lqg, [](const auto&) {})), std::logic_error);
}

TEST_CASE(
    "controller from artefact: a loop without a controller, and a PI without one sensor per "
    "actuator, are refused naming the artefact",
    "[sim][factory]") {
  namespace rt = controller::runtime;
  const auto none = scene::load_loop("tools/scenes/metrology_frame_no_controller.toml");
  REQUIRE(none.controller == artefact::ControllerKind::kNone);
  CHECK_FALSE(rt::has_compiled_kernels(none.controller));
  CHECK_THROWS_WITH(rt::with_controller<double>(none, [](const auto&) {}),
                    Contains(none.source) && Contains("no controller to run (type \"none\")"));

  auto uneven = frame(artefact::PlantForm::kDense);
  uneven.channels.sensors.pop_back();
  const auto refused = [&](auto call) {
    CHECK_THROWS_AS(call(), common::InputError);
    CHECK_THROWS_WITH(call(), Contains(uneven.source) &&
                                  Contains("needs one sensor per actuator; this loop has 5 "
                                           "sensors and 6 actuators"));
  };
  refused([&] { rt::with_controller<double>(uneven, [](const auto&) {}); });
  refused([&] { rt::with_controller<double, 6>(uneven, [](const auto&) {}); });
  refused([&] { rt::with_controller<double, 6, 5>(uneven, [](const auto&) {}); });
}
