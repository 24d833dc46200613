// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// How a continuous plant is sampled: the one enum of the discretisation methods, which the
// offline discretisation (plant/lti/discretise.hpp) computes with and the loop artefact
// (artefact/loop_schema.hpp) records. Here, on the bottom floor, so that both name the same type
// without one including the other (doc/design.md §2); each keeps its own names for it (the
// artefact's schema names, the offline command line's).

namespace flexloop::numeric {

enum class DiscretisationMethod {
  kZeroOrderHold,
  kFirstOrderHold,
  kTustin,
  kForwardEuler,
  kBackwardEuler
};

}  // namespace flexloop::numeric
