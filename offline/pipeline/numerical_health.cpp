// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/numerical_health.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "plant/lti/balanced_exponential.hpp"
#include "plant/lti/modal_form.hpp"
#include "plant/model/massless_condensation.hpp"
#include "plant/runtime/pole_precision.hpp"

namespace flexloop::pipeline {

namespace {

// The largest ‖A T‖_1 the stiff-exponential tests cover (tests/discretise).
constexpr double kTestedNormAT = 1e8;

std::string text(const std::ostringstream& os) {
  return os.str();
}

bool is_hold(plant::lti::DiscretisationMethod m) {
  return m == plant::lti::DiscretisationMethod::kZeroOrderHold ||
         m == plant::lti::DiscretisationMethod::kFirstOrderHold;
}

HealthCheck exponential(const scene::ScenePlant& p, const plant::lti::DiscreteStateSpace& d) {
  std::ostringstream f;
  f.precision(3);
  if (!is_hold(d.method)) {
    f << "|A T|_1 = " << plant::lti::induced_norm_1(p.plant.A * d.dt);
    return {"exponential", text(f),
            plant::lti::to_string(d.method) + ": no exponential (LU solves)", true};
  }
  // The matrix the hold exponentiates, as discretise builds it, before and after balancing.
  const Eigen::MatrixXd hold = plant::lti::hold_matrix(p.plant, d.method, d.dt);
  const double raw = plant::lti::induced_norm_1(hold);
  f << "|" << plant::lti::to_string(d.method) << " matrix|_1 = " << raw << ", balanced "
    << plant::lti::induced_norm_1(plant::lti::balance(hold).balanced);
  HealthCheck c{"exponential", text(f),
                "Eigen's Pade exponential of the matrix balanced by powers of two",
                raw <= kTestedNormAT};
  if (!c.ok) c.verdict += "; beyond the tested range (<= 1e8): check the result";
  return c;
}

HealthCheck above_nyquist(const scene::ScenePlant& p, const plant::lti::DiscreteStateSpace& d) {
  const double nyquist = 0.5 / d.dt;
  int count = 0;
  double highest = 0;
  for (double f : p.natural_frequencies_hz)
    if (f > nyquist) {
      ++count;
      highest = std::max(highest, f);
    }
  std::ostringstream f;
  f.precision(4);
  f << count << " of " << p.natural_frequencies_hz.size() << " modes above " << nyquist << " Hz";
  if (count > 0) f << " (highest " << highest << " Hz, " << highest / nyquist << " x Nyquist)";
  const bool holds = is_hold(d.method);
  std::string verdict = count == 0 ? "none"
                        : holds    ? "sampled exactly (aliased, as hardware sees them)"
                                   : "warped into the band by " + plant::lti::to_string(d.method);
  return {"modes above Nyquist", text(f), verdict, true};
}

HealthCheck statics(const scene::ScenePlant& p) {
  return {"static stability", plant::lti::to_string(p.statics),
          p.statics.stable() ? "runs" : "build, sim, plant, controller and hil refuse it",
          p.statics.stable()};
}

HealthCheck mass_matrix(const scene::ScenePlant& p) {
  const int nd = p.model.nd();
  if (nd == 0) return {"mass matrix", "no dynamic coordinates", "nothing to condense", true};
  const Eigen::MatrixXd Mdd = p.lin.M.topLeftCorner(nd, nd);
  const Eigen::VectorXd mu = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(
                                 0.5 * (Mdd + Mdd.transpose()), Eigen::EigenvaluesOnly)
                                 .eigenvalues();
  const double largest = mu.cwiseAbs().maxCoeff();
  int massless = 0;
  double smallest = std::numeric_limits<double>::infinity();
  for (double m : mu) {
    // The builder's own threshold (build_state_space condenses these directions).
    if (m <= plant::model::CondensationOptions{}.relative_mass_tolerance * largest)
      ++massless;
    else
      smallest = std::min(smallest, m);
  }
  std::ostringstream f;
  f.precision(3);
  f << "cond(Mdd) = " << largest / smallest << " over " << nd - massless << " massive directions, "
    << massless << " massless";
  const bool ok = largest / smallest < 1e12;
  std::string verdict = massless > 0 ? "massless directions condensed statically" : "regular";
  if (!ok) verdict += "; badly conditioned (> 1e12): check units and tiny masses";
  return {"mass matrix", text(f), verdict, ok};
}

HealthCheck sampled_loop(const scene::ScenePlant& p,
                         const std::optional<SampledLoopStability>& loop) {
  if (scene::has_fmu_controller(p))
    return {"sampled loop", "controller FMU, no matrices", "by simulation below", true};
  if (!scene::has_controller(p)) return {"sampled loop", "no controller", "plant alone", true};
  if (!loop) return {"sampled loop", "not formed", "see the sampled loop's line above", false};
  std::ostringstream f;
  f.precision(6);
  f << "spectral radius " << loop->spectral_radius;
  return {"sampled loop", text(f),
          loop->stable() ? "stable" : "unstable: the loop commands refuse it", loop->stable()};
}

HealthCheck float_headroom(const plant::lti::DiscreteStateSpace& d) {
  plant::lti::ModalForm m;
  try {
    m = plant::lti::to_modal_form(d);
  } catch (const std::invalid_argument& e) {
    return {"float", "no modal form: " + std::string(e.what()), "float not assessed", true};
  }
  double headroom = std::numeric_limits<double>::infinity(), worst_change = 0;
  int refused = 0, decaying = 0;
  for (Eigen::Index i = 0, b = 0; b < static_cast<Eigen::Index>(m.block_sizes.size()); ++b) {
    const int size = m.block_sizes[static_cast<std::size_t>(b)];
    const double a = m.Lambda_minus_I(i, i), im = size == 2 ? m.Lambda_minus_I(i, i + 1) : 0.0;
    i += size;
    const auto margin = plant::runtime::pole_margin<float>(a, im);
    // On the circle (integrators, undamped modes): marginal in double already.
    if (!(margin.exact < 0) || plant::runtime::on_unit_circle(a, im, margin.exact)) continue;
    decaying += size;
    if (!margin.kept()) refused += size;
    worst_change = std::max(worst_change, margin.decay_change());
    const double shift = std::abs(margin.stored - margin.exact);
    if (shift > 0) headroom = std::min(headroom, -margin.exact / shift);
  }
  std::ostringstream f, v;
  f.precision(3);
  f << decaying << " decaying poles, smallest headroom " << headroom
    << " (distance to |z| = 1 over float's shift of it), decay changed by up to "
    << 100 * worst_change << " %";
  if (refused == 0)
    v << "float keeps every decaying pole inside, within " << 100 * plant::runtime::kDecayTolerance
      << " % of its decay";
  else
    v << refused << " poles would decay more than " << 100 * plant::runtime::kDecayTolerance
      << " % off, or not at all, in float: the float plants refuse them";
  return {"float", text(f), text(v), refused == 0};
}

}  // namespace

std::vector<HealthCheck> numerical_health(const scene::ScenePlant& p,
                                          const plant::lti::DiscreteStateSpace& sampled_plant,
                                          const std::optional<SampledLoopStability>& loop) {
  return {statics(p),     exponential(p, sampled_plant), above_nyquist(p, sampled_plant),
          mass_matrix(p), sampled_loop(p, loop),         float_headroom(sampled_plant)};
}

void print_health(const std::vector<HealthCheck>& checks) {
  std::printf("numerical health:\n");
  for (const HealthCheck& c : checks)
    std::printf("  %-4s %-19s %s: %s\n", c.ok ? "ok" : "WARN", c.name.c_str(), c.figures.c_str(),
                c.verdict.c_str());
}

nlohmann::json health_json(const std::vector<HealthCheck>& checks) {
  nlohmann::json out = nlohmann::json::array();
  for (const HealthCheck& c : checks)
    out.push_back(
        {{"check", c.name}, {"figures", c.figures}, {"verdict", c.verdict}, {"ok", c.ok}});
  return out;
}

}  // namespace flexloop::pipeline
