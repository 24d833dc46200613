// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// How many channels of one kind a loop takes, for the whole project: the artefact's channel map,
// the LCM messages (one sample of 64 sensors and 64 performance channels is one UDP datagram) and
// the start-up-sized (general) runtime path. Disturbances,
// actuators, performance outputs and sensors may each number 1 .. kMaxChannels; the state count
// has no limit beyond memory. Vectors of channels are Eigen's bounded dynamic vectors, whose
// storage is inline (no allocation when sized, copied or returned); states live in vectors
// allocated once at start-up.
#include <Eigen/Core>

namespace flexloop::numeric {

inline constexpr int kMaxChannels = 64;

/// A vector of up to `kMaxRows` entries, sized at start-up, stored inline.
template <typename Scalar, int kMaxRows>
using BoundedVector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1, 0, kMaxRows, 1>;

/// Storage rows of an N-channel vector: N, or kMaxChannels for N = Eigen::Dynamic.
template <int N>
inline constexpr int kChannelRows = N == Eigen::Dynamic ? kMaxChannels : N;

/// A vector of N channels: fixed-size for a compiled N (the same type as Eigen::Matrix<Scalar, N,
/// 1>), bounded (inline, up to kMaxChannels) for N = Eigen::Dynamic.
template <class Scalar, int N>
using ChannelsOf = Eigen::Matrix<Scalar, N, 1, 0, kChannelRows<N>, 1>;

}  // namespace flexloop::numeric
