// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/modal_form.hpp"

#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace flexloop::plant::lti {

namespace {

constexpr double kResidualTolerance = 1e-10;

std::string refusal(const std::string& why) {
  return "to_modal_form: " + why +
         "; Ad is defective or nearly so (e.g. a double integrator), so it has no well-conditioned "
         "real block-diagonal form: use the dense form (DensePlant)";
}

// Balances M in place by a diagonal similarity with powers of two (exact): M <- S^-1 M S, and
// returns the diagonal of S. Numerical Recipes' balanc / LAPACK gebal without permutations.
Eigen::VectorXd balance(Eigen::MatrixXd& M) {
  constexpr double kRadix = 2.0;
  const Eigen::Index n = M.rows();
  Eigen::VectorXd s = Eigen::VectorXd::Ones(n);
  for (bool done = false; !done;) {
    done = true;
    for (Eigen::Index i = 0; i < n; ++i) {
      double c = M.col(i).cwiseAbs().sum() - std::abs(M(i, i));
      double r = M.row(i).cwiseAbs().sum() - std::abs(M(i, i));
      if (c == 0 || r == 0) continue;
      const double total = c + r;
      double f = 1;
      while (c < r / kRadix) {
        f *= kRadix;
        c *= kRadix * kRadix;
      }
      while (c > r * kRadix) {
        f /= kRadix;
        c /= kRadix * kRadix;
      }
      if ((c + r) / f < 0.95 * total) {
        done = false;
        s(i) *= f;
        M.row(i) /= f;
        M.col(i) *= f;
      }
    }
  }
  return s;
}

// Orthonormal basis of the span of the computed eigenvectors of each cluster of equal eigenvalues.
// For a semisimple repeated eigenvalue EigenSolver's back-substitution can return skewed vectors;
// any basis of the eigenspace is an eigenbasis. A defective cluster is not rescued: the residual
// check refuses it.
void orthonormalise_clusters(const Eigen::VectorXcd& lambda, double tol, Eigen::MatrixXcd& V) {
  const Eigen::Index n = lambda.size();
  std::vector<bool> done(static_cast<std::size_t>(n), false);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (done[i]) continue;
    std::vector<Eigen::Index> members;
    for (Eigen::Index j = i; j < n; ++j)
      if (!done[j] && std::abs(lambda(j) - lambda(i)) <= tol) members.push_back(j);
    for (auto j : members) done[j] = true;
    if (members.size() < 2) continue;
    const auto m = static_cast<Eigen::Index>(members.size());
    Eigen::MatrixXcd block(V.rows(), m);
    for (Eigen::Index k = 0; k < m; ++k) block.col(k) = V.col(members[k]);
    const Eigen::HouseholderQR<Eigen::MatrixXcd> qr(block);
    const Eigen::MatrixXcd Q = qr.householderQ() * Eigen::MatrixXcd::Identity(V.rows(), m);
    for (Eigen::Index k = 0; k < m; ++k) V.col(members[k]) = Q.col(k);
  }
}

// v -> e^{jθ} v / |v| with Re ⟂ Im: better conditioned T, same eigenvector.
Eigen::VectorXcd rotate_and_normalise(const Eigen::VectorXcd& v) {
  const Eigen::VectorXd p = v.real(), q = v.imag();
  const double theta = 0.5 * std::atan2(-2.0 * p.dot(q), p.squaredNorm() - q.squaredNorm());
  return std::polar(1.0, theta) * v / v.norm();
}

double condition_number(const Eigen::MatrixXcd& V) {
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXcd>(V).singularValues();
  return sv(sv.size() - 1) > 0 ? sv(0) / sv(sv.size() - 1)
                               : std::numeric_limits<double>::infinity();
}

// The floor's own position and velocity among the states (a gravity-preloaded plant): states
// "pos:<c>" and "vel:<c>" for an input "acc:<c>". Each pair is a 2x2 Jordan block at z = 1:
// rows [[1, t], [0, 1]] over (pos, vel), no row of it reading the structure.
struct FloorPair {
  Eigen::Index position, velocity;
  double t;  // Ad(pos, vel)
};

