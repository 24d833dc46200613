// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/modal_analysis.hpp"

#include "numeric/constants.hpp"
#include "plant/lti/frequency_response.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace flexloop::plant::lti {

namespace {
using cd = std::complex<double>;
using numeric::kEps;
using numeric::kTwoPi;
// Relative asymmetry accepted as rounding noise from assembly (then symmetrised).
constexpr double kSymmetryTol = 1e-10;

std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

void require_square_pair(const char* fn, const char* a_name, const Eigen::MatrixXd& a,
                         const char* b_name, const Eigen::MatrixXd& b) {
  auto dims = [](const Eigen::MatrixXd& m) {
    return std::to_string(m.rows()) + "x" + std::to_string(m.cols());
  };
  if (a.rows() != a.cols() || b.rows() != b.cols() || a.rows() != b.rows())
    throw std::invalid_argument(std::string(fn) + ": " + a_name + " (" + dims(a) + ") and " +
                                b_name + " (" + dims(b) + ") must be square and of equal size");
  if (!a.allFinite())
    throw std::invalid_argument(std::string(fn) + ": " + a_name + " has a non-finite entry");
  if (!b.allFinite())
    throw std::invalid_argument(std::string(fn) + ": " + b_name + " has a non-finite entry");
}

bool nearly_symmetric(const Eigen::MatrixXd& a) {
  const double scale = a.cwiseAbs().maxCoeff();
  return (a - a.transpose()).cwiseAbs().maxCoeff() <= kSymmetryTol * scale;
}

Eigen::MatrixXd symmetrised(const Eigen::MatrixXd& a) {
  return 0.5 * (a + a.transpose());
}

// The smallest pivot of the Cholesky (LDL^T) of D^-1/2 S D^-1/2, D = diag(S) > 0: how far each
// coordinate is from the span of the ones before it, in the units of its own diagonal; -1 when a
// diagonal entry is not positive or the factorisation fails.
double smallest_scaled_pivot(const Eigen::MatrixXd& S) {
  const Eigen::VectorXd d = S.diagonal();
  if (!(d.minCoeff() > 0)) return -1;
  const Eigen::VectorXd s = d.cwiseSqrt().cwiseInverse();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(s.asDiagonal() * S * s.asDiagonal());
  return ldlt.info() == Eigen::Success ? ldlt.vectorD().minCoeff() : -1;
}

// Definite beyond rounding: every scaled pivot above 100 n eps.
bool clearly_definite(const Eigen::MatrixXd& S) {
  return smallest_scaled_pivot(S) > 100.0 * static_cast<double>(S.rows()) * kEps;
}

// M must be symmetric positive definite. Judged by what the eigenproblem needs, a Cholesky
// factor, not by the eigenvalue spread: a lumped chain with small rotary inertia is definite at a
// condition number of 1e11. The Cholesky runs on the Jacobi-scaled D^-1/2 M D^-1/2 (unit
// diagonal), whose pivots say how far each coordinate's mass is from the span of the ones before
// it: a pivot below n eps is a massless coordinate (or combination), not rounding.
Eigen::MatrixXd checked_mass(const Eigen::MatrixXd& M) {
  const Eigen::Index n = M.rows();
  if (!nearly_symmetric(M))
    throw std::invalid_argument("natural_modes: mass matrix M is not symmetric (max |M - M^T| = " +
                                num((M - M.transpose()).cwiseAbs().maxCoeff()) + ")");
  Eigen::MatrixXd Ms = symmetrised(M);
  const Eigen::VectorXd d = Ms.diagonal();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (d(i) < 0)
      throw std::invalid_argument("natural_modes: mass matrix M is indefinite (M(" +
                                  std::to_string(i) + "," + std::to_string(i) + ") = " + num(d(i)) +
                                  "); a mass matrix must be positive definite");
    if (d(i) == 0)
      throw std::invalid_argument("natural_modes: mass matrix M is singular: coordinate " +
                                  std::to_string(i) +
                                  " has no mass (M(i,i) = 0): massless coordinates; condense them "
                                  "out statically or give them mass");
  }
  if (clearly_definite(Ms)) return Ms;
  // Refused: say how, with the eigenvalues of the scaled matrix (only on this path).
  const Eigen::VectorXd s = d.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = s.asDiagonal() * Ms * s.asDiagonal();
  const double tol = 100.0 * static_cast<double>(n) * kEps;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(scaled, Eigen::EigenvaluesOnly);
  const double smallest = es.eigenvalues().minCoeff(), largest = es.eigenvalues().maxCoeff();
  if (smallest < -tol * largest)
    throw std::invalid_argument(
        "natural_modes: mass matrix M is indefinite (scaled to a unit diagonal: smallest "
        "eigenvalue " +
        num(smallest) + ", largest " + num(largest) + "); a mass matrix must be positive definite");
  throw std::invalid_argument(
      "natural_modes: mass matrix M is singular (scaled to a unit diagonal: smallest eigenvalue " +
      num(smallest) + ", largest " + num(largest) +
      "): massless coordinates; condense them out statically or give them mass");
}

