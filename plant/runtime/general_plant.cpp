// SPDX-License-Identifier: BSD-3-Clause
#include "plant/runtime/general_plant.hpp"

#include <cmath>
#include <stdexcept>

#include "plant/runtime/pole_precision.hpp"

namespace flexloop::plant::runtime {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

std::string size_of(const Eigen::MatrixXd& m) {
  return std::to_string(m.rows()) + "x" + std::to_string(m.cols());
}

void require_finite(const std::string& what, const Eigen::MatrixXd& m) {
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      require(std::isfinite(m(i, j)),
              what + "(" + std::to_string(i) + "," + std::to_string(j) + ") is not finite");
}

}  // namespace

template <typename Scalar>
void GeneralStateOutput<Scalar>::load_output(const std::string& who, const Eigen::MatrixXd& B,
                                             const Eigen::MatrixXd& C, const Eigen::MatrixXd& D,
                                             Eigen::Index held_inputs) {
  const Eigen::Index nx = B.rows(), nu = B.cols(), ny = C.rows();
  require(nx >= 1, who + ": the plant has no state");
  require(C.cols() == nx, who + ": C is " + size_of(C) + ", expected " + std::to_string(ny) + "x" +
                              std::to_string(nx) + " (one column per state)");
  require(D.rows() == ny && D.cols() == nu, who + ": D is " + size_of(D) + ", expected " +
                                                std::to_string(ny) + "x" + std::to_string(nu) +
                                                " (outputs x inputs)");
  require(ny >= 1 && ny <= kMaxOutputs, who + ": " + std::to_string(ny) +
                                            " outputs; the runtime takes 1 .. " +
                                            std::to_string(kMaxOutputs));
  require(nu >= 2 && nu <= kMaxInputs,
          who + ": " + std::to_string(nu) + " inputs; the runtime takes 2 .. " +
              std::to_string(kMaxInputs) + " (at least one sampled and one held)");
  require(held_inputs >= 1 && held_inputs < nu && held_inputs <= numeric::kMaxChannels &&
              nu - held_inputs <= numeric::kMaxChannels,
          who + ": " + std::to_string(held_inputs) + " held inputs of " + std::to_string(nu) +
              "; each kind takes 1 .. " + std::to_string(numeric::kMaxChannels) + " channels");
  require_finite(who + ": C", C);
  require_finite(who + ": D", D);
  const Eigen::Index ns = nu - held_inputs;
  nu_ = nu;
  C_ = numeric::padded_matrix<Scalar>(C);
  D_held_ = numeric::padded_matrix<Scalar>(D.rightCols(held_inputs));
  D_sampled_ = numeric::padded_matrix<Scalar>(D.leftCols(ns));
  x_ = State::Zero(nx);
  next_ = State::Zero(numeric::padded_row_count<Scalar>(nx));
  held_ = Held::Zero(held_inputs);
  w_ = decltype(w_)::Zero(ns);
  u_ = Input::Zero(nu);
  cx_ = decltype(cx_)::Zero(numeric::padded_row_count<Scalar>(ny));
  // output() writes the padded rows of y_'s inline storage too (never read; after a copy of the
  // plant, which copies ny entries, they hold whatever the copy left until the next output()).
  y_ = Output::Zero(kMaxOutputs);
  y_.conservativeResize(ny);
  Eigen::MatrixXd from_input = C * B;
  from_input.rightCols(held_inputs) += D.rightCols(held_inputs);
  out_from_u_ = numeric::padded_matrix<Scalar>(from_input);
}

template <typename Scalar>
GeneralDensePlant<Scalar> GeneralDensePlant<Scalar>::from_matrices(const Eigen::MatrixXd& Ad,
                                                                   const Eigen::MatrixXd& Bd,
                                                                   const Eigen::MatrixXd& Cd,
                                                                   const Eigen::MatrixXd& Dd,
                                                                   Eigen::Index held_inputs) {
  const std::string who = "GeneralDensePlant";
  require(Ad.rows() == Ad.cols() && Ad.rows() == Bd.rows(),
          who + ": Ad is " + size_of(Ad) + " and Bd " + size_of(Bd) +
              "; Ad must be square with as many rows as Bd");
  require_finite(who + ": Ad", Ad);
  require_finite(who + ": Bd", Bd);
  require_dense_poles_kept_inside<Scalar>(Ad, who);
  GeneralDensePlant p;
  p.load_output(who, Bd, Cd, Dd, held_inputs);
  // The products in double, rounded to Scalar once.
  p.increment_from_x_ =
      numeric::padded_matrix<Scalar>(Ad - Eigen::MatrixXd::Identity(Ad.rows(), Ad.cols()));
  p.increment_from_u_ = numeric::padded_matrix<Scalar>(Bd);
  p.out_from_x_ = numeric::padded_matrix<Scalar>(Cd * Ad);
  return p;
}

