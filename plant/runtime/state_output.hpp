#pragma once
// What the dense and the modal plant share: the state x, the output y = C x + D u of the current
// state, and the vector and matrix types of the compile-time sizes. The dynamics (advance) are the
// derived class's. output() never allocates, locks, throws or makes a system call.
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
  using InputMatrix = Eigen::Matrix<Scalar, NX, NU>;
  using OutputMatrix = Eigen::Matrix<Scalar, NY, NX>;
  using FeedthroughMatrix = Eigen::Matrix<Scalar, NY, NU>;

  /// y = C x + D u, for the current state.
  Output output(const Input& u) const noexcept {
    return product_sum(C_, x_, D_, u);  // (C x) + (D u), column by column
  }

  const State& state() const noexcept { return x_; }
  void set_state(const State& x) noexcept { x_ = x; }
  void reset() noexcept { x_.setZero(); }

 protected:
  StateOutput() = default;

  /// Start-up: C and D from the artefact, named "<who>: <c_name>" in a size error.
  void load_output(const std::string& who, const char* c_name, const Eigen::MatrixXd& C,
                   const char* d_name, const Eigen::MatrixXd& D) {
    C_ = to_fixed<OutputMatrix>(who + ": " + c_name, C);
    D_ = to_fixed<FeedthroughMatrix>(who + ": " + d_name, D);
  }

  OutputMatrix C_;
  FeedthroughMatrix D_;
  State x_ = State::Zero();
};

}  // namespace flexloop::plant::runtime
