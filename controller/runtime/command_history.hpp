// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The commands a start-up-sized controller sent, as far back as the sensors' delay reaches: the
// measurement of sample k contains the command u_{k-1-d} (d: sensor + transport delay, 0 ..
// kMaxFeedthroughDelay), which the controller removes. Sized once at start-up; nothing after that
// allocates.
#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "artefact/pi_parameters.hpp"

namespace flexloop::controller::runtime {

template <class Vector>
class CommandHistory {
 public:
  /// Start-up: n channels, every command zero.
  void resize(Eigen::Index n) { entries_.assign(kEntries, Vector::Zero(n)); }
  /// Every remembered command u (the actuator has been holding it).
  void fill(const Vector& u) noexcept {
    for (auto& e : entries_) e = u;
  }
  /// The last command sent (what the actuator holds now).
  const Vector& last() const noexcept { return entries_[index(0)]; }
  /// The command sent `back` samples before the last (0: the last), e.g. at a run's start.
  void set_earlier(int back, const Vector& u) noexcept { entries_[index(back)] = u; }
  /// When the actuator reports that it applied something else (e.g. a safe command).
  void replace_last(const Vector& u) noexcept { entries_[index(0)] = u; }
  /// u_{k-1-d}: the command the current measurement contains.
  const Vector& measured(int delay) const noexcept { return entries_[index(delay)]; }
  /// The command just sent becomes the last.
  void remember(const Vector& u) noexcept {
    head_ = head_ + 1 == kEntries ? 0 : head_ + 1;
    std::copy_n(u.data(), u.size(), entries_[static_cast<std::size_t>(head_)].data());
  }

 private:
  static constexpr int kEntries = artefact::kMaxFeedthroughDelay + 1;
  std::size_t index(int back) const noexcept {
    const int i = head_ - back;
    return static_cast<std::size_t>(i < 0 ? i + kEntries : i);
  }
  std::vector<Vector> entries_;
  int head_ = 0;
};

}  // namespace flexloop::controller::runtime
