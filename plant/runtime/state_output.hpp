#pragma once
// What the dense and the modal plant share: the state x, the output y = C x + D u of the current
// state, and the vector and matrix types of the compile-time sizes. The dynamics (advance) are the
// derived class's. output() never allocates, locks, throws or makes a system call.
//
// The state part of the output, C x, is kept with the state (cx_) instead of being computed from
// it in output(): advance() computes it for the next state alongside that state, from the same
// x_k and u_k, as C x_{k+1} = (C Ad) x_k + (C Bd) u_k (DESIGN.md §6). In a closed loop this takes
// the new state off the path from one command to the next: u_k reaches y_{k+1} through one product
// of the command's columns, (C Bd) u_k + D u_k, instead of through x_{k+1} and then C x_{k+1}
// (measured in plant/runtime/README.md). It is not a recursion (each C x_{k+1} comes from x_k, not
// from C x_k), so rounding does not accumulate in it.
#include <Eigen/Core>
#include <string>

#include "plant/runtime/column_product.hpp"
#include "plant/runtime/fixed_size_matrix.hpp"

namespace flexloop::plant::runtime {

template <typename Scalar, int NX, int NU, int NY>
class StateOutput {
  static_assert(NX > 0 && NU > 0 && NY > 0, "sizes are compile-time and positive");

 public:
  using State = Eigen::Matrix<Scalar, NX, 1>;
  using Input = Eigen::Matrix<Scalar, NU, 1>;
  using Output = Eigen::Matrix<Scalar, NY, 1>;
  using OutputMatrix = Eigen::Matrix<Scalar, NY, NX>;
  using FeedthroughMatrix = Eigen::Matrix<Scalar, NY, NU>;

  /// y = C x + D u, for the current state (C x kept with it). Forced inline: left to itself GCC
  /// inlined it into one plant form's closed loop and called it from the other's, by turns.
  EIGEN_ALWAYS_INLINE Output output(const Input& u) const noexcept {
    return (cx_ + column_product(D_, u)).template head<NY>();
  }

  const State& state() const noexcept { return x_; }
  void set_state(const State& x) noexcept {
    x_ = x;
    cx_.template head<NY>() = column_product(C_, x);
  }
  void reset() noexcept {
    x_.setZero();
    cx_.setZero();
  }

 protected:
  StateOutput() = default;

  // Output-sized columns are padded to whole SIMD packets (column_product.hpp) with zero rows: 12
  // doubles take 16 lanes, two aligned 8-wide packets, where 12 rows would put every other
  // column across a cache-line boundary; 12 floats take one 16-wide packet.
  static constexpr int kOutputLanes = kPaddedRows<Scalar, NY>;
  using OutputLanes = Eigen::Matrix<Scalar, kOutputLanes, 1>;
  // The rows of advance()'s products, which give the next state's increment (rows 0 .. NX-1) and
  // its C x (rows NX .. NX+NY-1) together; padded the same way.
  static constexpr int kStackedRows = kPaddedRows<Scalar, NX + NY>;
  using Stacked = Eigen::Matrix<Scalar, kStackedRows, 1>;

  /// Start-up: C and D from the artefact, named "<who>: <c_name>" in a size error. Returns C,
  /// checked, in double (for the stacked products of advance()).
  Eigen::Matrix<double, NY, NX> load_output(const std::string& who, const char* c_name,
                                            const Eigen::MatrixXd& C, const char* d_name,
                                            const Eigen::MatrixXd& D) {
    const auto C_checked = to_fixed<Eigen::Matrix<double, NY, NX>>(who + ": " + c_name, C);
    C_ = C_checked.template cast<Scalar>();
    D_ = padded_rows<kOutputLanes>(to_fixed<FeedthroughMatrix>(who + ": " + d_name, D));
    return C_checked;
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
  /// Within a step: x += the increment of `next`, C x = its next rows (padding lanes stay zero).
  void take_next(const Stacked& next) noexcept {
    x_ += next.template head<NX>();
    cx_.template head<NY>() = next.template segment<NY>(NX);
  }

  OutputMatrix C_;  // for set_state() only
  Eigen::Matrix<Scalar, kOutputLanes, NU> D_;
  State x_ = State::Zero();
  OutputLanes cx_ = OutputLanes::Zero();  // C x_, set by advance() and set_state()
};

}  // namespace flexloop::plant::runtime
