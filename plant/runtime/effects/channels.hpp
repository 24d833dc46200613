#pragma once
// Shared vocabulary of the simulated-hardware effects (DESIGN.md §6): N channels (one per strut
// or sensor) of Scalar (double or float) at run time, SI parameters in double at start-up.
// Every effect is a small class with fixed-size state, a static from_parameters(...) start-up
// constructor that validates and throws std::invalid_argument naming the effect and the
// offending value, and a noexcept step that does not allocate, lock, throw or make system calls.
#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N>
using ChannelVector = Eigen::Matrix<Scalar, N, 1>;

/// Start-up parameters, one value per channel, SI units.
template <int N>
using ChannelParameters = Eigen::Matrix<double, N, 1>;

/// One flag per channel (e.g. which actuators saturated this step).
template <int N>
using ChannelFlags = Eigen::Array<bool, N, 1>;

template <class Scalar, int N>
inline constexpr bool kValidChannels = std::is_floating_point_v<Scalar>&& N >= 1;

/// Throws std::invalid_argument("<effect>: <what>") unless ok.
inline void require(bool ok, const char* effect, const std::string& what) {
  if (!ok) throw std::invalid_argument(std::string(effect) + ": " + what);
}

/// Throws unless every entry of v is finite and satisfies `valid`; the message names the channel.
template <int N, class Predicate>
void require_each(const ChannelParameters<N>& v, const char* effect, const char* name,
                  const char* condition, Predicate valid) {
  for (int c = 0; c < N; ++c)
    require(std::isfinite(v(c)) && valid(v(c)), effect,
            std::string(name) + " of channel " + std::to_string(c) + " is " + std::to_string(v(c)) +
                ", must be " + condition);
}

}  // namespace flexloop::plant::runtime::effects
