// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/reduction_error.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "numeric/constants.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/model/superelement_residual.hpp"

namespace flexloop::plant::lti {

namespace {

using numeric::kTwoPi;
using Complex = std::complex<double>;

// A body's interface rows the machine moves (a fixed interface translation has no motion, so its
// rows of Delta act on nothing): indices into body.interface_coordinates.
std::vector<int> moving_rows(const model::Model& m, const model::Superelement& body) {
  std::vector<int> rows;
  for (std::size_t r = 0; r < body.interface_coordinates.size(); ++r)
    if (m.coordinate_roles[static_cast<std::size_t>(body.interface_coordinates[r])] !=
        model::CoordinateRole::kFixed)
      rows.push_back(static_cast<int>(r));
  return rows;
}

// u = T q for the body's reduced coordinates (interface rows of DF(x), then unit rows for its
// modal amplitudes), as linearise joins the body.
Eigen::MatrixXd body_map(const model::Model& m, const model::Linearisation& lin,
                         const model::Superelement& body) {
  const auto nb = static_cast<Eigen::Index>(body.interface_coordinates.size());
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(nb + body.mode_count(), m.nq());
  for (Eigen::Index r = 0; r < nb; ++r)
    T.row(r) = lin.DFx.row(body.interface_coordinates[static_cast<std::size_t>(r)]);
  for (int k = 0; k < body.mode_count(); ++k) {
    const auto label = std::find(m.generalised.begin(), m.generalised.end(), body.mode_labels[k]);
    T(nb + k, label - m.generalised.begin()) = 1.0;
  }
  return T;
}

// The body's damping ratio: D = M Phi diag(2 zeta w) Phi' M over its own modes (the reader's
// modal damping), read back from its highest mode; 0 for an undamped body.
double body_zeta(const model::Superelement& body) {
  if (body.D.isZero(0.0)) return 0.0;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(body.K, body.M);
  const Eigen::Index last = body.K.rows() - 1;
  const double w = std::sqrt(std::max(modes.eigenvalues()(last), 0.0));
  if (!(w > 0)) return 0.0;
  const Eigen::VectorXd phi = modes.eigenvectors().col(last);
  return phi.dot(body.D * phi) / (2 * w);
}

BodyComparison compare_body(const model::Superelement& body, double lowest_hz, double band_hz) {
  BodyComparison c;
  c.id = body.id;
  c.cut_off_hz = body.modes_up_to_hz;
  c.modes_kept = body.mode_count();
  c.interface_dofs = static_cast<int>(body.interface_coordinates.size());
  c.full_dofs = static_cast<long>(body.full_dofs);
  const double zeta = body_zeta(body);
  c.zeta_is_the_body_s = zeta > 0;
  c.zeta = zeta > 0 ? zeta : 0.01;
  c.high_hz = band_hz;
  c.low_hz = lowest_hz > 0 && lowest_hz < band_hz / 2 ? lowest_hz : band_hz / 100;
  // zeta_k = alpha / (2 w_k) + beta w_k / 2 = zeta at w_1 and w_2, at least 2 zeta sqrt(w_1 w_2)
  // / (w_1 + w_2) between.
  const double w1 = kTwoPi * c.low_hz, w2 = kTwoPi * c.high_hz;
  c.alpha = 2 * c.zeta * w1 * w2 / (w1 + w2);
  c.beta = 2 * c.zeta / (w1 + w2);
  return c;
}

// The linearisation with each body's damping replaced by its Rayleigh damping.
model::Linearisation with_rayleigh(const model::Model& m, const model::Linearisation& lin,
                                   const std::vector<BodyComparison>& bodies) {
  model::Linearisation out = lin;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const auto& body = m.superelements[i];
    const Eigen::MatrixXd T = body_map(m, lin, body);
    const Eigen::MatrixXd D = bodies[i].alpha * body.M + bodies[i].beta * body.K - body.D;
    out.D += T.transpose() * D * T;
  }
  return out;
}

// Delta = S_full - S_red of every body at w (block diagonal over the bodies' moving interface
// rows), with each body's Rayleigh damping; `remainder` takes the worst series bound.
Eigen::MatrixXcd interface_delta(const model::Model& m, const std::vector<BodyComparison>& bodies,
                                 const std::vector<std::vector<int>>& rows, double w,
                                 double& remainder) {
  Eigen::Index n = 0;
  for (const auto& r : rows) n += static_cast<Eigen::Index>(r.size());
  Eigen::MatrixXcd delta = Eigen::MatrixXcd::Zero(n, n);
  Eigen::Index at = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Complex a(1.0, w * bodies[i].beta), b(w * w, -w * bodies[i].alpha);
    const model::ResidualStiffness s = model::residual_stiffness(m.superelements[i], a, b);
    remainder = std::max(remainder, s.remainder);
    const auto& r = rows[i];
    if (s.delta.size() > 0)
      for (std::size_t p = 0; p < r.size(); ++p)
        for (std::size_t q = 0; q < r.size(); ++q)
          delta(at + static_cast<Eigen::Index>(p), at + static_cast<Eigen::Index>(q)) =
              s.delta(r[p], r[q]);
    at += static_cast<Eigen::Index>(r.size());
  }
  return delta;
}