// Symmetric K: w^2 and shapes of (K - w^2 M) phi = 0. With K definite the problem is solved the
// other way round, M phi = (1 / w^2) K phi (Cholesky of K): each w^2 then comes out to its own
// relative accuracy, the lowest modes included. The Cholesky of M (the only way when K is singular
// or indefinite: rigid-body modes, beyond buckling) gives each w^2 to eps max|w^2| absolute, which
// loses the first mode of a lumped 400-beam chain (w^2 = 9e2 beside 1.6e14) to rounding.
struct SymmetricModes {
  Eigen::VectorXd w2;
  Eigen::MatrixXd shapes;
  bool from_stiffness = false;  // solved with K's Cholesky: every w^2 > 0 is resolved
};
SymmetricModes symmetric_modes(const Eigen::MatrixXd& Ms, const Eigen::MatrixXd& Ks) {
  SymmetricModes out;
  if (clearly_definite(Ks)) {
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(
        Ms, Ks, Eigen::ComputeEigenvectors | Eigen::Ax_lBx);
    if (ges.info() == Eigen::Success && ges.eigenvalues().minCoeff() > 0) {
      out.w2 = ges.eigenvalues().cwiseInverse();
      out.shapes = ges.eigenvectors();
      out.from_stiffness = true;
      return out;
    }
  }
  // Cholesky M = L L^T, symmetric eigenproblem of L^-1 K L^-T; eigenvectors M-orthonormal.
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(
      Ks, Ms, Eigen::ComputeEigenvectors | Eigen::Ax_lBx);
  if (ges.info() != Eigen::Success)
    throw std::runtime_error("natural_modes: symmetric eigensolver did not converge");
  out.w2 = ges.eigenvalues();
  out.shapes = ges.eigenvectors();
  return out;
}

// Scale to phi^T M phi = 1 and make the largest-magnitude entry positive (a deterministic sign).
void normalise_shape(Eigen::Ref<Eigen::VectorXd> phi, const Eigen::MatrixXd& M) {
  phi /= std::sqrt(phi.dot(M * phi));
  Eigen::Index imax = 0;
  phi.cwiseAbs().maxCoeff(&imax);
  if (phi(imax) < 0.0) phi = -phi;
}
}  // namespace

Modes natural_modes(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K) {
  require_square_pair("natural_modes", "M", M, "K", K);
  const Eigen::Index n = M.rows();
  Modes modes;
  if (n == 0) return modes;
  const Eigen::MatrixXd Ms = checked_mass(M);

  Eigen::VectorXcd w2(n);
  Eigen::MatrixXd shapes(n, n);
  bool resolved = false;  // every w^2 to its own relative accuracy: none is rounded to zero
  if (nearly_symmetric(K)) {
    SymmetricModes sm = symmetric_modes(Ms, symmetrised(K));
    w2 = sm.w2.cast<cd>();
    shapes = std::move(sm.shapes);
    resolved = sm.from_stiffness;
  } else {
    // K phi = w^2 M phi by real QZ; betas are nonzero because M is nonsingular.
    const Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> ges(K, Ms, true);
    if (ges.info() != Eigen::Success)
      throw std::runtime_error("natural_modes: QZ eigensolver did not converge");
    w2 = ges.alphas().cwiseQuotient(ges.betas().cast<cd>());
    const Eigen::MatrixXcd V = ges.eigenvectors();
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Index imax = 0;
      V.col(i).cwiseAbs().maxCoeff(&imax);
      // Turn the largest entry onto the real axis: a real eigenvector becomes exactly real.
      const cd phase =
          std::abs(V(imax, i)) > 0.0 ? std::conj(V(imax, i)) / std::abs(V(imax, i)) : cd(1.0);
      shapes.col(i) = (V.col(i) * phase).real();
    }
  }

  const double scale = w2.cwiseAbs().maxCoeff();
  const double zero_tol = resolved ? 0.0 : 100.0 * static_cast<double>(n) * kEps * scale;
  const double imag_tol = std::sqrt(kEps) * scale;
  Eigen::VectorXd f(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double mag = std::sqrt(std::abs(w2(i))) / kTwoPi;
    if (std::abs(w2(i)) <= zero_tol)
      f(i) = 0.0;
    else if (std::abs(w2(i).imag()) <= imag_tol && w2(i).real() > 0.0)
      f(i) = mag;
    else
      f(i) = -mag;  // divergence or flutter
    normalise_shape(shapes.col(i), Ms);
  }

  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return f(a) < f(b); });
  modes.frequencies_hz.resize(n);
  modes.shapes.resize(n, n);
  modes.omega_squared.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index i = order[static_cast<std::size_t>(k)];
    modes.frequencies_hz(k) = f(i);
    modes.shapes.col(k) = shapes.col(i);
    modes.omega_squared(k) = w2(i);
  }
  return modes;
}

