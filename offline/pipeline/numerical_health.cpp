#include "offline/pipeline/numerical_health.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "plant/lti/balanced_exponential.hpp"
#include "plant/lti/modal_form.hpp"
#include "plant/runtime/pole_precision.hpp"

namespace flexloop::cli {

namespace {

// The largest ‖A T‖_1 the stiff-exponential tests cover (tests/discretise).
constexpr double kTestedNormAT = 1e8;
// Mass eigenvalues below this fraction of the largest are massless (condensed).
constexpr double kMasslessFraction = 1e-12;

std::string text(const std::ostringstream& os) {
  return os.str();
}

HealthCheck exponential(const scene::ScenePlant& p, const plant::lti::DiscreteStateSpace& d) {
  const Eigen::MatrixXd AT = p.plant.A * d.dt;
  const double raw = plant::lti::induced_norm_1(AT);
  const bool holds = d.method == plant::lti::DiscretisationMethod::kZeroOrderHold ||
                     d.method == plant::lti::DiscretisationMethod::kFirstOrderHold;
  std::ostringstream f;
  f.precision(3);
  f << "|A T|_1 = " << raw;
  if (holds) f << ", balanced " << plant::lti::induced_norm_1(plant::lti::balance(AT).balanced);
  HealthCheck c{"exponential", text(f), "", raw <= kTestedNormAT};
  c.verdict = holds ? "exponential of the balanced augmented matrix (powers of two), Eigen's Pade"
                    : to_string(d.method) + ": no exponential (LU solves)";
  if (!c.ok) c.verdict += "; beyond the tested range (|A T| <= 1e8): check the result";
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
  const bool holds = d.method == plant::lti::DiscretisationMethod::kZeroOrderHold ||
                     d.method == plant::lti::DiscretisationMethod::kFirstOrderHold;
  std::string verdict = count == 0 ? "none"
                        : holds    ? "sampled exactly (aliased, as hardware sees them)"
                                   : "warped into the band by " + to_string(d.method);
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
    if (m <= kMasslessFraction * largest)
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

HealthCheck sampled_loop(std::optional<double> radius) {
  if (!radius) return {"sampled loop", "no controller", "plant alone", true};
  std::ostringstream f;
  f.precision(6);
  f << "spectral radius " << *radius;
  const bool ok = *radius <= 1 + 1e-9;
  return {"sampled loop", text(f), ok ? "stable" : "unstable: the loop commands refuse it", ok};
}

HealthCheck float_headroom(const plant::lti::DiscreteStateSpace& d) {
  plant::lti::ModalForm m;
  try {
    m = plant::lti::to_modal_form(d);
  } catch (const std::invalid_argument&) {
    return {"float", "no modal form (defective Ad)", "dense form only; run in double", true};
  }
  double headroom = std::numeric_limits<double>::infinity();
  int lost = 0, decaying = 0;
  for (Eigen::Index i = 0, b = 0; b < static_cast<Eigen::Index>(m.block_sizes.size()); ++b) {
    const bool pair = m.block_sizes[b] == 2;
    const double a = m.Lambda_minus_I(i, i), im = pair ? m.Lambda_minus_I(i, i + 1) : 0.0;
    i += m.block_sizes[b];
    const auto margin = plant::runtime::pole_margin<float>(a, im);
    if (!(margin.exact < 0)) continue;  // on the circle (integrators, undamped): marginal anyway
    ++decaying;
    if (margin.stored >= 0) ++lost;
    const double shift = std::abs(margin.stored - margin.exact);
    if (shift > 0) headroom = std::min(headroom, -margin.exact / shift);
  }
  std::ostringstream f;
  f.precision(3);
  f << decaying << " decaying poles, smallest headroom " << headroom
    << " (distance to |z| = 1 over float's shift of it)";
  return {"float", text(f),
          lost == 0 ? "float keeps every decaying pole inside"
                    : std::to_string(lost) + " poles would not decay in float: run in double",
          lost == 0};
}

}  // namespace

std::vector<HealthCheck> numerical_health(const scene::ScenePlant& p,
                                          const plant::lti::DiscreteStateSpace& sampled_plant,
                                          std::optional<double> sampled_loop_radius) {
  return {statics(p),     exponential(p, sampled_plant),     above_nyquist(p, sampled_plant),
          mass_matrix(p), sampled_loop(sampled_loop_radius), float_headroom(sampled_plant)};
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

}  // namespace flexloop::cli
