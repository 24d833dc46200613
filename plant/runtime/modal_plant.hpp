// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The discrete plant in real modal coordinates z (x = T z), doc/design.md §6:
//
//   y_k = Cm z_k + Dd u_k,        z_{k+1} = Λ z_k + Bm u_k = z_k + ((Λ - I) z_k + Bm u_k)
//
// Λ is real block-diagonal (1x1 blocks for real eigenvalues, 2x2 blocks [[a, b], [-b, a]] for
// complex pairs), with every 2x2 block starting at an even index (plant::lti::to_modal_form puts
// the pairs first). For the state rows that fill whole SIMD packets (8 of 12 with AVX-512 double)
// the step keeps Λ - I as two vectors, its diagonal d and each entry's partner coefficient o (b
// in the first row of a pair, -b in the second, 0 for a real eigenvalue), so
//   ((Λ - I) z)_i = d_i z_i + o_i z_(i xor 1)
// costs two multiply-adds per packet, and z_(i xor 1) is z with neighbours swapped inside the
// packet (an in-lane permute). The remaining state rows share one product of z with the next
// output's Cm Λ z (below), so that every sum of the step stays in whole packets in registers.
// Why Λ - I and not Λ: at high sample rates the poles sit near 1 and the small increment carries
// the dynamics; a - 1 keeps full relative precision where a itself would lose it (in float the
// pole error of a lightly damped mode drops from ~6e-8 to ~6e-8 |a - 1|). The increment is summed
// first and added to z once.
// Bm and Cm are dense. Same interface as DensePlant; state() is the modal state z, and
// physical_state() = T z is the state of the dense form (not used in a step). As the dense form,
// advance() also computes Cm z_{k+1} = (Cm Λ) z_k + (Cm Bm) u_k for the next output
// (state_output.hpp): one product of u with the stacked [Bm; Cm Bm + [0 D_h]], one product of z
// with [the rest of Λ - I; Cm Λ], and the packets of d ∘ z + o ∘ swap(z).
//
// The numbers come from the offline plant::lti::to_modal_form (plant/lti/modal_form.hpp), which
// refuses defective plants; from_modal_form checks sizes and the block structure at start-up.
// output() and advance() never allocate, lock, throw or make a system call.
#include <Eigen/Core>
#include <stdexcept>
#include <string>

#include "numeric/column_product.hpp"
#include "numeric/fixed_size_matrix.hpp"
#include "plant/runtime/pole_precision.hpp"
#include "plant/runtime/state_output.hpp"

namespace flexloop::plant::runtime {

template <typename Scalar, int NX, int NU, int NY, int NH = 0>
class ModalPlant : public StateOutput<Scalar, NX, NU, NY, NH> {
  using Base = StateOutput<Scalar, NX, NU, NY, NH>;

 public:
  /// Start-up only: Λ - I, Bm, Cm, D and T of plant::lti::ModalForm, rounded to Scalar.
  /// @throws std::invalid_argument for a size other than (NX, NU, NY), a non-finite entry, a
  /// Λ - I that is not real block-diagonal with 1x1 and 2x2 blocks, or a decaying pole that
  /// Scalar cannot keep inside the unit circle (pole_precision.hpp).
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
    namespace ei = Eigen::internal;
    const typename Base::State& z = this->x_;
    // Stacked rows 0 .. NX-1: the increment; NX ..: Cm z_{k+1} + D_h h (state_output.hpp).
    auto next = StackedSums::template product<NU>(from_u_.data(), u);
    const auto rest = RestSums::template product<NX>(from_z_.data(), z);
    if constexpr (kSwapRows == 0) {
      next.add(rest);
    } else {
      constexpr int kFirst = kSwapRows / kPacket;
#pragma GCC unroll 16
      for (int p = 0; p < RestSums::kCount; ++p)
        next.packets[kFirst + p] = ei::padd(next.packets[kFirst + p], rest.packets[p]);
#pragma GCC unroll 16
      for (int p = 0; p < kFirst; ++p) {
        const Packet zp = ei::ploadu<Packet>(z.data() + p * kPacket);
        const Packet swapped = numeric::detail::swap_neighbours<Scalar>(zp);
        next.packets[p] = ei::pmadd(
            ei::ploadu<Packet>(d_.data() + p * kPacket), zp,
            ei::pmadd(ei::ploadu<Packet>(o_.data() + p * kPacket), swapped, next.packets[p]));
      }
    }
    typename Base::Stacked sums;
    next.store(sums.data());
    this->take_next(sums, u);
  }

  /// x = T z, the state of the equivalent dense plant (for logging and comparison).
  typename Base::State physical_state() const noexcept {
    return T_ * this->x_;
  }

 private:
  ModalPlant() = default;

