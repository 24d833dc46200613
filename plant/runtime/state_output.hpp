// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the dense and the modal plant share: the state x, the output y = C x + D u of the current
// state, and the vector and matrix types of the compile-time sizes. The dynamics (advance) are the
// derived class's. output() never allocates, locks, throws or makes a system call.
//
// Held inputs (NH > 0): the last NH inputs are held from one advance() to the next, as actuator
// forces are in the sampled loop (plant/lti/feedback_interconnection.hpp): at sample k the
// sensors see the force applied since k-1, and the controller's new command enters only with
// advance(). The first NS = NU - NH inputs are sampled (floor accelerations, known at the
// instant). Then
//
//   output(w_k) = C x_k + D_s w_k + D_h h,   h = the held inputs of the last advance() (0 first)
//
// and the plant keeps C x + D_h h with the state, computed in advance() from the same u_k by
// stacking (C Bd + [0 D_h]) u_k: the command reaches the next output through that one product of
// its columns, not through a second product with D_h at the next sample (measured in
// plant/runtime/README.md). With NH = 0 every input is sampled: output(u) = C x + D u.
//
// The state part of the output, C x, is kept with the state (cx_) instead of being computed from
// it in output(): advance() computes it for the next state alongside that state, from the same
// x_k and u_k, as C x_{k+1} = (C Ad) x_k + (C Bd) u_k (doc/design.md §6). In a closed loop this
// takes the new state off the path from one command to the next: u_k reaches y_{k+1} through one
// product of the command's columns, (C Bd) u_k + D u_k, instead of through x_{k+1} and then C
// x_{k+1} (measured in plant/runtime/README.md). It is not a recursion (each C x_{k+1} comes from
// x_k, not from C x_k), so rounding does not accumulate in it.
#include <Eigen/Core>
#include <string>

#include "numeric/column_product.hpp"
#include "numeric/fixed_size_matrix.hpp"

namespace flexloop::plant::runtime {

template <typename Scalar, int NX, int NU, int NY, int NH>
class StateOutput {
  static_assert(NX > 0 && NU > 0 && NY > 0, "sizes are compile-time and positive");
  static_assert(NH >= 0 && NH < NU, "held inputs: 0 .. NU - 1 (at least one input is sampled)");

 public:
  /// Inputs sampled at each output (the rest, NH, are held from one advance() to the next).
  static constexpr int kSampledInputs = NU - NH;
  static constexpr int kHeldInputs = NH;
  using State = Eigen::Matrix<Scalar, NX, 1>;
  using Input = Eigen::Matrix<Scalar, NU, 1>;
  using Held = Eigen::Matrix<Scalar, NH, 1>;
  using Output = Eigen::Matrix<Scalar, NY, 1>;

  /// y = C x + D [w; h] for the current state x and the held inputs h (kept with the state), w the
  /// sampled inputs (all of u when NH = 0): any vector expression of NU - NH entries, read entry
  /// by entry (a head() of the input vector is not copied first). Forced inline: left to itself
  /// GCC inlined it into one plant form's closed loop and called it from the other's, by turns.
  template <typename W>
  EIGEN_ALWAYS_INLINE Output output(const Eigen::MatrixBase<W>& w) const noexcept {
    static_assert(W::SizeAtCompileTime == kSampledInputs,
                  "output(w): w is the sampled inputs, NU - NH entries (the held ones are kept)");
    return (cx_ + numeric::column_product(D_sampled_, w)).template head<NY>();
  }

  static constexpr Eigen::Index states() noexcept { return NX; }
  static constexpr Eigen::Index inputs() noexcept { return NU; }
  static constexpr Eigen::Index outputs() noexcept { return NY; }
  static constexpr Eigen::Index held_inputs() noexcept { return NH; }
  static constexpr Eigen::Index sampled_inputs() noexcept { return kSampledInputs; }

