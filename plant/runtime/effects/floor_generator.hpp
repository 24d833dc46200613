// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Stationary random floor acceleration on N independent channels (doc/design.md §6): each channel
// runs the same discrete shaping filter of order NF, driven by its own unit-variance white
// sequence n_k (GaussianNoise, channel c seeded by (seed, c)):
//   a_k     = Cd x_k + Dd n_k          [m/s²]
//   x_{k+1} = Ad x_k + Bd n_k
// The filter is designed offline (plant/lti/vibration_criterion.hpp: design_floor_filter, then
// discretise_floor_filter, whose Bd already carries the 1/sqrt(dt) noise scaling). The channels
// run side by side in SIMD lanes: the state is held as one row per channel (rows padded to whole
// packets, numeric/column_product.hpp), so state i of every channel is one column product,
//   x_{k+1}(i, all channels) = Σ_j Ad(i, j) x_k(j, all channels) + Bd(i) n_k,
// with the same arithmetic in every lane (channel c's signal does not depend on N). With
// N = Eigen::Dynamic the lanes are those of kMaxChannels channels, of which the first n run.
//
// Start: by default each channel's state is drawn from the filter's stationary distribution
// N(0, P), P = Ad P Adᵀ + Bd Bdᵀ (found at start-up by the doubling iteration of
// numeric/stationary_covariance.hpp, which also proves |eig(Ad)| < 1), so the floor is stationary
// from the first sample; FloorStart::kAtRest starts from x = 0 instead. Same seed, same signal (on
// the same build, see gaussian_noise.hpp); channel c's signal depends only on (matrices, seed, c).
#include <Eigen/Dense>
#include <cstdint>

#include "numeric/column_product.hpp"
#include "numeric/fixed_size_matrix.hpp"
#include "numeric/stationary_covariance.hpp"
#include "plant/runtime/effects/channels.hpp"
#include "plant/runtime/effects/gaussian_noise.hpp"

namespace flexloop::plant::runtime::effects {

enum class FloorStart { kStationary, kAtRest };

template <class Scalar, int N, int NF>
class FloorGenerator {
  static_assert(kValidChannels<Scalar, N> && NF >= 1);

 public:
  using Vector = ChannelVector<Scalar, N>;
  using StateMatrix = Eigen::Matrix<Scalar, NF, N, 0, NF, numeric::kChannelRows<N>>;
  using Motion = Eigen::Matrix<Scalar, 2, N, 0, 2, numeric::kChannelRows<N>>;

  /// Start-up (allocates). Ad NF x NF, Bd NF x 1, Cd 1 x NF, Dd 1 x 1, input a unit-variance
  /// white sequence, output acceleration [m/s²].
  /// @throws std::invalid_argument when a size differs from the compiled one (NF states, one noise
  ///         input, one output), an entry is not finite, or Ad is not stable (spectral radius >=
  ///         1).
  static FloorGenerator from_parameters(const Eigen::MatrixXd& Ad, const Eigen::MatrixXd& Bd,
                                        const Eigen::MatrixXd& Cd, const Eigen::MatrixXd& Dd,
                                        std::uint64_t seed,
                                        FloorStart start = FloorStart::kStationary,
                                        Eigen::Index channels = N) {
    FloorGenerator g(numeric::to_fixed<Eigen::Matrix<Scalar, NF, NF>>("floor generator: Ad", Ad),
                     numeric::to_fixed<Eigen::Matrix<Scalar, NF, 1>>("floor generator: Bd", Bd),
                     numeric::to_fixed<Eigen::Matrix<Scalar, 1, NF>>("floor generator: Cd", Cd),
                     numeric::to_fixed<Eigen::Matrix<Scalar, 1, 1>>("floor generator: Dd", Dd),
                     GaussianNoise<Scalar, N>::from_seed(seed, channels));
    if (start == FloorStart::kStationary) g.draw_stationary_state(stationary_covariance(Ad, Bd));
    return g;
  }

