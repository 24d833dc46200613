#pragma once
// The discrete plant in real modal coordinates z (x = T z), DESIGN.md §6:
//
//   y_k = Cm z_k + Dd u_k,        z_{k+1} = Λ z_k + Bm u_k = z_k + ((Λ - I) z_k + Bm u_k)
//
// Λ is real block-diagonal (1x1 blocks for real eigenvalues, 2x2 blocks [[a, b], [-b, a]] for
// complex pairs), with every 2x2 block starting at an even index (plant::lti::to_modal_form puts
// the pairs first). The step keeps Λ - I as two vectors, its diagonal d and each entry's partner
// coefficient o (b in the first row of a pair, -b in the second, 0 for a real eigenvalue), so
//   ((Λ - I) z)_i = d_i z_i + o_i z_(i xor 1)
// costs 2 NX multiply-adds instead of NX², and z_(i xor 1) is z with neighbours swapped inside
// each SIMD packet (a one-cycle in-lane permute; no unaligned or shifted reads).
// Why Λ - I and not Λ: at high sample rates the poles sit near 1 and the small increment carries
// the dynamics; a - 1 keeps full relative precision where a itself would lose it (in float the
// pole error of a lightly damped mode drops from ~6e-8 to ~6e-8 |a - 1|). The increment is summed
// first and added to z once.
// Bm and Cm are dense. Same interface as DensePlant; state() is the modal state z, and
// physical_state() = T z is the state of the dense form (not used in a step). As the dense form,
// advance() also computes Cm z_{k+1} = (Cm Λ) z_k + (Cm Bm) u_k for the next output
// (state_output.hpp); Bm and Cm Bm (+ [0 D_h] for held inputs) are stacked into one product of u.
//
// The numbers come from the offline plant::lti::to_modal_form (plant/lti/modal_form.hpp), which
// refuses defective plants; from_modal_form checks sizes and the block structure at start-up.
// output() and advance() never allocate, lock, throw or make a system call.
#include <Eigen/Core>
#include <stdexcept>
#include <string>

#include "plant/runtime/column_product.hpp"
#include "plant/runtime/fixed_size_matrix.hpp"
#include "plant/runtime/state_output.hpp"

namespace flexloop::plant::runtime {

template <typename Scalar, int NX, int NU, int NY, int NH = 0>
class ModalPlant : public StateOutput<Scalar, NX, NU, NY, NH> {
  using Base = StateOutput<Scalar, NX, NU, NY, NH>;

 public:
  /// Start-up only: Λ - I, Bm, Cm, D and T of plant::lti::ModalForm, rounded to Scalar.
  /// @throws std::invalid_argument for a size other than (NX, NU, NY), a non-finite entry, or a
  /// Λ - I that is not real block-diagonal with 1x1 and 2x2 blocks.
  static ModalPlant from_modal_form(const Eigen::MatrixXd& Lambda_minus_I,
                                    const Eigen::MatrixXd& Bm, const Eigen::MatrixXd& Cm,
                                    const Eigen::MatrixXd& D, const Eigen::MatrixXd& T);

  /// Convenience for plant::lti::ModalForm (not included here: the online library must not depend
  /// on the offline one).
  template <typename Form>
  static ModalPlant from_modal_form(const Form& form) {
    return from_modal_form(form.Lambda_minus_I, form.B, form.C, form.D, form.T);
  }

  /// z <- z + ((Λ - I) z + Bm u), and Cm z + D_h h of the new state, h = the held part of u.
  void advance(const typename Base::Input& u) noexcept {
    const typename Base::State& z = this->x_;
    // Rows 0 .. NX-1: Bm u, then the increment; rows NX ..: (Cm Bm + [0 D_h]) u, then
    // Cm z_{k+1} + D_h h.
    typename Base::State dynamics;
#pragma GCC unroll 64
    for (int i = 0; i < NX; ++i) dynamics[i] = d_[i] * z[i] + o_[i] * z[partner(i)];
    typename Base::Stacked next = column_product(from_u_, u);
    next.template head<NX>() += dynamics;
    next.template segment<NY>(NX) += column_product(Cm_Lambda_, z).template head<NY>();
    this->take_next(next, u);
  }

