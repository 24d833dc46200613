// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The discrete plant on the general path (doc/design.md §6): any state count, any channel counts up
// to kMaxChannels per kind, sized once at start-up from the artefact. The same sample as the
// compiled DensePlant / ModalPlant (state_output.hpp explains the held inputs and why the next
// output's C x is computed in advance()):
//
//   output(w)   = C x + D_s w + D_h h          h: the held inputs of the last advance()
//   advance(u):   x <- x + ((Ad - I) x + Bd u),  C x + D_h h of the new state, h = held part of u
//
// Dense form (GeneralDensePlant): the increment (Ad - I) x + Bd u and the next output's
// (C Ad) x + (C Bd + [0 D_h]) u, (NX + NY)(NX + NU) multiply-adds. Modal form (GeneralModalPlant,
// from plant::lti::ModalForm): z <- z + ((Λ - I) z + Bm u) with Λ - I applied block by block (2x2
// pairs first, then 1x1), and the next output from (Cm Λ) z and (Cm Bm + [0 D_h]) u:
// O(NX (NU + NY)) instead of O(NX²).
//
// Storage: the matrices and the state are allocated at start-up (from_matrices, from_modal_form),
// with their rows padded to whole SIMD packets for the step's products
// (numeric/dynamic_product.hpp); the channel vectors are bounded (inline). output() and
// advance() only write into that storage: they never allocate, lock, throw or make a system call
// (tests/alloc checks it at several sizes).
#include <Eigen/Core>
#include <algorithm>
#include <string>
#include <type_traits>
#include <vector>

#include "numeric/channel_limits.hpp"
#include "numeric/dynamic_product.hpp"

namespace flexloop::plant::runtime {

/// What both general forms share: sizes, the state, the held inputs and the output.
template <typename Scalar>
class GeneralStateOutput {
 public:
  /// Inputs: sampled (disturbances) then held (actuator commands); outputs: any.
  static constexpr int kMaxInputs = 2 * numeric::kMaxChannels,
                       kMaxOutputs = 2 * numeric::kMaxChannels;
  using State = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  using Input = numeric::BoundedVector<Scalar, kMaxInputs>;
  using Held = numeric::BoundedVector<Scalar, numeric::kMaxChannels>;
  using Output = numeric::BoundedVector<Scalar, kMaxOutputs>;

  Eigen::Index states() const noexcept { return x_.size(); }
  Eigen::Index inputs() const noexcept { return nu_; }
  Eigen::Index outputs() const noexcept { return y_.size(); }
  Eigen::Index held_inputs() const noexcept { return held_.size(); }
  Eigen::Index sampled_inputs() const noexcept { return nu_ - held_.size(); }

  /// y = C x + D [w; h]; w: the sampled inputs (a vector or a segment of one).
  template <typename W>
  const Output& output(const Eigen::MatrixBase<W>& w) noexcept {
    // Writes the padded rows too: y_'s inline storage holds kMaxOutputs >= padded rows.
    numeric::product(D_sampled_.data(), D_sampled_.cols(), contiguous(w, w_), D_sampled_.rows(),
                     cx_.data(), y_.data());
    return y_;
  }

  const State& state() const noexcept { return x_; }
  const Held& held() const noexcept { return held_; }
  /// Sets x; the held inputs stay.
  void set_state(const State& x) noexcept {
    x_ = x;
    cx_.noalias() = C_ * x_;
    cx_.noalias() += D_held_ * held_;
  }
  /// Sets x and the held inputs (a run's start, artefact/loop_start.hpp).
  void set_state(const State& x, const Held& held) noexcept {
    held_ = held;
    set_state(x);
  }
  void reset() noexcept {
    x_.setZero();
    held_.setZero();
    cx_.setZero();
  }

 protected:
  GeneralStateOutput() = default;

  /// Start-up: sizes and C, D (the plant's coordinates), checked, and the next output's product
  /// from u, C B + [0 D_h] (B in the plant's coordinates).
  /// @throws std::invalid_argument naming `who` and the matrix for inconsistent sizes, channel
  /// counts beyond the limits, or non-finite entries.
  void load_output(const std::string& who, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                   const Eigen::MatrixXd& D, Eigen::Index held_inputs);
  /// v's entries, contiguous: v's own storage where it has one (a vector or a segment of one),
  /// else copied into `buffer`.
  template <typename V, typename Buffer>
  static const Scalar* contiguous(const Eigen::MatrixBase<V>& v, Buffer& buffer) noexcept {
    // A column vector at compile time: a one-row block of a matrix also has inner stride 1, but
    // its entries are a column apart.
    if constexpr (std::is_same_v<typename V::Scalar, Scalar> && V::ColsAtCompileTime == 1 &&
                  V::InnerStrideAtCompileTime == 1 && requires { v.derived().data(); }) {
      return v.derived().data();
    } else {
      buffer = v;
      return buffer.data();
    }
  }