// G_full = P_yu - P_yf Delta (I + P_xf Delta)^-1 P_xu of the augmented response P.
Eigen::MatrixXcd full_response(const Eigen::MatrixXcd& P, Eigen::Index ny, Eigen::Index nu,
                               const Eigen::MatrixXcd& delta) {
  const Eigen::Index nf = delta.rows();
  if (nf == 0) return P.topLeftCorner(ny, nu);  // every interface translation fixed
  const Eigen::MatrixXcd inner =
      Eigen::MatrixXcd::Identity(nf, nf) + P.bottomRightCorner(nf, nf) * delta;
  const Eigen::MatrixXcd x = inner.partialPivLu().solve(P.bottomLeftCorner(nf, nu));
  return P.topLeftCorner(ny, nu) - P.topRightCorner(ny, nf) * (delta * x);
}

// The pairs' worst relative errors over the compared responses.
void pair_errors(const std::vector<Eigen::MatrixXcd>& red,
                 const std::vector<Eigen::MatrixXcd>& full, const std::vector<double>& f,
                 ReductionError& e) {
  const std::size_t ny = e.outputs.size(), nu = e.inputs.size();
  e.pairs.assign(ny * nu, PairError{});
  for (std::size_t o = 0; o < ny; ++o)
    for (std::size_t i = 0; i < nu; ++i) {
      PairError& p = e.pairs[o * nu + i];
      double peak = 0, worst = 0;
      for (std::size_t k = 0; k < f.size(); ++k) {
        const auto oi = static_cast<Eigen::Index>(o), ii = static_cast<Eigen::Index>(i);
        const double g = std::abs(full[k](oi, ii)), d = std::abs(red[k](oi, ii) - full[k](oi, ii));
        peak = std::max(peak, g);
        if (d > worst) worst = d, p.of_peak_hz = f[k];
        if (g > 0 && d / g > p.relative) p.relative = d / g, p.relative_hz = f[k];
      }
      p.compared = peak > 0;
      p.of_peak = p.compared ? worst / peak : 0.0;
    }
}

}  // namespace

namespace {

// Each body's moving interface rows of DF(x) on the dynamic coordinates.
std::vector<Eigen::MatrixXd> interface_maps(const model::Model& m, const model::Linearisation& lin,
                                            const std::vector<std::vector<int>>& rows) {
  std::vector<Eigen::MatrixXd> maps;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& body = m.superelements[i];
    Eigen::MatrixXd T(static_cast<Eigen::Index>(rows[i].size()), m.nd());
    for (std::size_t r = 0; r < rows[i].size(); ++r)
      T.row(static_cast<Eigen::Index>(r)) =
          lin.DFx.row(body.interface_coordinates[static_cast<std::size_t>(rows[i][r])])
              .head(m.nd());
    maps.push_back(std::move(T));
  }
  return maps;
}

// The full machine's k-th eigenvalue: lambda = lambda_k(K + sum T_b' Delta_b(lambda) T_b, M),
// undamped, by fixed-point iteration from the reduced machine's (monotone: Delta <= 0 falls with
// lambda, and is small beside K).
double full_eigenvalue(const model::Model& m, const Eigen::MatrixXd& M, const Eigen::MatrixXd& K,
                       const std::vector<std::vector<int>>& rows,
                       const std::vector<Eigen::MatrixXd>& maps, Eigen::Index k, double lambda) {
  for (int iteration = 0; iteration < 100; ++iteration) {
    Eigen::MatrixXd Kf = K;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const model::ResidualStiffness s =
          model::residual_stiffness(m.superelements[i], Complex(1.0), Complex(lambda));
      if (s.delta.size() == 0) continue;
      Eigen::MatrixXd d(maps[i].rows(), maps[i].rows());
      for (std::size_t p = 0; p < rows[i].size(); ++p)
        for (std::size_t q = 0; q < rows[i].size(); ++q)
          d(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(q)) =
              s.delta(rows[i][p], rows[i][q]).real();
      Kf += maps[i].transpose() * d * maps[i];
    }
    const double next = natural_modes(M, Kf).omega_squared(k).real();
    const bool settled = std::abs(next - lambda) <= 1e-15 * std::abs(lambda);
    lambda = next;
    if (settled) break;
  }
  return lambda;
}

