// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/massless_condensation.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace flexloop::plant::model {

namespace {

[[noreturn]] void fail(const std::string& msg) {
  throw std::invalid_argument("massless condensation: " + msg);
}

void check_matrix(const Eigen::MatrixXd& A, Eigen::Index n, const char* name, bool optional) {
  if (optional && A.size() == 0) return;
  if (A.rows() != n || A.cols() != n) {
    std::ostringstream os;
    os << name << " is " << A.rows() << "x" << A.cols() << ", expected " << n << "x" << n;
    fail(os.str());
  }
  if (!A.allFinite()) fail(std::string(name) + " has non-finite entries");
}

std::string label_of(const std::vector<std::string>& labels, Eigen::Index i) {
  if (static_cast<std::size_t>(i) < labels.size()) return labels[static_cast<std::size_t>(i)];
  return "q[" + std::to_string(i) + "]";
}

// The coordinates that carry most of the vector v (largest first, those above 10% of the max).
std::string participants(const Eigen::VectorXd& v, const std::vector<std::string>& labels) {
  std::vector<Eigen::Index> idx(static_cast<std::size_t>(v.size()));
  std::iota(idx.begin(), idx.end(), Eigen::Index{0});
  std::sort(idx.begin(), idx.end(),
            [&](Eigen::Index a, Eigen::Index b) { return std::abs(v(a)) > std::abs(v(b)); });
  const double vmax = v.cwiseAbs().maxCoeff();
  std::string out;
  for (std::size_t k = 0; k < idx.size() && k < 8; ++k) {
    if (std::abs(v(idx[k])) < 0.1 * vmax) break;
    out += (out.empty() ? "" : ", ") + label_of(labels, idx[k]);
  }
  return out;
}

}  // namespace

MasslessCondensation condense_massless(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K,
                                       const Eigen::MatrixXd& D, const Eigen::MatrixXd& G,
                                       const CondensationOptions& options,
                                       const std::vector<std::string>& labels) {
  const Eigen::Index n = M.rows();
  if (n == 0) fail("empty mass matrix");
  check_matrix(M, n, "M", false);
  check_matrix(K, n, "K", false);
  check_matrix(D, n, "D", true);
  check_matrix(G, n, "G", true);
  const Eigen::MatrixXd Dm = D.size() ? D : Eigen::MatrixXd::Zero(n, n);
  const Eigen::MatrixXd Gm = G.size() ? G : Eigen::MatrixXd::Zero(n, n);

  const double mnorm = M.norm();
  if (!(mnorm > 0.0)) fail("M is zero: every direction is massless");
  if ((M - M.transpose()).norm() > 1e-12 * mnorm) fail("M is not symmetric");

  // Massive / massless split from the eigen-decomposition of M (ascending eigenvalues).
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (M + M.transpose()));
  if (es.info() != Eigen::Success) fail("eigen-decomposition of M failed");
  const Eigen::VectorXd& mu = es.eigenvalues();
  const double mu_max = mu(n - 1);
  const double threshold = options.relative_mass_tolerance * mu_max;
  if (mu(0) < -threshold) {
    std::ostringstream os;
    os << "M is indefinite (eigenvalue " << mu(0) << ", largest " << mu_max
       << "); its directions involve " << participants(es.eigenvectors().col(0), labels);
    fail(os.str());
  }
  Eigen::Index nb = 0;
  while (nb < n && mu(nb) <= threshold) ++nb;
  const Eigen::Index na = n - nb;

  MasslessCondensation out;
  out.massless_count = static_cast<int>(nb);
  out.Z = es.eigenvectors().leftCols(nb);
  out.Y = es.eigenvectors().rightCols(na);
  out.M = out.Y.transpose() * M * out.Y;
  out.M = 0.5 * (out.M + out.M.transpose()).eval();

  const double dnorm = Dm.norm();
  out.damping_coupling = (nb > 0 && dnorm > 0.0) ? (out.Z.transpose() * Dm).norm() / dnorm : 0.0;
  if (options.damping == MasslessDampingPolicy::kRefuse &&
      out.damping_coupling > options.relative_damping_tolerance) {
    std::ostringstream os;
    os << "the damping acts on massless directions (||Z^T D|| / ||D|| = " << out.damping_coupling
       << "), so they follow first-order dynamics and a static condensation is not exact";
    fail(os.str());
  }

  if (nb == 0) {
    out.T = out.Y;
    out.K = out.Y.transpose() * K * out.Y;
    out.D = out.Y.transpose() * Dm * out.Y;
    out.G = out.Y.transpose() * Gm * out.Y;
    return out;
  }

  // b = -(Z^T Kt Z)^-1 Z^T Kt Y a with the total stiffness Kt = K + G.
  const Eigen::MatrixXd Kt = K + Gm;
  const Eigen::MatrixXd Kbb = out.Z.transpose() * Kt * out.Z;
  Eigen::BDCSVD<Eigen::MatrixXd> svd(Kbb, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const double kt_scale = Eigen::BDCSVD<Eigen::MatrixXd>(Kt).singularValues()(0);
  const double smin = svd.singularValues()(nb - 1);
  if (!(smin > options.relative_stiffness_tolerance * kt_scale)) {
    const Eigen::VectorXd mech = out.Z * svd.matrixV().col(nb - 1);
    std::ostringstream os;
    os << "massless mechanism: Z^T (K + G) Z is singular (smallest singular value " << smin
       << ", largest of K + G " << kt_scale
       << "), so a motion of the massless directions costs neither inertia nor strain energy; it "
          "involves "
       << participants(mech, labels)
       << ". Give these coordinates mass or inertia, stiffness, or make them rigid";
    fail(os.str());
  }
  const Eigen::MatrixXd W = Kbb.partialPivLu().solve(out.Z.transpose() * Kt * out.Y);
  out.T = out.Y - out.Z * W;
  out.K = out.T.transpose() * K * out.T;
  out.D = out.T.transpose() * Dm * out.T;
  out.G = out.T.transpose() * Gm * out.T;
  return out;
}

MasslessCondensation condense_massless(const Model& m, const Linearisation& lin,
                                       const CondensationOptions& options) {
  const Eigen::Index nd = m.nd();
  if (lin.M.rows() < nd || lin.M.cols() < nd)
    fail("linearisation is smaller than the model's dynamic coordinates");
  auto dd = [nd](const Eigen::MatrixXd& A) -> Eigen::MatrixXd {
    return A.size() ? Eigen::MatrixXd(A.topLeftCorner(nd, nd)) : Eigen::MatrixXd::Zero(nd, nd);
  };
  if (!dd(lin.C).isZero(0.0) || !dd(lin.N).isZero(0.0))
    fail(
        "C or N is non-zero (a moving operating point): condense M, C + D, K + N + G with the "
        "matrix overload");
  const std::vector<std::string> labels(m.generalised.begin(), m.generalised.begin() + nd);
  return condense_massless(dd(lin.M), dd(lin.K), dd(lin.D), dd(lin.G), options, labels);
}

}  // namespace flexloop::plant::model