  using Packet = typename numeric::detail::PacketLevel<Scalar, 0>::type;
  static constexpr int kPacket = numeric::detail::kPacketSize<Scalar, 0>;
  // The state rows stepped as d ∘ z + o ∘ swap(z): whole widest packets from row 0 (none without
  // SIMD). The stacked rows from there on (the other state rows, Cm z, padding) are whole packets
  // too, one product of z.
  static constexpr int kSwapRows = kPacket >= 2 ? NX / kPacket * kPacket : 0;
  static constexpr int kRestRows = Base::kStackedRows - kSwapRows;
  // The sums in registers (column_product.hpp): all stacked rows, and the rows from kSwapRows on.
  using StackedSums = numeric::detail::Accumulator<Scalar, Base::kStackedRows>;
  using RestSums = numeric::detail::Accumulator<Scalar, kRestRows>;
  static_assert(kSwapRows == 0 || (StackedSums::kRest == 0 && RestSums::kRest == 0),
                "the swapped rows and the rest must be whole packets of the stacked sums");

  static constexpr int kSwapLanes = kSwapRows > 0 ? kSwapRows : 1;
  Eigen::Matrix<Scalar, kSwapLanes, 1> d_ = decltype(d_)::Zero(), o_ = decltype(o_)::Zero();
  Eigen::Matrix<Scalar, Base::kStackedRows, NU> from_u_;  // [Bm; Cm Bm + [0 D_h]]
  Eigen::Matrix<Scalar, kRestRows, NX> from_z_;  // [(Λ - I) rows kSwapRows ..; Cm Λ], rows padded
  Eigen::Matrix<Scalar, NX, NX> T_;
};

template <typename Scalar, int NX, int NU, int NY, int NH>
ModalPlant<Scalar, NX, NU, NY, NH> ModalPlant<Scalar, NX, NU, NY, NH>::from_modal_form(
    const Eigen::MatrixXd& Lambda_minus_I, const Eigen::MatrixXd& Bm, const Eigen::MatrixXd& Cm,
    const Eigen::MatrixXd& D, const Eigen::MatrixXd& T) {
  using Square = Eigen::Matrix<double, NX, NX>;
  const Square L = numeric::to_fixed<Square>("ModalPlant: Lambda - I", Lambda_minus_I);
  const auto B = numeric::to_fixed<Eigen::Matrix<double, NX, NU>>("ModalPlant: Bm", Bm);
  ModalPlant p;
  const auto out = p.load_output("ModalPlant", "Cm", Cm, "D", D);
  // The products in double, rounded to Scalar once.
  p.from_u_ = Base::stacked(B, out.next_output_from_input(B));
  p.from_z_ = Base::stacked(L, Eigen::Matrix<double, NY, NX>(out.C * (L + Square::Identity())))
                  .template bottomRows<kRestRows>();
  p.T_ = numeric::to_fixed<Eigen::Matrix<Scalar, NX, NX>>("ModalPlant: T", T);
  // Walk the diagonal block by block; anything outside the blocks must be exactly zero. d and o
  // of every row; the step uses those of the first kSwapRows (the pairs never straddle row
  // kSwapRows: they start at even rows, and kSwapRows is even).
  Eigen::Matrix<double, NX, 1> d = Eigen::Matrix<double, NX, 1>::Zero(), o = d;
  Square outside = L;
  for (int i = 0; i < NX;) {
    d(i) = L(i, i);
    outside(i, i) = 0;
    const bool pair = i + 1 < NX && (L(i, i + 1) != 0 || L(i + 1, i) != 0);
    if (!pair) {
      require_pole_kept_inside<Scalar>(L(i, i), 0.0, i, "ModalPlant");
      i += 1;
      continue;
    }
    // A complex pair [[a, b], [-b, a]], or the floor's double integrator [[0, t], [0, 0]]
    // (plant::lti::to_modal_form under gravity preload): the step treats both alike.
    const bool jordan = L(i, i) == 0 && L(i + 1, i + 1) == 0 && L(i + 1, i) == 0;
    if (!jordan && (L(i, i) != L(i + 1, i + 1) || L(i, i + 1) != -L(i + 1, i)))
      throw std::invalid_argument("ModalPlant: Lambda - I block at " + std::to_string(i) +
                                  " is not of the form [[a, b], [-b, a]] or [[0, t], [0, 0]]");
    if (i % 2 != 0)
      throw std::invalid_argument("ModalPlant: the 2x2 block of Lambda - I at " +
                                  std::to_string(i) +
                                  " starts at an odd index; put the complex pairs first "
                                  "(plant::lti::to_modal_form does)");
    require_pole_kept_inside<Scalar>(L(i, i), L(i, i + 1), i, "ModalPlant");
    d(i + 1) = L(i + 1, i + 1);
    o(i) = L(i, i + 1);
    o(i + 1) = L(i + 1, i);
    outside.template block<2, 2>(i, i).setZero();
    i += 2;
  }
  if (outside.cwiseAbs().maxCoeff() != 0)
    throw std::invalid_argument(
        "ModalPlant: Lambda - I is not real block-diagonal (1x1 and 2x2 blocks)");
  if constexpr (kSwapRows > 0) {
    p.d_ = d.template head<kSwapRows>().template cast<Scalar>();
    p.o_ = o.template head<kSwapRows>().template cast<Scalar>();
  }
  return p;
}

}  // namespace flexloop::plant::runtime