template <typename Scalar>
GeneralModalPlant<Scalar> GeneralModalPlant<Scalar>::from_modal_form(
    const Eigen::MatrixXd& Lambda_minus_I, const Eigen::MatrixXd& Bm, const Eigen::MatrixXd& Cm,
    const Eigen::MatrixXd& D, const Eigen::MatrixXd& T, Eigen::Index held_inputs) {
  const std::string who = "GeneralModalPlant";
  const Eigen::Index n = Bm.rows();
  require(Lambda_minus_I.rows() == n && Lambda_minus_I.cols() == n,
          who + ": Lambda - I is " + size_of(Lambda_minus_I) + ", expected " + std::to_string(n) +
              "x" + std::to_string(n));
  require(T.rows() == n && T.cols() == n, who + ": T is " + size_of(T) + ", expected " +
                                              std::to_string(n) + "x" + std::to_string(n));
  require_finite(who + ": Lambda - I", Lambda_minus_I);
  require_finite(who + ": Bm", Bm);
  require_finite(who + ": T", T);
  GeneralModalPlant p;
  p.load_output(who, Bm, Cm, D, held_inputs);
  // Block structure: 2x2 blocks [[d, b], [-b, d]] at even indices first, then 1x1 blocks.
  p.d_.resize(n);
  p.o_.setZero(n);
  Eigen::Index k = 0;
  const auto off_block_zero = [&](Eigen::Index first, Eigen::Index size) {
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index i = first; i < first + size; ++i)
        if ((j < first || j >= first + size) && Lambda_minus_I(i, j) != 0) return false;
    return true;
  };
  while (k + 1 < n && Lambda_minus_I(k, k + 1) != 0) {
    require(off_block_zero(k, 2), who + ": Lambda - I is not block-diagonal at rows " +
                                      std::to_string(k) + ", " + std::to_string(k + 1));
    // A complex pair, or the floor's double integrator [[0, t], [0, 0]] (gravity preload).
    const bool jordan = Lambda_minus_I(k, k) == 0 && Lambda_minus_I(k + 1, k + 1) == 0 &&
                        Lambda_minus_I(k + 1, k) == 0;
    require(jordan || (Lambda_minus_I(k, k) == Lambda_minus_I(k + 1, k + 1) &&
                       Lambda_minus_I(k, k + 1) == -Lambda_minus_I(k + 1, k)),
            who + ": Lambda - I block at " + std::to_string(k) +
                " is not of the form [[a, b], [-b, a]] or [[0, t], [0, 0]]");
    require_pole_kept_inside<Scalar>(Lambda_minus_I(k, k), Lambda_minus_I(k, k + 1), k, who);
    p.d_(k) = static_cast<Scalar>(Lambda_minus_I(k, k));
    p.d_(k + 1) = static_cast<Scalar>(Lambda_minus_I(k + 1, k + 1));
    p.o_(k) = static_cast<Scalar>(Lambda_minus_I(k, k + 1));
    p.o_(k + 1) = static_cast<Scalar>(Lambda_minus_I(k + 1, k));
    k += 2;
  }
  p.pairs_ = k / 2;
  for (; k < n; ++k) {
    require(off_block_zero(k, 1),
            who + ": Lambda - I is not real block-diagonal with its 2x2 blocks first (row " +
                std::to_string(k) + ")");
    require_pole_kept_inside<Scalar>(Lambda_minus_I(k, k), 0.0, k, who);
    p.d_(k) = static_cast<Scalar>(Lambda_minus_I(k, k));
  }
  const Eigen::MatrixXd Lambda = Lambda_minus_I + Eigen::MatrixXd::Identity(n, n);
  p.bm_ = numeric::padded_matrix<Scalar>(Bm);
  p.out_from_x_ = numeric::padded_matrix<Scalar>(Cm * Lambda);
  p.T_ = T;
  return p;
}

template class GeneralStateOutput<double>;
template class GeneralStateOutput<float>;
template class GeneralDensePlant<double>;
template class GeneralDensePlant<float>;
template class GeneralModalPlant<double>;
template class GeneralModalPlant<float>;

}  // namespace flexloop::plant::runtime