Eigen::VectorXd buckling_multipliers(const Eigen::MatrixXd& K, const Eigen::MatrixXd& G) {
  require_square_pair("buckling_multipliers", "K", K, "G", G);
  const Eigen::Index n = K.rows();
  std::vector<double> lambda;
  const double tol_n = 100.0 * static_cast<double>(std::max<Eigen::Index>(n, 1)) * kEps;

  bool done = false;
  if (n > 0 && nearly_symmetric(K) && nearly_symmetric(G)) {
    const Eigen::MatrixXd Ks = symmetrised(K);
    const Eigen::LLT<Eigen::MatrixXd> llt(Ks);
    if (llt.info() == Eigen::Success) {
      // K SPD: G x = mu K x is symmetric-definite even for singular or indefinite G;
      // K x + lambda G x = 0  <=>  mu = -1/lambda, and mu = 0 is an infinite multiplier.
      const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(
          symmetrised(G), Ks, Eigen::EigenvaluesOnly | Eigen::Ax_lBx);
      if (ges.info() == Eigen::Success) {
        const Eigen::VectorXd mu = ges.eigenvalues();
        const double cut = tol_n * mu.cwiseAbs().maxCoeff();
        for (Eigen::Index i = 0; i < n; ++i)
          if (std::abs(mu(i)) > cut) lambda.push_back(-1.0 / mu(i));
        done = true;
      }
    }
  }
  if (n > 0 && !done) {
    // General pencil K x = lambda (-G) x by real QZ: lambda = alpha / beta; beta ~ rounding means
    // lambda infinite (G singular in that direction); alpha and beta both ~ rounding means the
    // pencil is singular and every lambda is an eigenvalue.
    const Eigen::MatrixXd minus_G = -G;
    const Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> ges(K, minus_G, false);
    if (ges.info() != Eigen::Success)
      throw std::runtime_error("buckling_multipliers: QZ eigensolver did not converge");
    const double k_tol = tol_n * K.norm(), g_tol = tol_n * G.norm();
    for (Eigen::Index i = 0; i < n; ++i) {
      const cd alpha = ges.alphas()(i);
      const double beta = ges.betas()(i);
      if (std::abs(beta) <= g_tol) {
        if (std::abs(alpha) <= k_tol)
          throw std::invalid_argument(
              "buckling_multipliers: K + lambda G is singular for every lambda (K and G share a "
              "null space); remove the unconstrained coordinates");
        continue;  // infinite multiplier
      }
      if (std::abs(alpha.imag()) > std::sqrt(kEps) * std::abs(alpha)) continue;  // complex
      lambda.push_back(alpha.real() / beta);
    }
  }
  std::stable_sort(lambda.begin(), lambda.end(), [](double a, double b) {
    return std::abs(a) < std::abs(b) || (std::abs(a) == std::abs(b) && a < b);
  });
  return Eigen::Map<const Eigen::VectorXd>(lambda.data(), static_cast<Eigen::Index>(lambda.size()));
}

