// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Piezo actuator: command u (the controller's actuator output, e.g. σa in N) to strut force f.
//   c = g ⊙ u                          commanded force [N], g force per command unit
//   s = clamp(c, f_min, f_max)        stroke/voltage limits expressed as force [N]
//   f = s                              (kLagged = false)
//   f = FirstOrderLag(τ).step(s)       (kLagged = true: the amplifier/piezo bandwidth; the sample's
//                                       mean force, see first_order_lag.hpp)
// The limits act on the command, before the lag, as an amplifier's voltage limit does; the lagged
// force therefore stays within them too. After each step saturated() tells which channels were
// clipped and unsaturated_force() - limited_force() by how much, for the PI controller's
// anti-windup. A NaN command gives zero force and counts as saturated; ±inf clip to the limits.
// Whether the lag exists is a template parameter, so an actuator without it pays nothing for it.
#include <limits>
#include <type_traits>

#include "plant/runtime/effects/channels.hpp"
#include "plant/runtime/effects/first_order_lag.hpp"

namespace flexloop::plant::runtime::effects {

template <int N>
struct PiezoActuatorParameters {
  /// Unit gain, no lag and limits still to set (NaN), for n channels (n = N when N is compiled in).
  PiezoActuatorParameters() : PiezoActuatorParameters(N == Eigen::Dynamic ? 1 : N) {}
  explicit PiezoActuatorParameters(Eigen::Index n)
      : gain(ChannelParameters<N>::Ones(n)),
        force_min(ChannelParameters<N>::Constant(n, std::numeric_limits<double>::quiet_NaN())),
        force_max(ChannelParameters<N>::Constant(n, std::numeric_limits<double>::quiet_NaN())),
        lag_time_constant(ChannelParameters<N>::Zero(n)) {}
  ChannelParameters<N> gain;       ///< g [N per command unit], != 0
  ChannelParameters<N> force_min;  ///< [N]
  ChannelParameters<N> force_max;  ///< [N]
  /// τ [s]; must be > 0 for a lagged actuator and 0 for one without a lag.
  ChannelParameters<N> lag_time_constant;
};

template <class Scalar, int N, bool kLagged = false>
class PiezoActuator {
  static_assert(kValidChannels<Scalar, N>);
  struct NoLag {};
  using Lag = std::conditional_t<kLagged, FirstOrderLag<Scalar, N>, NoLag>;

 public:
  using Vector = ChannelVector<Scalar, N>;

  /// dt [s] is the sample time (used by the lag only).
  /// @throws std::invalid_argument when a gain is zero or not finite, a limit is not finite or
  ///         force_min >= force_max, or the lag time constants do not match kLagged.
  static PiezoActuator from_parameters(const PiezoActuatorParameters<N>& p, double dt) {
    constexpr const char* kName = "piezo actuator";
    const int n = channel_count<N>(kName, p.gain.size());
    require(p.force_min.size() == n && p.force_max.size() == n && p.lag_time_constant.size() == n,
            kName, "gain, limits and lag time constants must have one value per channel");
    require_each<N>(p.gain, kName, "gain", "!= 0", [](double v) { return v != 0; });
    require_each<N>(p.force_min, kName, "force_min [N]", "finite", [](double) { return true; });
    require_each<N>(p.force_max, kName, "force_max [N]", "finite", [](double) { return true; });
    for (int c = 0; c < n; ++c)
      require(p.force_min(c) < p.force_max(c), kName,
              "channel " + std::to_string(c) + ": force_min " + std::to_string(p.force_min(c)) +
                  " N is not below force_max " + std::to_string(p.force_max(c)) + " N");
    if constexpr (kLagged) {
      return PiezoActuator(p, FirstOrderLag<Scalar, N>::from_parameters(p.lag_time_constant, dt));
    } else {
      require_each<N>(p.lag_time_constant, kName, "lag time constant [s]",
                      "0 (this actuator type has no lag; use PiezoActuator<..., true>)",
                      [](double v) { return v == 0; });
      return PiezoActuator(p, NoLag{});
    }
  }

  /// Command u_k held over the sample; returns the force the struts get during it.
  // Eigen expressions with the packets of the stages around it: no branch per channel, and no
  // change of SIMD width that would pass the force through memory.
  Vector step(const Vector& command) noexcept {
    unsaturated_ = gain_.cwiseProduct(command);
    const auto commanded = unsaturated_.array();
    // A NaN command as zero: max(0, c) + min(0, c) is c for every number and 0 for NaN (std::max
    // and std::min return their first argument when the second is NaN; so do Eigen's).
    const auto zero = Vector::Zero(command.size()).array();
    const auto finite = zero.max(commanded) + zero.min(commanded);
    limited_ = finite.max(min_.array()).min(max_.array()).matrix();
    saturated_ = limited_.array() != commanded;  // NaN != anything: a NaN counts as saturated
    if constexpr (kLagged)
      return lag_.step(limited_);
    else
      return limited_;
  }

  /// The lag's force at this instant (a run's start); nothing without a lag.
  void set_lag_state(const Vector& force) noexcept {
    if constexpr (kLagged) lag_.reset(force);
  }

  /// Which channels the last step clipped.
  const ChannelFlags<N>& saturated() const noexcept { return saturated_; }
  /// g ⊙ u of the last step, before the limits (NaN kept).
  const Vector& unsaturated_force() const noexcept { return unsaturated_; }
  /// The last step's force after the limits, before the lag.
  const Vector& limited_force() const noexcept { return limited_; }
  const Vector& force_min() const noexcept { return min_; }
  const Vector& force_max() const noexcept { return max_; }

 private:
  PiezoActuator(const PiezoActuatorParameters<N>& p, Lag lag)
      : gain_(p.gain.template cast<Scalar>()),
        min_(p.force_min.template cast<Scalar>()),
        max_(p.force_max.template cast<Scalar>()),
        unsaturated_(Vector::Zero(p.gain.size())),
        limited_(Vector::Zero(p.gain.size())),
        saturated_(ChannelFlags<N>::Constant(p.gain.size(), false)),
        lag_(lag) {}
  Vector gain_, min_, max_;
  Vector unsaturated_, limited_;
  ChannelFlags<N> saturated_;
  [[no_unique_address]] Lag lag_;
};

}  // namespace flexloop::plant::runtime::effects