  /// The floor acceleration of this sample [m/s²], one per channel; advances the filters.
  Vector step() noexcept {
    const Lanes n = noise_.template sample_lanes<NP>();
    const Lanes a = numeric::column_product(x_, c_) + d_ * n;
    Lanes next[NF];
    for (int i = 0; i < NF; ++i) next[i] = numeric::column_product(x_, a_t_.col(i)) + b_(i) * n;
    for (int i = 0; i < NF; ++i) x_.col(i) = next[i];
    return a.template head<N>(channels());
  }

  int channels() const noexcept { return noise_.channels(); }

  /// The filters' states, one column per channel.
  StateMatrix state() const noexcept { return x_.template topRows<N>(channels()).transpose(); }

  /// Start-up: the floor's velocity and displacement as rows over the filter state (2 x NF,
  /// plant::lti::floor_motion_outputs), so that motion() can say where the floor is.
  /// @throws std::invalid_argument for another size or a non-finite entry.
  void set_motion_outputs(const Eigen::MatrixXd& motion) {
    motion_ =
        numeric::to_fixed<Eigen::Matrix<Scalar, 2, NF>>("floor generator: motion outputs", motion);
  }
  /// Floor velocity [m/s] (row 0) and displacement [m] (row 1) per channel at the sample the next
  /// step() returns (zero until set_motion_outputs). A plant with the floor's position and
  /// velocity as states starts them here.
  Motion motion() const noexcept { return motion_ * state(); }

  /// P = Ad P Adᵀ + Bd Bdᵀ (numeric/stationary_covariance.hpp). @throws std::invalid_argument
  /// when Ad is not stable (the doubling does not settle).
  static Eigen::MatrixXd stationary_covariance(const Eigen::MatrixXd& Ad,
                                               const Eigen::MatrixXd& Bd) {
    auto p = numeric::stationary_covariance(Ad, Bd);
    require(p.has_value(), "floor generator", "Ad is not stable (spectral radius >= 1)");
    return *p;
  }

 private:
  // Lanes: the channels, then zero padding.
  static constexpr int NP = numeric::kPaddedRows<Scalar, numeric::kChannelRows<N>>;
  using Lanes = Eigen::Matrix<Scalar, NP, 1>;

  FloorGenerator(const Eigen::Matrix<Scalar, NF, NF>& a, const Eigen::Matrix<Scalar, NF, 1>& b,
                 const Eigen::Matrix<Scalar, 1, NF>& c, const Eigen::Matrix<Scalar, 1, 1>& d,
                 const GaussianNoise<Scalar, N>& noise)
      : a_t_(a.transpose()), b_(b), c_(c.transpose()), d_(d(0)), noise_(noise) {}

  // x_c = V sqrt(Λ) z with P = V Λ Vᵀ (P is only semidefinite in general), z from channel c.
  void draw_stationary_state(const Eigen::MatrixXd& p) {
    const Eigen::MatrixXd root = numeric::covariance_root(p);
    for (int c = 0; c < channels(); ++c) {
      Eigen::VectorXd z(NF);
      for (int i = 0; i < NF; ++i) z(i) = static_cast<double>(noise_.sample(c));
      x_.row(c) = (root * z).transpose().cast<Scalar>();
    }
  }

  Eigen::Matrix<Scalar, NF, NF> a_t_;  // Adᵀ: column i holds row i of Ad
  Eigen::Matrix<Scalar, NF, 1> b_;
  Eigen::Matrix<Scalar, NF, 1> c_;  // Cdᵀ
  Scalar d_;
  Eigen::Matrix<Scalar, NP, NF> x_ = Eigen::Matrix<Scalar, NP, NF>::Zero();  // row c: channel c
  Eigen::Matrix<Scalar, 2, NF> motion_ = Eigen::Matrix<Scalar, 2, NF>::Zero();
  GaussianNoise<Scalar, N> noise_;
};

}  // namespace flexloop::plant::runtime::effects
