// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/loop_figures.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/loop_start_builder.hpp"
#include "plant/lti/frequency_response.hpp"

namespace flexloop::pipeline {

bool closed_loop_stable(const scene::ScenePlant& p,
                        const std::optional<controller::design::SampledLoopStability>& sampled) {
  return p.loop.stable() && sampled && sampled->stable();
}

controller::design::InputDiskMargins loop_disk_margins(const scene::ScenePlant& p) {
  return controller::design::input_disk_margins(scene::sampled_loop_model(p));
}

plant::lti::StateSpace floor_to_performance(const scene::ScenePlant& p) {
  plant::lti::StateSpace g11 = p.plant;
  g11.B = p.plant.B.leftCols(p.partition.disturbances);
  g11.D = p.plant.D.topLeftCorner(p.partition.performance, p.partition.disturbances);
  g11.C = p.plant.C.topRows(p.partition.performance);
  g11.inputs.resize(static_cast<std::size_t>(p.partition.disturbances));
  g11.outputs.resize(static_cast<std::size_t>(p.partition.performance));
  return g11;
}

std::vector<Eigen::MatrixXcd> closed_loop_response(const scene::ScenePlant& p,
                                                   const scene::SampledScene* sampled,
                                                   const std::vector<double>& frequencies_hz) {
  if (scene::has_continuous_loop(p))
    return plant::lti::frequency_response(p.closed_loop, frequencies_hz);
  if (!sampled)
    throw std::invalid_argument(
        "closed_loop_response: a discrete controller needs the sampled scene");
  return plant::lti::frequency_response(sampled->closed_loop, frequencies_hz);
}

Eigen::VectorXd largest_singular_values(const std::vector<Eigen::MatrixXcd>& responses) {
  Eigen::VectorXd sigma(static_cast<Eigen::Index>(responses.size()));
  for (std::size_t k = 0; k < responses.size(); ++k)
    sigma(static_cast<Eigen::Index>(k)) = plant::lti::largest_singular_value(responses[k]);
  return sigma;
}

SampledAgainstDesign sampled_against_design(const scene::ScenePlant& p,
                                            const scene::SampledScene& sampled,
                                            const std::vector<double>& frequencies_hz) {
  SampledAgainstDesign r;
  const double nyquist_hz = 0.5 / sampled.closed_loop.dt;
  for (const double f : frequencies_hz)
    if (f < nyquist_hz) r.f.push_back(f);
  r.sampled = largest_singular_values(plant::lti::frequency_response(sampled.closed_loop, r.f));
  r.design = largest_singular_values(plant::lti::frequency_response(p.closed_loop, r.f));
  const Eigen::VectorXd open =
      largest_singular_values(plant::lti::frequency_response(floor_to_performance(p), r.f));
  r.excess_db = -std::numeric_limits<double>::infinity();
  r.judged_from_hz =
      p.natural_frequencies_hz.size() > 0 ? p.natural_frequencies_hz.minCoeff() / 10 : 0.0;
  r.judged_to_hz = nyquist_hz / 2;
  for (Eigen::Index k = 0; k < r.sampled.size(); ++k) {
    const double f = r.f[static_cast<std::size_t>(k)];
    if (f < r.judged_from_hz || f > r.judged_to_hz) continue;
    const double reference = std::max(r.design(k), open(k));
    const double excess = 20 * std::log10(r.sampled(k) / reference);
    if (excess > r.excess_db) {
      r.excess_db = excess;
      r.excess_hz = f;
    }
  }
  const Eigen::VectorXcd poles = p.plant.A.eigenvalues();
  for (const std::complex<double>& s : poles)
    r.modes_above_nyquist += s.imag() > 0 && std::abs(s) > 2 * std::numbers::pi * nyquist_hz;
  return r;
}

Eigen::VectorXd stationary_rms(const scene::ScenePlant& p, const scene::SampledScene& sampled,
                               bool closed) {
  const artefact::LoopArtefact a =
      scene::loop_artefact_without_start(p, sampled, artefact::PlantForm::kDense);
  return scene::stationary_moments(a, closed).performance_mean_square.cwiseSqrt();
}

}  // namespace flexloop::pipeline
