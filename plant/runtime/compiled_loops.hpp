// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The loops the runtime has compiled fast paths for: one typed list, CompiledLoops, which
// `flexloop sim`, the plant process and the controller process all dispatch on at start-up. A loop
// whose counts and form match an entry runs on fixed-size kernels (plant, PI and every effect);
// every other loop runs on the general path, sized at start-up, with no rebuild. To add a fast
// path, add an entry: the three users pick it up, and the compiler instantiates what it needs.
//
// The plant's inputs are [disturbances; actuators] and its outputs [performance; sensors]
// (artefact/loop_artefact.hpp); it holds the actuator commands itself (NH = NC held inputs,
// plant/runtime/state_output.hpp).
#include <Eigen/Core>

#include "artefact/loop_schema.hpp"

namespace flexloop::plant::runtime {

// One enum across the seam: the form as the artefact holds it (artefact/loop_schema.hpp).
using artefact::PlantForm;

/// One compiled loop: NX states, NW disturbances, NC actuators, NZ performance outputs, NS
/// sensors, stepped in the given plant form.
template <int NX_, int NW_, int NC_, int NZ_, int NS_, PlantForm Form_>
struct CompiledLoop {
  static constexpr int NX = NX_, NW = NW_, NC = NC_, NZ = NZ_, NS = NS_;
  static constexpr int NU = NW + NC, NY = NZ + NS, NH = NC;
  static constexpr PlantForm kForm = Form_;
  static_assert(NX > 0 && NW > 0 && NC > 0 && NZ > 0 && NS > 0, "a compiled loop has every kind");
};

/// A list of types to dispatch on at start-up (first_match).
template <class... Ts>
struct TypeList {};

template <class... Loops>
using LoopList = TypeList<Loops...>;

using CompiledLoops =
    LoopList<CompiledLoop<12, 6, 6, 6, 6, PlantForm::kDense>,   // the metrology frame
             CompiledLoop<12, 6, 6, 6, 6, PlantForm::kModal>,   // the same, modal form
             CompiledLoop<24, 6, 6, 6, 6, PlantForm::kDense>>;  // under gravity preload

/// The counts and form of a loaded loop, as the dispatch compares them.
struct LoopCounts {
  Eigen::Index states = 0, disturbances = 0, actuators = 0, performance = 0, sensors = 0;
  PlantForm form = PlantForm::kDense;
};

template <class Loop>
constexpr bool matches(const LoopCounts& n) {
  return n.states == Loop::NX && n.disturbances == Loop::NW && n.actuators == Loop::NC &&
         n.performance == Loop::NZ && n.sensors == Loop::NS && n.form == Loop::kForm;
}

/// Start-up: f(T{}) for the first T of the list with match(T{}), otherwise() when there is none
/// (every call returns the same type).
template <class Match, class F, class Otherwise>
decltype(auto) first_match(TypeList<>, Match&&, F&&, Otherwise&& otherwise) {
  return otherwise();
}
template <class T, class... Rest, class Match, class F, class Otherwise>
decltype(auto) first_match(TypeList<T, Rest...>, Match&& match, F&& f, Otherwise&& otherwise) {
  if (match(T{})) return f(T{});
  return first_match(TypeList<Rest...>{}, match, f, otherwise);
}

/// Start-up: f(Loop{}) for the first compiled loop whose counts and form equal n, otherwise()
/// when there is none (both return the same type).
template <class F, class Otherwise>
decltype(auto) with_compiled_loop(const LoopCounts& n, F&& f, Otherwise&& otherwise) {
  return first_match(
      CompiledLoops{}, [&n](auto loop) { return matches<decltype(loop)>(n); }, f, otherwise);
}

/// Start-up: f(Loop{}) for the first compiled loop with these actuator and sensor counts (what a
/// controller of the loop sees), otherwise() when there is none.
template <class F, class Otherwise>
decltype(auto) with_compiled_channels(Eigen::Index actuators, Eigen::Index sensors, F&& f,
                                      Otherwise&& otherwise) {
  return first_match(
      CompiledLoops{},
      [=](auto loop) { return actuators == decltype(loop)::NC && sensors == decltype(loop)::NS; },
      f, otherwise);
}

}  // namespace flexloop::plant::runtime
