// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// An effect slot of the simulated hardware (simulated_hardware.hpp) whose effect is chosen at
// start-up: one of Effects, or none. The compiled compositions fix each slot's effect at compile
// time (an absent one is NoEffect and costs nothing); a loop whose effects no compiled
// composition lists runs with these slots instead, so that one instantiation serves every
// combination. A step dispatches once on the choice, which does not change during a run (a
// branch the predictor learns); no choice passes the signal through unchanged.
#include <utility>
#include <variant>

#include "plant/runtime/simulated_hardware.hpp"

namespace flexloop::plant::runtime {

/// Vector: the signal the slot passes (each effect's step(const Vector&) returns a Vector).
template <class Vector, class... Effects>
class EffectChoice {
 public:
  /// No effect: the signal passes through.
  EffectChoice() = default;
  template <class Effect>
  explicit EffectChoice(Effect effect) : effect_(std::move(effect)) {}

  /// x through the chosen effect, or x itself when none was chosen.
  Vector step(const Vector& x) noexcept {
    return std::visit(
        [&x](auto& effect) -> Vector {
          if constexpr (kPresent<std::decay_t<decltype(effect)>>)
            return effect.step(x);
          else
            return x;
        },
        effect_);
  }

  /// f(effect) on the chosen effect; nothing when none was chosen.
  template <class F>
  void visit(F&& f) noexcept {
    std::visit(
        [&f](auto& effect) {
          if constexpr (kPresent<std::decay_t<decltype(effect)>>) f(effect);
        },
        effect_);
  }

  /// Whether an effect was chosen.
  bool present() const noexcept { return effect_.index() != 0; }

 private:
  std::variant<NoEffect, Effects...> effect_;
};

}  // namespace flexloop::plant::runtime
