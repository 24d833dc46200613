// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Shared vocabulary of the simulated-hardware effects (doc/design.md §6): N channels (one per strut
// or sensor) of Scalar (double or float) at run time, SI parameters in double at start-up.
// Every effect is a small class with fixed-size state, a static from_parameters(...) start-up
// constructor that validates and throws std::invalid_argument naming the effect and the
// offending value, and a noexcept step that does not allocate, lock, throw or make system calls.
//
// N is a compile-time channel count (the compiled fast paths), or Eigen::Dynamic: the count is
// then set at start-up (1 .. kMaxChannels) and the vectors are Eigen's bounded dynamic vectors,
// whose storage is inline (kMaxChannels entries): sized once, they never allocate, and a step
// may return them by value as it does fixed-size ones.
#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "numeric/channel_limits.hpp"

namespace flexloop::plant::runtime::effects {

using numeric::kChannelRows;
using numeric::kMaxChannels;

/// The channel count of an N-channel effect built for n channels: N when N is compiled in.
/// @throws std::invalid_argument naming the effect for n outside 1 .. kChannelRows<N> or n != N.
template <int N>
int channel_count(const char* effect, Eigen::Index n) {
  if (n < 1 || n > numeric::kChannelRows<N> || (N != Eigen::Dynamic && n != N))
    throw std::invalid_argument(
        std::string(effect) + ": " + std::to_string(n) + " channels; this build takes " +
        (N == Eigen::Dynamic ? "1 .. " + std::to_string(numeric::kMaxChannels)
                             : std::to_string(N)));
  return static_cast<int>(n);
}

template <class Scalar, int N>
using ChannelVector = numeric::ChannelsOf<Scalar, N>;

/// Start-up parameters, one value per channel, SI units.
template <int N>
using ChannelParameters = Eigen::Matrix<double, N, 1, 0, numeric::kChannelRows<N>, 1>;

/// One flag per channel (e.g. which actuators saturated this step).
template <int N>
using ChannelFlags = Eigen::Array<bool, N, 1, 0, numeric::kChannelRows<N>, 1>;

template <class Scalar, int N>
inline constexpr bool kValidChannels = std::is_floating_point_v<Scalar> &&
                                       (N >= 1 || N == Eigen::Dynamic);

/// n channels of one value each (n = N when N is compiled in).
template <int N>
ChannelParameters<N> constant_parameters(Eigen::Index n, double value) {
  return ChannelParameters<N>::Constant(n, value);
}

/// Throws std::invalid_argument("<effect>: <what>") unless ok.
inline void require(bool ok, const char* effect, const std::string& what) {
  if (!ok) throw std::invalid_argument(std::string(effect) + ": " + what);
}

/// Throws unless every entry of v is finite and satisfies `valid`; the message names the channel.
template <int N, class Predicate>
void require_each(const ChannelParameters<N>& v, const char* effect, const char* name,
                  const char* condition, Predicate valid) {
  for (Eigen::Index c = 0; c < v.size(); ++c)
    require(std::isfinite(v(c)) && valid(v(c)), effect,
            std::string(name) + " of channel " + std::to_string(c) + " is " + std::to_string(v(c)) +
                ", must be " + condition);
}

}  // namespace flexloop::plant::runtime::effects