StaticStability static_stability(const Modes& modes, const Eigen::MatrixXd& K,
                                 const Eigen::MatrixXd& G) {
  require_square_pair("static_stability", "K", K, "G", G);
  StaticStability s;
  for (Eigen::Index i = 0; i < modes.frequencies_hz.size(); ++i) {
    if (!(modes.frequencies_hz(i) < 0.0)) continue;  // natural_modes: f < 0 flags an unstable mode
    const cd w2 = modes.omega_squared(i);
    // natural_modes' "complex" (sqrt(eps) of the largest |w^2|): an oscillation that grows.
    const double scale = modes.omega_squared.cwiseAbs().maxCoeff();
    const bool complex =
        std::abs(w2.imag()) > std::sqrt(std::numeric_limits<double>::epsilon()) * scale;
    ++(complex ? s.flutter : s.divergent);
    // q ~ e^{s t} with s^2 = -w^2: the principal root is the growing one.
    s.growth_rate = std::max(s.growth_rate, std::sqrt(-w2).real());
  }
  s.preloaded = G.norm() > 1e-12 * K.norm();
  if (!s.preloaded) return s;
  try {
    s.buckling_multipliers = buckling_multipliers(K, G);
  } catch (const std::invalid_argument&) {
    // Sizes and finiteness were checked above: K + lambda G is singular for every lambda (a
    // mechanism of K that G does not load), so no multiplier measures the load.
    return s;
  }
  for (const double l : s.buckling_multipliers)
    if (l >= 0.0 && (s.critical_multiplier < 0.0 || l < s.critical_multiplier))
      s.critical_multiplier = l;
  return s;
}

std::string to_string(const StaticStability& s) {
  const double lc = s.critical_multiplier;
  char load[160] = "";
  // 3 significant digits, 6 within 0.5 % of buckling (where 3 would print "1").
  const int digits = std::abs(lc - 1.0) < 5e-3 ? 6 : 3;
  if (s.preloaded && lc > 0.0)
    std::snprintf(load, sizeof load,
                  "the preload is %.*g times the first buckling load (buckling multiplier %.*g)",
                  digits, 1.0 / lc, digits, lc);
  else if (s.preloaded && lc == 0.0)
    std::snprintf(
        load, sizeof load,
        "the preload loads a mechanism of the unloaded structure (buckling multiplier 0)");
  if (s.stable()) {
    if (!s.preloaded) return "statically stable (no preload)";
    if (lc < 0.0) return "statically stable: no buckling load in the preload's direction";
    return std::string("statically stable: ") + load;
  }
  std::string prefix;
  // With K positive definite, K + G turns indefinite only past a multiplier in (0, 1]; otherwise
  // the unloaded stiffness itself is to blame.
  if (!s.preloaded)
    prefix = "no preload, yet the stiffness is not positive definite: ";
  else if (lc >= 0.0 && lc <= 1.0)
    prefix = std::string(load) + ": ";
  else if (lc > 1.0)
    prefix = std::string(load) + ", yet the unloaded stiffness is not positive definite: ";
  char modes[300];
  const int n = s.divergent + s.flutter;
  std::snprintf(modes, sizeof modes,
                "the linearised model is statically unstable, %d divergent mode%s%s%s growing as "
                "e^(%.3g t) (a disturbance doubles every %.3g s)",
                s.divergent, s.divergent == 1 ? "" : "s",
                s.flutter > 0 ? (" and " + std::to_string(s.flutter) +
                                 (s.flutter == 1 ? " flutter mode" : " flutter modes"))
                                    .c_str()
                              : "",
                n > 1 ? ", the fastest" : "", s.growth_rate, std::log(2.0) / s.growth_rate);
  return prefix + modes;
}

Eigen::VectorXcd poles(const StateSpace& sys) {
  sys.validate();
  if (sys.nx() == 0) return Eigen::VectorXcd(0);
  // Exact power-of-two balancing first (as LAPACK's xGEEV does): states in metres beside states
  // in newtons make A badly scaled, and repeated poles are then computed far less accurately.
  const Eigen::VectorXd t = balancing_scaling(sys.A);
  const Eigen::MatrixXd Ab = t.cwiseInverse().asDiagonal() * sys.A * t.asDiagonal();
  const Eigen::EigenSolver<Eigen::MatrixXd> es(Ab, false);
  if (es.info() != Eigen::Success)
    throw std::runtime_error("poles: eigenvalues of A did not converge");
  std::vector<cd> p(es.eigenvalues().begin(), es.eigenvalues().end());
  std::sort(p.begin(), p.end(), [](const cd& a, const cd& b) {
    if (std::abs(a.imag()) != std::abs(b.imag())) return std::abs(a.imag()) < std::abs(b.imag());
    if (a.real() != b.real()) return a.real() < b.real();
    return a.imag() < b.imag();
  });
  return Eigen::Map<const Eigen::VectorXcd>(p.data(), static_cast<Eigen::Index>(p.size()));
}

}  // namespace flexloop::plant::lti
