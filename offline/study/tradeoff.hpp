// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What accuracy costs in time (doc/design.md §8): a scene's plant over discretisation method x rate
// x plant form x scalar x model order, each configuration measured in the same run against exact
// references:
//
//   hinf_error   relative H∞ error of the discrete frequency response against the exact plant
//                (the full model) as the loop drives it, over the band [f_lo, f_hi], f_hi the
//                smaller of the band (default 2 x the highest natural frequency) and 0.999 x
//                Nyquist: the floor's columns against the continuous G(jω) (the floor is a
//                continuous signal the loop samples), the actuators' columns against G behind
//                the zero-order hold their DAC applies (exactly the full model's ZOH
//                discretisation). Per input-output pair max_f |H_ij - G_ij| / max_f |G_ij|, the
//                worst pair (so that N and m/s^2 channels weigh alike); a pair whose peak is below
//                1e-3 x the largest among the pairs of its units (a coupling symmetry nearly
//                cancels) is judged against that instead of against itself. The scalar enters as
//                the runtime stores the plant: Ad - I (or Λ - I), Bd, Cd, Dd rounded to it.
//   dc_error     the same at f = 0 (z = 1), relative to each pair's peak; NaN when the plant has
//                a pole at the origin.
//   step_error   open loop, a unit step on every input at once, on the runtime kernel of the
//                configuration (its form and scalar), against the full model discretised by ZOH
//                in double at the same rate, which is exact at the samples for a step: worst
//                output's max_k |y - y_ref| / max_k |y_ref|.
//   closed_loop_error, closed_loop_rms_error
//                the scene's floor (its spectrum and seed, from rest) through the scene's
//                controller at the configuration's rate, on the configuration's kernels, against
//                the same loop with the full model by exact ZOH in double at that rate (the same
//                floor samples and controller, so what differs is the plant alone): worst
//                performance output's RMS(z - z_ref) / RMS(z_ref), and | RMS(z)/RMS(z_ref) - 1 |.
//                Hardware effects are left out: they are the same in every configuration.
//   ns_per_step  the closed-loop step (plant output + controller + plant advance) on the kernels
//                `flexloop sim` uses for it (a compiled loop where one matches, in double with the
//                PI; otherwise the general path, sized at start-up) timed in-process: `repeats`
//                runs of `bench_steps` steps (each after a tenth of them untimed), round-robin
//                over the configurations so that the machine's slow and fast phases fall on all
//                of them alike; median and spread; period_share = ns_per_step / period. Each
//                configuration's loop is kept until the timing: a sweep of large dense plants
//                holds them all (2000 states: 64 MB each in double).
//
// A configuration a method cannot discretise (forward Euler of a lightly damped mode) or a form
// it cannot take (the modal form of a defective plant) is kept as a row with its reason.
#include <functional>
#include <string>
#include <vector>

#include "artefact/loop_schema.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/discretise.hpp"

namespace flexloop::study {

/// The scalar the runtime kernels step in.
enum class Scalar { kDouble, kFloat };
/// The plant a row discretises: the full model, or a reduced one.
enum class Reduction { kFull, kModal, kModalDc, kBalanced };

/// "double", "float".
std::string to_string(Scalar s);
/// "full", "modal", "modal-dc", "balanced".
std::string to_string(Reduction r);

struct Configuration {
  plant::lti::DiscretisationMethod method = plant::lti::DiscretisationMethod::kZeroOrderHold;
  bool prewarp = false;  ///< Tustin pre-warped at the lowest natural frequency
  double rate_hz = 0;
  artefact::PlantForm form = artefact::PlantForm::kDense;
  Scalar scalar = Scalar::kDouble;
  Reduction reduction = Reduction::kFull;
  int order = 0;  ///< states of the plant

  /// "zoh", "foh", "tustin", "tustin-prewarp", "backward-euler", "euler" (the --methods names).
  std::string method_name() const;
  std::string label() const;  ///< e.g. "zoh 10000 Hz dense double full 12"
};

struct Measurement {
  Configuration config;
  std::string skipped;  ///< empty: measured; else why not
  double hinf_error = 0, dc_error = 0, step_error = 0;
  double closed_loop_error = 0, closed_loop_rms_error = 0;
  double ns_per_step = 0, ns_min = 0, ns_max = 0;  ///< median, and the spread of the repeats
  double period_share = 0;
  /// balanced: the a-priori bound 2 Σ σ_discarded (absolute); else NaN
  double reduction_bound = 0;
  /// "compiled" (a fast path of plant/runtime/compiled_loops.hpp) or "general"
  std::string kernel;
  double closed_loop_radius = 0;  ///< spectral radius of the sampled closed loop (> 1: unstable)
};

/// What the front and the budget call cost: the closed-loop step's time, or the share of the
/// sample period it takes (its time x the rate: what a real-time core or a simulation pays per
/// simulated second).
enum class Cost { kStep, kShare };

struct TradeoffOptions {
  std::vector<std::string> methods{"zoh",  "foh", "tustin", "tustin-prewarp", "backward-euler",
                                   "euler"};
  std::vector<double> rates_hz;  ///< empty: the scene's rate / 10, / 2, x 1, x 2
  std::vector<std::string> forms{"dense", "modal"};
  std::vector<std::string> scalars{"double", "float"};
  std::vector<std::string> reductions{"modal", "modal-dc", "balanced"};
  std::vector<int> orders;  ///< reduced orders; empty: about 3/4, 1/2 and 1/4 of the full order
  double band_hz = 0;       ///< 0: 2 x the highest natural frequency
  int points = 300;         ///< frequency grid (log-spaced, plus each mode's frequency)
  double run_s = 0.5;       ///< closed-loop and step runs, simulated seconds
  long bench_steps = 5000;
  int repeats = 15;
  Cost cost = Cost::kStep;
  /// Called before each configuration: done so far, total.
  std::function<void(std::size_t, std::size_t, const Configuration&)> progress;
};

struct TradeoffResult {
  std::vector<Measurement> rows;
  Configuration default_config;  ///< the scene's method and rate, dense, double, full order
  int full_order = 0;
  double band_low_hz = 0, band_hz = 0;
  double prewarp_hz = 0;    ///< tustin-prewarp's frequency: the lowest natural frequency
  Cost cost = Cost::kStep;  ///< as the options asked
};

/// ns_per_step or period_share.
double cost_of(const Measurement& m, Cost cost);

/// @throws flexloop::InputError naming the scene for options it cannot take (an unknown method,
///         a rate <= 0, an order outside 1 .. full order).
TradeoffResult run_tradeoff(const scene::ScenePlant& p, const TradeoffOptions& o);

/// Index of the cheapest measured row (r.cost) with hinf_error <= budget; -1: none.
long cheapest_within(const TradeoffResult& r, double budget);

/// Indices of the measured rows on the Pareto front of (cost, hinf_error): no other row is at
/// most as costly and at most as wrong and better in one. Sorted by cost.
std::vector<std::size_t> pareto_front(const TradeoffResult& r);

}  // namespace flexloop::study