std::vector<FloorPair> floor_pairs(const StateSpace& s) {
  std::vector<FloorPair> pairs;
  const auto index = [&s](const std::string& label) -> Eigen::Index {
    for (std::size_t i = 0; i < s.states.size(); ++i)
      if (s.states[i] == label) return static_cast<Eigen::Index>(i);
    return -1;
  };
  for (const std::string& input : s.inputs) {
    if (input.rfind("acc:", 0) != 0) continue;
    const Eigen::Index p = index("pos:" + input.substr(4)), v = index("vel:" + input.substr(4));
    if (p >= 0 && v >= 0) pairs.push_back({p, v, s.A(p, v)});
  }
  return pairs;
}

// True when the floor pairs' rows are [[1, t], [0, 1]] on their own pair and zero elsewhere,
// to rounding: the zero-order hold of a double integrator gives them so, up to the fill-in of the
// exponential's Padé solve (1e-17 where an exact zero belongs). The modal form takes them exact;
// its residual and step-response checks judge the rest.
bool floor_rows_are_jordan_blocks(const Eigen::MatrixXd& A, const std::vector<FloorPair>& pairs) {
  constexpr double kRounding = 1e-13;
  for (const auto& f : pairs)
    for (Eigen::Index j = 0; j < A.cols(); ++j) {
      const double p = j == f.position ? 1.0 : j == f.velocity ? f.t : 0.0;
      const double v = j == f.velocity ? 1.0 : 0.0;
      if (std::abs(A(f.position, j) - p) > kRounding || std::abs(A(f.velocity, j) - v) > kRounding)
        return false;
    }
  return true;
}

// Checks that T is an eigenbasis (relative residual of Δ T = T (Λ - I), else refused saying
// `what`) and fills Λ, Bm = T^-1 Bd, Cm = Cd T and D.
void finish(ModalForm& m, const StateSpace& s, const char* what) {
  const Eigen::Index n = s.nx();
  const Eigen::MatrixXd delta = s.A - Eigen::MatrixXd::Identity(n, n);
  const double residual = (delta * m.T - m.T * m.Lambda_minus_I).norm();
  if (residual > kResidualTolerance * delta.norm() * m.T.norm()) {
    std::ostringstream os;
    os << what << " (relative residual " << residual / (delta.norm() * m.T.norm()) << ")";
    throw std::invalid_argument(refusal(os.str()));
  }
  m.Lambda = m.Lambda_minus_I + Eigen::MatrixXd::Identity(n, n);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(m.T);
  m.B = lu.solve(s.B);
  m.C = s.C * m.T;
  m.D = s.D;
}

// The floor's inputs move the structure through its slowest modes (a differential floor
// displacement, growing as t² under a step of acceleration, bends it statically): X = T_S L^-1 R
// amplifies the slow modes' decomposition error by 1 / |Λ - I|, which the residual, dominated by
// the fast modes, does not show. So the modal form on a floor must give the dense form's step
// responses, 1e-6 relative, over 1000 samples, input by input; else it is refused. (The shipped
// metrology frame under preload: 1e-13; a 206-state cantilever with 0.5 Hz modes at 10 kHz: 1.)
void require_same_response(const DiscreteStateSpace& d, const ModalForm& m) {
  const StateSpace& s = d.sys;
  const Eigen::Index n = s.nx();
  const Eigen::MatrixXd delta = s.A - Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(n, s.nu()), z = x;
  double worst = 0;
  for (int k = 0; k < 1000; ++k) {
    x += delta * x + s.B;
    z += m.Lambda_minus_I * z + m.B;
    const Eigen::MatrixXd y = s.C * x, difference = y - m.C * z;
    for (Eigen::Index j = 0; j < y.cols(); ++j)
      worst = std::max(worst, difference.col(j).cwiseAbs().maxCoeff() /
                                  std::max(y.col(j).cwiseAbs().maxCoeff(), 1e-300));
  }
  if (worst > 1e-6) {
    std::ostringstream os;
    os << "the floor's blocks separate from the structure only inexactly: a step response "
          "differs from the dense form's by "
       << worst << " (relative) within 1000 samples (slow structural modes beside the floor's "
       << "double integrators)";
    throw std::invalid_argument(refusal(os.str()));
  }
}