  /// x = T z, the state of the equivalent dense plant (for logging and comparison).
  typename Base::State physical_state() const noexcept {
    return T_ * this->x_;
  }

 private:
  ModalPlant() = default;
  // i's partner in its 2x2 block (pairs start at even indices); a last odd index is its own.
  static constexpr int partner(int i) {
    return (i ^ 1) < NX ? (i ^ 1) : i;
  }

  typename Base::State d_ = Base::State::Zero(), o_ = Base::State::Zero();
  Eigen::Matrix<Scalar, Base::kStackedRows, NU> from_u_;     // [Bm; Cm Bm + [0 D_h]]
  Eigen::Matrix<Scalar, Base::kOutputLanes, NX> Cm_Lambda_;  // Cm Λ, rows padded
  Eigen::Matrix<Scalar, NX, NX> T_;
};

template <typename Scalar, int NX, int NU, int NY, int NH>
ModalPlant<Scalar, NX, NU, NY, NH> ModalPlant<Scalar, NX, NU, NY, NH>::from_modal_form(
    const Eigen::MatrixXd& Lambda_minus_I, const Eigen::MatrixXd& Bm, const Eigen::MatrixXd& Cm,
    const Eigen::MatrixXd& D, const Eigen::MatrixXd& T) {
  using Square = Eigen::Matrix<double, NX, NX>;
  const Square L = to_fixed<Square>("ModalPlant: Lambda - I", Lambda_minus_I);
  const auto B = to_fixed<Eigen::Matrix<double, NX, NU>>("ModalPlant: Bm", Bm);
  ModalPlant p;
  const auto out = p.load_output("ModalPlant", "Cm", Cm, "D", D);
  // The products in double, rounded to Scalar once.
  p.from_u_ = Base::stacked(B, out.next_output_from_input(B));
  p.Cm_Lambda_ = padded_rows<Base::kOutputLanes>(
      Eigen::Matrix<Scalar, NY, NX>((out.C * (L + Square::Identity())).template cast<Scalar>()));
  p.T_ = to_fixed<Eigen::Matrix<Scalar, NX, NX>>("ModalPlant: T", T);
  // Walk the diagonal block by block; anything outside the blocks must be exactly zero.
  Square outside = L;
  for (int i = 0; i < NX;) {
    p.d_(i) = static_cast<Scalar>(L(i, i));
    outside(i, i) = 0;
    const bool pair = i + 1 < NX && (L(i, i + 1) != 0 || L(i + 1, i) != 0);
    if (!pair) {
      i += 1;
      continue;
    }
    if (L(i, i) != L(i + 1, i + 1) || L(i, i + 1) != -L(i + 1, i))
      throw std::invalid_argument("ModalPlant: Lambda - I block at " + std::to_string(i) +
                                  " is not of the form [[a, b], [-b, a]]");
    if (i % 2 != 0)
      throw std::invalid_argument("ModalPlant: the 2x2 block of Lambda - I at " +
                                  std::to_string(i) +
                                  " starts at an odd index; put the complex pairs first "
                                  "(plant::lti::to_modal_form does)");
    p.d_(i + 1) = static_cast<Scalar>(L(i + 1, i + 1));
    p.o_(i) = static_cast<Scalar>(L(i, i + 1));
    p.o_(i + 1) = static_cast<Scalar>(L(i + 1, i));
    outside.template block<2, 2>(i, i).setZero();
    i += 2;
  }
  if (outside.cwiseAbs().maxCoeff() != 0)
    throw std::invalid_argument(
        "ModalPlant: Lambda - I is not real block-diagonal (1x1 and 2x2 blocks)");
  return p;
}

}  // namespace flexloop::plant::runtime
