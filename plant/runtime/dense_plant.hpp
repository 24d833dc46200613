// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The discrete plant in the form the offline discretisation produces it (doc/design.md §6):
//
//   y_k = Cd x_k + Dd u_k,        x_{k+1} = Ad x_k + Bd u_k
//
// with compile-time sizes NX (states), NU (inputs), NY (outputs), NH (held inputs, the last NH of
// u; state_output.hpp) and Scalar double or float. A step costs (NX + NY)(NX + NU) multiply-adds
// in advance() and NY (NU - NH) in output(). The update is computed as
//   x_{k+1} = x_k + ((Ad - I) x_k + Bd u_k)
// (Ad - I is exact in floating point for the entries near 1): at high sample rates Ad ≈ I + A T
// and the increment carries the dynamics; rounding Ad - I instead of Ad to the runtime's scalar
// keeps the poles near z = 1 to full relative precision, which matters for float. The matrices are
// loaded once at start-up from the discrete artefact (from_matrices, which checks the sizes);
// output() and advance() never allocate, lock, throw or make a system call. The usual sample is
//   y = plant.output(u); ...; plant.advance(u);                 (NH = 0)
//   y = plant.output(w); h = controller(y); plant.advance([w; h]);   (NH held inputs)
// so the output sees the state before the update. advance() also computes C x_{k+1} (+ D_h h)
// for the next output (state_output.hpp): one product of x_k and one of u_k with the stacked
// matrices [Ad - I; C Ad] and [Bd; C Bd + [0 D_h]].
#include <Eigen/Core>

#include "numeric/column_product.hpp"
#include "numeric/fixed_size_matrix.hpp"
#include "plant/runtime/pole_precision.hpp"
#include "plant/runtime/state_output.hpp"

namespace flexloop::plant::runtime {

template <typename Scalar, int NX, int NU, int NY, int NH = 0>
class DensePlant : public StateOutput<Scalar, NX, NU, NY, NH> {
  using Base = StateOutput<Scalar, NX, NU, NY, NH>;

 public:
  /// Start-up only. The matrices are in double (the artefact's precision) and are rounded to
  /// Scalar. The state starts at zero.
  /// @throws std::invalid_argument naming the matrix, its size and the expected size when a
  /// size differs from (NX, NU, NY), or an entry that is not finite; in float, for a decaying
  /// pole that float would not keep inside the unit circle (pole_precision.hpp).
  static DensePlant from_matrices(const Eigen::MatrixXd& Ad, const Eigen::MatrixXd& Bd,
                                  const Eigen::MatrixXd& Cd, const Eigen::MatrixXd& Dd);

  /// x <- x + ((Ad - I) x + Bd u), and C x + D_h h of the new state, h = the held part of u.
  void advance(const typename Base::Input& u) noexcept {
    // Rows 0 .. NX-1: the increment; rows NX ..: C x_{k+1} + D_h h (column_product.hpp).
    this->take_next(numeric::product_sum(from_x_, this->x_, from_u_, u), u);
  }

 private:
  DensePlant() = default;

  Eigen::Matrix<Scalar, Base::kStackedRows, NX> from_x_;  // [Ad - I; C Ad]
  Eigen::Matrix<Scalar, Base::kStackedRows, NU> from_u_;  // [Bd; C Bd + [0 D_h]]
};

template <typename Scalar, int NX, int NU, int NY, int NH>
DensePlant<Scalar, NX, NU, NY, NH> DensePlant<Scalar, NX, NU, NY, NH>::from_matrices(
    const Eigen::MatrixXd& Ad, const Eigen::MatrixXd& Bd, const Eigen::MatrixXd& Cd,
    const Eigen::MatrixXd& Dd) {
  using Square = Eigen::Matrix<double, NX, NX>;
  const Square A = numeric::to_fixed<Square>("DensePlant: Ad", Ad);
  const auto B = numeric::to_fixed<Eigen::Matrix<double, NX, NU>>("DensePlant: Bd", Bd);
  require_dense_poles_kept_inside<Scalar>(Ad, "DensePlant");
  DensePlant p;
  const auto out = p.load_output("DensePlant", "Cd", Cd, "Dd", Dd);
  // The products in double, rounded to Scalar once.
  p.from_x_ =
      Base::stacked(Square(A - Square::Identity()), Eigen::Matrix<double, NY, NX>(out.C * A));
  p.from_u_ = Base::stacked(B, out.next_output_from_input(B));
  return p;
}

}  // namespace flexloop::plant::runtime