ModalForm modal_form_on_floor(const DiscreteStateSpace& d, const std::vector<FloorPair>& pairs,
                              const ModalFormOptions& options);

}  // namespace

ModalForm to_modal_form(const DiscreteStateSpace& d, const ModalFormOptions& options) {
  const StateSpace& s = d.sys;
  s.validate();
  const Eigen::Index n = s.nx();
  if (n == 0) throw std::invalid_argument("to_modal_form: the system has no states");
  if (const auto pairs = floor_pairs(s); !pairs.empty() && floor_rows_are_jordan_blocks(s.A, pairs))
    return modal_form_on_floor(d, pairs, options);

  const Eigen::MatrixXd delta = s.A - Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd balanced = delta;
  const Eigen::VectorXd scale = balance(balanced);
  const Eigen::EigenSolver<Eigen::MatrixXd> es(balanced, true);
  if (es.info() != Eigen::Success)
    throw std::invalid_argument(refusal("the eigen-decomposition of Ad did not converge"));
  const Eigen::VectorXcd mu = es.eigenvalues();  // eigenvalues of Ad, minus 1
  Eigen::MatrixXcd V = es.eigenvectors();
  orthonormalise_clusters(mu, 8 * std::numeric_limits<double>::epsilon() * balanced.norm(), V);
  for (Eigen::Index i = 0; i < n; ++i) V.col(i).normalize();

  ModalForm m;
  m.dt = d.dt;
  m.eigenvector_condition = condition_number(V);
  if (!(m.eigenvector_condition <= options.max_condition)) {
    std::ostringstream os;
    os << "the eigenvector matrix has condition number " << m.eigenvector_condition << " > "
       << options.max_condition;
    throw std::invalid_argument(refusal(os.str()));
  }

  m.Lambda_minus_I.setZero(n, n);
  m.T.resize(n, n);
  // EigenSolver gives real eigenvalues with an exactly zero imaginary part, and complex ones as
  // adjacent conjugate pairs. The pairs go first, so that every 2x2 block starts at an even index
  // (the runtime's modal step swaps neighbours inside SIMD packets, plant/runtime/modal_plant.hpp).
  std::vector<Eigen::Index> pairs, reals;
  for (Eigen::Index i = 0; i < n;) {
    if (mu(i).imag() == 0.0) {
      reals.push_back(i);
      i += 1;
      continue;
    }
    if (i + 1 >= n || mu(i + 1) != std::conj(mu(i)))
      throw std::invalid_argument("to_modal_form: unpaired complex eigenvalue of Ad");
    pairs.push_back(i);
    i += 2;
  }
  Eigen::Index k = 0;  // the next free modal coordinate
  for (const Eigen::Index i : pairs) {
    const Eigen::VectorXcd v = rotate_and_normalise(scale.asDiagonal() * V.col(i));
    const double a = mu(i).real(), b = mu(i).imag();
    m.T.col(k) = v.real();
    m.T.col(k + 1) = v.imag();
    m.Lambda_minus_I.block<2, 2>(k, k) << a, b, -b, a;
    m.block_sizes.push_back(2);
    k += 2;
  }
  for (const Eigen::Index i : reals) {
    m.T.col(k) = (scale.asDiagonal() * V.col(i).real()).normalized();
    m.Lambda_minus_I(k, k) = mu(i).real();
    m.block_sizes.push_back(1);
    k += 1;
  }
  finish(m, s, "the eigenvectors do not span invariant subspaces");
  return m;
}