// The reduced machine's natural frequencies up to the band and the full machine's.
void natural_frequencies(const model::Model& m, const model::Linearisation& lin,
                         const std::vector<std::vector<int>>& rows, const Modes& reduced,
                         ReductionError& e) {
  const int nd = m.nd();
  const Eigen::MatrixXd M = lin.M.topLeftCorner(nd, nd);
  const Eigen::MatrixXd K = (lin.K + lin.N + lin.G).topLeftCorner(nd, nd);
  const std::vector<Eigen::MatrixXd> maps = interface_maps(m, lin, rows);
  std::vector<double> red, full;
  for (Eigen::Index k = 0; k < reduced.frequencies_hz.size(); ++k) {
    const double f = reduced.frequencies_hz(k);
    if (f < 0) continue;  // statically unstable: no natural frequency
    if (f > e.band_hz) break;
    const double lambda = full_eigenvalue(m, M, K, rows, maps, k, reduced.omega_squared(k).real());
    red.push_back(f);
    full.push_back(std::sqrt(std::max(lambda, 0.0)) / kTwoPi);
  }
  e.reduced_hz =
      Eigen::Map<const Eigen::VectorXd>(red.data(), static_cast<Eigen::Index>(red.size()));
  e.full_hz =
      Eigen::Map<const Eigen::VectorXd>(full.data(), static_cast<Eigen::Index>(full.size()));
}

// The outputs the full machine has (not a body's modal amplitude), and the others.
void split_outputs(const model::Model& m, const std::vector<std::string>& outputs,
                   ReductionError& e) {
  for (const auto& name : outputs) {
    const std::string target = name.substr(name.find(':') + 1);
    bool modal = false;
    for (const auto& body : m.superelements)
      modal = modal || std::find(body.mode_labels.begin(), body.mode_labels.end(), target) !=
                           body.mode_labels.end();
    (modal ? e.left_out : e.outputs).push_back(name);
  }
}

// The reduced machine's lowest positive natural frequency (0: none).
double lowest_positive_hz(const Modes& modes, double cut_off_hz) {
  for (Eigen::Index k = 0; k < modes.frequencies_hz.size(); ++k)
    if (modes.frequencies_hz(k) > 1e-6 * cut_off_hz) return modes.frequencies_hz(k);
  return 0.0;
}

}  // namespace

ReductionError reduction_error(const model::Model& m, const model::Linearisation& lin,
                               const std::vector<std::string>& inputs,
                               const std::vector<std::string>& outputs,
                               const std::vector<double>& frequencies_hz, double up_to_hz) {
  ReductionError e;
  if (m.superelements.empty()) return e;
  for (const auto& body : m.superelements)
    if (body.residual_moments.empty())
      throw std::invalid_argument("superelement '" + body.id +
                                  "' was reduced without its unkept modes' moments: read the "
                                  "model after model::set_reduction_error_band_hz");
  const int nd = m.nd();
  Modes reduced;
  try {
    reduced =
        natural_modes(lin.M.topLeftCorner(nd, nd), (lin.K + lin.N + lin.G).topLeftCorner(nd, nd));
  } catch (const std::invalid_argument& x) {
    e.frequencies_note = x.what();
  }
  e.band_hz = up_to_hz;
  for (const auto& body : m.superelements) e.band_hz = std::min(e.band_hz, body.modes_up_to_hz / 2);
  std::vector<std::vector<int>> rows;
  std::vector<std::string> in = inputs;
  e.inputs = inputs;
  split_outputs(m, outputs, e);
  std::vector<std::string> out = e.outputs;
  for (const auto& body : m.superelements) {
    e.bodies.push_back(
        compare_body(body, lowest_positive_hz(reduced, body.modes_up_to_hz), e.band_hz));
    rows.push_back(moving_rows(m, body));
    for (const int r : rows.back()) {
      const std::string& label = m.coordinate_labels[static_cast<std::size_t>(
          body.interface_coordinates[static_cast<std::size_t>(r)])];
      in.push_back("force:" + label);
      out.push_back("pos:" + label);
    }
  }
  std::vector<double> f;
  for (const double fk : frequencies_hz)
    if (fk > 0 && fk <= e.band_hz) f.push_back(fk);
  if (!f.empty()) {
    e.lowest_hz = *std::min_element(f.begin(), f.end());
    e.highest_hz = *std::max_element(f.begin(), f.end());
  }
  e.points = static_cast<int>(f.size());
  const StateSpace P = build_state_space(m, with_rayleigh(m, lin, e.bodies), in, out);
  const std::vector<Eigen::MatrixXcd> responses = frequency_response(P, f);
  const auto ny = static_cast<Eigen::Index>(e.outputs.size()),
             nu = static_cast<Eigen::Index>(inputs.size());
  for (std::size_t k = 0; k < f.size(); ++k) {
    const Eigen::MatrixXcd delta = interface_delta(m, e.bodies, rows, kTwoPi * f[k], e.remainder);
    e.reduced.push_back(responses[k].topLeftCorner(ny, nu));
    e.full.push_back(full_response(responses[k], ny, nu, delta));
  }
  e.frequencies_hz = f;
  pair_errors(e.reduced, e.full, f, e);
  if (e.frequencies_note.empty()) natural_frequencies(m, lin, rows, reduced, e);
  return e;
}

}  // namespace flexloop::plant::lti
