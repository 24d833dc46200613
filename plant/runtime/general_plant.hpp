#pragma once
// The discrete plant on the general path (DESIGN.md §6): any state count, any channel counts up
// to kMaxChannels per kind, sized once at start-up from the artefact. The same sample as the
// compiled DensePlant / ModalPlant (state_output.hpp explains the held inputs and why the next
// output's C x is computed in advance()):
//
//   output(w)   = C x + D_s w + D_h h          h: the held inputs of the last advance()
//   advance(u):   x <- x + ((Ad - I) x + Bd u),  C x + D_h h of the new state, h = held part of u
//
// Dense form (GeneralDensePlant): the stacked products [Ad - I; C Ad] x and [Bd; C Bd + [0 D_h]] u,
// (NX + NY)(NX + NU) multiply-adds. Modal form (GeneralModalPlant, from plant::lti::ModalForm):
// z <- z + ((Λ - I) z + Bm u) with Λ - I applied block by block (2x2 pairs first, then 1x1), and
// the next output from (Cm Λ) z and (Cm Bm + [0 D_h]) u: O(NX (NU + NY)) instead of O(NX²).
//
// Storage: the matrices and the state are allocated at start-up (from_matrices, from_modal_form);
// the channel vectors are bounded (inline). output() and advance() only write into that storage
// through Eigen's no-alias products: they never allocate, lock, throw or make a system call
// (tests/alloc checks it at several sizes).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "online/numeric/channel_limits.hpp"

namespace flexloop::plant::runtime {

/// What both general forms share: sizes, the state, the held inputs and the output.
template <typename Scalar>
class GeneralStateOutput {
 public:
  /// Inputs: sampled (disturbances) then held (actuator commands); outputs: any.
  static constexpr int kMaxInputs = 2 * kMaxChannels, kMaxOutputs = 2 * kMaxChannels;
  using State = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  using Input = BoundedVector<Scalar, kMaxInputs>;
  using Held = BoundedVector<Scalar, kMaxChannels>;
  using Output = BoundedVector<Scalar, kMaxOutputs>;

  Eigen::Index states() const noexcept { return x_.size(); }
  Eigen::Index inputs() const noexcept { return nu_; }
  Eigen::Index outputs() const noexcept { return y_.size(); }
  Eigen::Index held_inputs() const noexcept { return held_.size(); }
  Eigen::Index sampled_inputs() const noexcept { return nu_ - held_.size(); }

  /// y = C x + D [w; h]; w: the sampled inputs (a vector or a segment of one).
  template <typename W>
  const Output& output(const Eigen::MatrixBase<W>& w) noexcept {
    y_ = cx_;
    y_.noalias() += D_sampled_ * w;
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
  void reset() noexcept {
    x_.setZero();
    held_.setZero();
    cx_.setZero();
  }

 protected:
  GeneralStateOutput() = default;

  /// Start-up: sizes and C, D (the plant's coordinates), checked. Returns C B + [0 D_h] for the
  /// stacked input product (B in the plant's coordinates).
  /// @throws std::invalid_argument naming `who` and the matrix for inconsistent sizes, channel
  /// counts beyond the limits, or non-finite entries.
  Eigen::MatrixXd load_output(const std::string& who, const Eigen::MatrixXd& B,
                              const Eigen::MatrixXd& C, const Eigen::MatrixXd& D,
                              Eigen::Index held_inputs);
  /// Within a step: x += the increment (rows 0 .. NX-1 of next_), C x + D_h h = its last NY rows.
  template <typename U>
  void take_next(const Eigen::MatrixBase<U>& u) noexcept {
    cx_ = next_.tail(cx_.size());
    held_ = u.tail(held_.size());
  }

  Eigen::Index nu_ = 0;
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> C_, D_held_, D_sampled_;
  State x_, next_;  // next_: the stacked sums of advance(), NX + NY rows
  Held held_;
  Output cx_, y_;  // C x + D_h h, and the last output
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
    this->next_.noalias() = from_x_ * this->x_;
    this->next_.noalias() += from_u_ * u;
    this->x_ += this->next_.head(this->x_.size());
    this->take_next(u);
  }

 private:
  GeneralDensePlant() = default;
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> from_x_;  // [Ad - I; C Ad]
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> from_u_;  // [Bd; C Bd + [0 D_h]]
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
    auto& z = this->x_;
    auto& next = this->next_;
    const Eigen::Index n = z.size();
    next.noalias() = from_u_ * u;
    next.tail(this->cx_.size()).noalias() += cm_lambda_ * z;
    // Pairs: [[a, b], [-b, a]] - I as d = a - 1 on the diagonal, o = ±b off it.
    for (Eigen::Index k = 0; k < 2 * pairs_; k += 2) {
      const Scalar z0 = z(k), z1 = z(k + 1);
      z(k) += (d_(k) * z0 + o_(k) * z1) + next(k);
      z(k + 1) += (d_(k + 1) * z1 + o_(k + 1) * z0) + next(k + 1);
    }
    for (Eigen::Index k = 2 * pairs_; k < n; ++k) z(k) += d_(k) * z(k) + next(k);
    this->take_next(u);
  }

  /// The physical state x = T z (start-up and tests; allocates).
  Eigen::VectorXd physical_state() const { return T_ * this->x_.template cast<double>(); }

 private:
  GeneralModalPlant() = default;
  Eigen::Index pairs_ = 0;
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> d_, o_;                   // Λ - I by blocks
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> from_u_;     // [Bm; Cm Bm + [0 D_h]]
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> cm_lambda_;  // Cm Λ
  Eigen::MatrixXd T_;
};

extern template class GeneralStateOutput<double>;
extern template class GeneralStateOutput<float>;
extern template class GeneralDensePlant<double>;
extern template class GeneralDensePlant<float>;
extern template class GeneralModalPlant<double>;
extern template class GeneralModalPlant<float>;

}  // namespace flexloop::plant::runtime
