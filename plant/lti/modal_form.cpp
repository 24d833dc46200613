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

}  // namespace

ModalForm to_modal_form(const DiscreteStateSpace& d, const ModalFormOptions& options) {
  const StateSpace& s = d.sys;
  s.validate();
  const Eigen::Index n = s.nx();
  if (n == 0) throw std::invalid_argument("to_modal_form: the system has no states");

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
  const double residual = (delta * m.T - m.T * m.Lambda_minus_I).norm();
  if (residual > kResidualTolerance * delta.norm() * m.T.norm()) {
    std::ostringstream os;
    os << "the eigenvectors do not span invariant subspaces (relative residual "
       << residual / (delta.norm() * m.T.norm()) << ")";
    throw std::invalid_argument(refusal(os.str()));
  }

  m.Lambda = m.Lambda_minus_I + Eigen::MatrixXd::Identity(n, n);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(m.T);
  m.B = lu.solve(s.B);
  m.C = s.C * m.T;
  m.D = s.D;
  return m;
}

}  // namespace flexloop::plant::lti