  /// Within a step, before x changes: C x + D_h h of the next state from the present one,
  /// (C Ad) x + (C Bd + [0 D_h]) u (dense; modal: Cm Λ and Cm Bm), and the held inputs. Returns
  /// u's entries, contiguous, for the rest of the step.
  template <typename U>
  const Scalar* next_output(const Eigen::MatrixBase<U>& u) noexcept {
    const Scalar* in = contiguous(u, u_);
    numeric::product_sum(out_from_x_.data(), x_.size(), x_.data(), out_from_u_.data(), nu_, in,
                         out_from_x_.rows(), nullptr, cx_.data());
    std::copy_n(in + (nu_ - held_.size()), held_.size(), held_.data());
    return in;
  }

  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  Eigen::Index nu_ = 0;
  // Rows padded to whole SIMD packets (zeros below): C, D_h and D_s as loaded, and the next
  // output's products from x and from u.
  Matrix C_, D_held_, D_sampled_, out_from_x_, out_from_u_;
  State x_, next_;  // next_: the increment of x in advance(), padded rows
  Held held_;
  numeric::BoundedVector<Scalar, numeric::kMaxChannels>
      w_;    // the sampled inputs, contiguous for the product
  Input u_;  // the inputs, where they are not contiguous
  // C x + D_h h with padded rows (the padding zero), and the last output, whose inline storage
  // also takes the padded rows output() writes.
  numeric::BoundedVector<Scalar, kMaxOutputs> cx_;
  Output y_;
};

/// Dense form: x <- x + ([Ad - I] x + Bd u).
template <typename Scalar>
class GeneralDensePlant : public GeneralStateOutput<Scalar> {
  using Base = GeneralStateOutput<Scalar>;

 public:
  /// Start-up: the last `held_inputs` inputs are held (the actuator commands).
  /// @throws std::invalid_argument for inconsistent sizes or non-finite entries.
  static GeneralDensePlant from_matrices(const Eigen::MatrixXd& Ad, const Eigen::MatrixXd& Bd,
                                         const Eigen::MatrixXd& Cd, const Eigen::MatrixXd& Dd,
                                         Eigen::Index held_inputs);

  template <typename U>
  void advance(const Eigen::MatrixBase<U>& u) noexcept {
    const Scalar* in = this->next_output(u);
    auto& x = this->x_;
    numeric::product_sum(increment_from_x_.data(), x.size(), x.data(), increment_from_u_.data(),
                         this->nu_, in, increment_from_x_.rows(), nullptr, this->next_.data());
    x += this->next_.head(x.size());
  }

 private:
  GeneralDensePlant() = default;
  typename Base::Matrix increment_from_x_, increment_from_u_;  // Ad - I, Bd (padded rows)
};

/// Modal form: z <- z + ((Λ - I) z + Bm u), Λ real block-diagonal (2x2 blocks first).
template <typename Scalar>
class GeneralModalPlant : public GeneralStateOutput<Scalar> {
  using Base = GeneralStateOutput<Scalar>;

 public:
  /// Start-up: Λ - I, Bm, Cm, D and T of plant::lti::ModalForm; the last `held_inputs` inputs
  /// are held. @throws std::invalid_argument for inconsistent sizes, non-finite entries, a
  /// Λ - I that is not real block-diagonal with its 2x2 blocks first, or a decaying pole that
  /// Scalar cannot keep inside the unit circle (pole_precision.hpp).
  static GeneralModalPlant from_modal_form(const Eigen::MatrixXd& Lambda_minus_I,
                                           const Eigen::MatrixXd& Bm, const Eigen::MatrixXd& Cm,
                                           const Eigen::MatrixXd& D, const Eigen::MatrixXd& T,
                                           Eigen::Index held_inputs);
  template <typename Form>
  static GeneralModalPlant from_modal_form(const Form& form, Eigen::Index held_inputs) {
    return from_modal_form(form.Lambda_minus_I, form.B, form.C, form.D, form.T, held_inputs);
  }

  template <typename U>
  void advance(const Eigen::MatrixBase<U>& u) noexcept {
    const Scalar* in = this->next_output(u);
    auto& z = this->x_;
    auto& next = this->next_;
    const Eigen::Index n = z.size();
    numeric::product(bm_.data(), this->nu_, in, bm_.rows(), nullptr, next.data());
    // Pairs: [[a, b], [-b, a]] - I as d = a - 1 on the diagonal, o = ±b off it. On raw
    // pointers that cannot alias, so that the compiler may take several pairs per instruction.
    Scalar* __restrict zp = z.data();
    const Scalar* __restrict dp = d_.data();
    const Scalar* __restrict op = o_.data();
    const Scalar* __restrict np = next.data();
    for (Eigen::Index k = 0; k < 2 * pairs_; k += 2) {
      const Scalar z0 = zp[k], z1 = zp[k + 1];
      zp[k] = z0 + ((dp[k] * z0 + op[k] * z1) + np[k]);
      zp[k + 1] = z1 + ((dp[k + 1] * z1 + op[k + 1] * z0) + np[k + 1]);
    }
    for (Eigen::Index k = 2 * pairs_; k < n; ++k) zp[k] += dp[k] * zp[k] + np[k];
  }

  /// The physical state x = T z (start-up and tests; allocates).
  Eigen::VectorXd physical_state() const { return T_ * this->x_.template cast<double>(); }

 private:
  GeneralModalPlant() = default;
  Eigen::Index pairs_ = 0;
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> d_, o_;  // Λ - I by blocks
  typename Base::Matrix bm_;                        // Bm (padded rows)
  Eigen::MatrixXd T_;
};

extern template class GeneralStateOutput<double>;
extern template class GeneralStateOutput<float>;
extern template class GeneralDensePlant<double>;
extern template class GeneralDensePlant<float>;
extern template class GeneralModalPlant<double>;
extern template class GeneralModalPlant<float>;

}  // namespace flexloop::plant::runtime