namespace {

// The structure's modal form, the floor's Jordan blocks beside it, decoupled by the Sylvester
// equation Ad_SS X - X Ad_FF = -Ad_SF: with x_S = T_S z_S + X z_F the structure's modal state
// z_S does not see the floor's (it is the structure's motion relative to the floor), and
// z_F = x_F. In the structure's modal coordinates, X = T_S Y, L = Λ_S - I, N = Ad_FF - I
// (per channel [[0, t], [0, 0]]):  L Y - Y N = -R,  R = T_S^-1 Ad_SF,  so per channel
// L y_p = -r_p and L y_v = t y_p - r_v: two block-diagonal solves. L must be invertible: a
// structure with a pole at z = 1 of its own (a free rigid-body mode) is refused.
ModalForm modal_form_on_floor(const DiscreteStateSpace& d, const std::vector<FloorPair>& pairs,
                              const ModalFormOptions& options) {
  const StateSpace& s = d.sys;
  const Eigen::Index n = s.nx(), nw = static_cast<Eigen::Index>(pairs.size());
  std::vector<bool> is_floor(static_cast<std::size_t>(n), false);
  std::vector<Eigen::Index> floor, structure;
  for (const auto& f : pairs) {
    is_floor[static_cast<std::size_t>(f.position)] =
        is_floor[static_cast<std::size_t>(f.velocity)] = true;
    floor.push_back(f.position);
    floor.push_back(f.velocity);
  }
  for (Eigen::Index i = 0; i < n; ++i)
    if (!is_floor[static_cast<std::size_t>(i)]) structure.push_back(i);
  const Eigen::Index ns = static_cast<Eigen::Index>(structure.size());
  if (ns == 0) throw std::invalid_argument("to_modal_form: the plant has only the floor's states");

  DiscreteStateSpace sub = d;
  sub.sys.A = s.A(structure, structure);
  sub.sys.B = s.B(structure, Eigen::all);
  sub.sys.C = s.C(Eigen::all, structure);
  sub.sys.states.clear();
  for (const Eigen::Index i : structure) sub.sys.states.push_back(s.states[i]);
  const ModalForm ms = to_modal_form(sub, options);

  const Eigen::PartialPivLU<Eigen::MatrixXd> T_s(ms.T);
  const Eigen::MatrixXd R = T_s.solve(s.A(structure, floor));
  const Eigen::FullPivLU<Eigen::MatrixXd> L(ms.Lambda_minus_I);
  if (!L.isInvertible())
    throw std::invalid_argument(
        "to_modal_form: the structure has a pole at z = 1 of its own (a free rigid-body mode), "
        "which the floor's double integrators cannot be separated from: use the dense form");
  Eigen::MatrixXd Y(ns, 2 * nw);
  for (Eigen::Index c = 0; c < nw; ++c) {
    Y.col(2 * c) = L.solve(-R.col(2 * c));
    Y.col(2 * c + 1) = L.solve(pairs[c].t * Y.col(2 * c) - R.col(2 * c + 1));
  }
  const Eigen::MatrixXd X = ms.T * Y;

  // Modal coordinates: the structure's pairs, the floor's blocks (2x2, at even indices), the
  // structure's real modes.
  Eigen::Index pair_rows = 0;
  for (const int b : ms.block_sizes) pair_rows += b == 2 ? 2 : 0;
  const auto z_of = [&](Eigen::Index k) { return k < pair_rows ? k : k + 2 * nw; };
  ModalForm m;
  m.dt = d.dt;
  m.eigenvector_condition = ms.eigenvector_condition;
  m.T = Eigen::MatrixXd::Zero(n, n);
  m.Lambda_minus_I = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index k = 0; k < ns; ++k) {
    m.T(structure, z_of(k)) = ms.T.col(k);
    for (Eigen::Index j = 0; j < ns; ++j)
      m.Lambda_minus_I(z_of(k), z_of(j)) = ms.Lambda_minus_I(k, j);
  }
  for (Eigen::Index c = 0; c < nw; ++c) {
    const Eigen::Index zp = pair_rows + 2 * c, zv = zp + 1;
    m.T(structure, zp) = X.col(2 * c);
    m.T(structure, zv) = X.col(2 * c + 1);
    m.T(pairs[c].position, zp) = 1;
    m.T(pairs[c].velocity, zv) = 1;
    m.Lambda_minus_I(zp, zv) = pairs[c].t;
  }
  for (const int b : ms.block_sizes)
    if (b == 2) m.block_sizes.push_back(2);
  for (Eigen::Index c = 0; c < nw; ++c) m.block_sizes.push_back(2);
  for (const int b : ms.block_sizes)
    if (b == 1) m.block_sizes.push_back(1);

  finish(m, s, "the floor's blocks do not separate from the structure");
  require_same_response(d, m);
  return m;
}

}  // namespace

}  // namespace flexloop::plant::lti