  const State& state() const noexcept { return x_; }
  /// The held inputs: those of the last advance() (zero after reset()).
  const Held& held() const noexcept { return held_; }
  /// Sets x; the held inputs stay.
  void set_state(const State& x) noexcept {
    x_ = x;
    cx_.template head<NY>() = C_ * x;
    if constexpr (NH > 0) cx_.template head<NY>() += D_held_ * held_;
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
  StateOutput() = default;

  // Output-sized columns are padded to whole SIMD packets (column_product.hpp) with zero rows: 12
  // doubles take 16 lanes, two aligned 8-wide packets, where 12 rows would put every other
  // column across a cache-line boundary; 12 floats take one 16-wide packet.
  static constexpr int kOutputLanes = numeric::kPaddedRows<Scalar, NY>;
  using OutputLanes = Eigen::Matrix<Scalar, kOutputLanes, 1>;
  // The rows of advance()'s products, which give the next state's increment (rows 0 .. NX-1) and
  // its C x (rows NX .. NX+NY-1) together; padded the same way.
  static constexpr int kStackedRows = numeric::kPaddedRows<Scalar, NX + NY>;
  using Stacked = Eigen::Matrix<Scalar, kStackedRows, 1>;

  /// C and D of the artefact, checked, in double (start-up).
  struct CheckedOutput {
    Eigen::Matrix<double, NY, NX> C;
    Eigen::Matrix<double, NY, NU> D;
    /// The next output's part from the input of advance(): C B u_k, and D_h h_k for the held
    /// inputs (they stay in the output until the next advance()). B: NX x NU, in the plant's
    /// coordinates (Bd, or Bm of the modal form).
    Eigen::Matrix<double, NY, NU> next_output_from_input(
        const Eigen::Matrix<double, NX, NU>& B) const {
      Eigen::Matrix<double, NY, NU> m = C * B;
      if constexpr (NH > 0) m.template rightCols<NH>() += D.template rightCols<NH>();
      return m;
    }
  };
  /// Start-up: C and D from the artefact, named "<who>: <c_name>" in a size error. Returns them
  /// checked, in double (for the stacked products of advance()).
  CheckedOutput load_output(const std::string& who, const char* c_name, const Eigen::MatrixXd& C,
                            const char* d_name, const Eigen::MatrixXd& D) {
    CheckedOutput checked{numeric::to_fixed<Eigen::Matrix<double, NY, NX>>(who + ": " + c_name, C),
                          numeric::to_fixed<Eigen::Matrix<double, NY, NU>>(who + ": " + d_name, D)};
    C_ = checked.C.template cast<Scalar>();
    D_held_ = checked.D.template rightCols<NH>().template cast<Scalar>();
    D_sampled_ = numeric::padded_rows<kOutputLanes>(Eigen::Matrix<Scalar, NY, kSampledInputs>(
        checked.D.template leftCols<kSampledInputs>().template cast<Scalar>()));
    return checked;
  }
  /// Start-up: [top; bottom] in Scalar with the rows padded to kStackedRows.
  template <int K>
  static Eigen::Matrix<Scalar, kStackedRows, K> stacked(
      const Eigen::Matrix<double, NX, K>& top, const Eigen::Matrix<double, NY, K>& bottom) {
    Eigen::Matrix<Scalar, kStackedRows, K> m = Eigen::Matrix<Scalar, kStackedRows, K>::Zero();
    m.template topRows<NX>() = top.template cast<Scalar>();
    m.template middleRows<NY>(NX) = bottom.template cast<Scalar>();
    return m;
  }
  /// Within a step: x += the increment of `next`, C x + D_h h = its next rows (padding lanes stay
  /// zero), h = the held inputs of u.
  void take_next(const Stacked& next, const Input& u) noexcept {
    x_ += next.template head<NX>();
    cx_.template head<NY>() = next.template segment<NY>(NX);
    if constexpr (NH > 0) held_ = u.template tail<NH>();
  }

  Eigen::Matrix<Scalar, NY, NX> C_;       // for set_state() only
  Eigen::Matrix<Scalar, NY, NH> D_held_;  // for set_state() only
  Eigen::Matrix<Scalar, kOutputLanes, kSampledInputs> D_sampled_;
  State x_ = State::Zero();
  Held held_ = Held::Zero();
  OutputLanes cx_ = OutputLanes::Zero();  // C x_ + D_h held_, set by advance() and set_state()
};

}  // namespace flexloop::plant::runtime
