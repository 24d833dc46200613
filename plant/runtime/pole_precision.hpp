// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Whether a pole keeps its decay once the runtime stores it in Scalar. The modal plant keeps
// Λ - I: a pole z = 1 + a ± jb as the entries a and b. Its squared modulus is |z|² = 1 + m with
// m = 2a + a² + b² (m < 0: inside the circle, decaying at a rate ∝ -m). Rounding a and b to
// float moves m by up to about 2^-24 (2|a| + 2b²). A lightly damped fast mode whose -m is not
// well above that changes its decay, and the height of its resonance peak (∝ 1/-m) with it; one
// whose -m is below it ends up on or outside the circle: a plant that decays in double would
// ring forever or grow. Start-up refuses both, a pole whose decay float changes by more than
// kDecayTolerance and one float does not keep inside (ModalPlant, GeneralModalPlant, and likewise
// DensePlant, GeneralDensePlant); `flexloop analyse` reports each pole's headroom.
#include <Eigen/Core>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace flexloop::plant::runtime {

/// The largest relative change of a decaying pole's m that start-up accepts: past it, that mode's
/// resonance peak in the stored plant is more than 10 % off the machine's.
inline constexpr double kDecayTolerance = 0.1;

struct PoleMargin {
  double exact;   ///< m = |z|² - 1 from a, b in double
  double stored;  ///< the same from a, b rounded to Scalar (computed in double)

  /// How much rounding changed the decay: |stored - exact| / |exact|.
  double decay_change() const noexcept { return std::abs(stored - exact) / std::abs(exact); }
  /// Decays in Scalar, at a rate within kDecayTolerance of double's.
  bool kept() const noexcept { return stored < 0 && decay_change() <= kDecayTolerance; }
};

template <typename Scalar>
PoleMargin pole_margin(double a, double b) noexcept {
  const auto m = [](double x, double y) { return 2 * x + x * x + y * y; };
  return {m(a, b), m(static_cast<Scalar>(a), static_cast<Scalar>(b))};
}

/// A pole whose |m| is within the rounding of computing it in double, 16 eps (|a| + |b|), is on
/// the unit circle (an undamped mode, an integrator): marginal in double already, so float is
/// not asked to keep it inside (an eigensolver's last bits decide the sign of its m).
inline bool on_unit_circle(double a, double b, double exact_margin) noexcept {
  return std::abs(exact_margin) <= 16 * 2.220446049250313e-16 * (std::abs(a) + std::abs(b));
}

/// The refusal of both forms: `pole` says which ("the pole at row 4"), `stored_as` how float
/// holds it; `exact` and `stored` are |z|^2 - 1 in double and as stored.
[[noreturn]] inline void throw_pole_not_kept(const std::string& who, const std::string& pole,
                                             double a, double b, double exact, double stored,
                                             const std::string& stored_as) {
  std::ostringstream os;
  os.precision(3);
  os << who << ": " << pole << ", z = 1 + (" << a << (b < 0 ? " - " : " + ") << std::abs(b)
     << "j), decays with |z|^2 - 1 = " << exact << " in double but " << stored << " " << stored_as
     << ": ";
  if (stored >= 0)
    os << "float puts it on or outside the unit circle, the plant would not decay";
  else
    os << "float changes its decay by " << 100 * std::abs(stored - exact) / std::abs(exact)
       << " % (more than " << 100 * kDecayTolerance
       << " %), and its resonance peak by about as much";
  os << "; run it in double";
  throw std::invalid_argument(os.str());
}

/// @throws std::invalid_argument naming `who`, the row and both margins when the pole 1 + a ± jb
/// is inside the unit circle in double (not on it) and, stored as Scalar, is not
/// (PoleMargin::kept).
template <typename Scalar>
void require_pole_kept_inside(double a, double b, Eigen::Index row, const std::string& who) {
  const PoleMargin p = pole_margin<Scalar>(a, b);
  if (!(p.exact < 0) || on_unit_circle(a, b, p.exact) || p.kept()) return;
  throw_pole_not_kept(who, "the pole at row " + std::to_string(row), a, b, p.exact, p.stored,
                      "in float");
}

/// The dense plants' counterpart: they store Ad - I rounded to Scalar, so their poles are the
/// eigenvalues of I + fl(Ad - I). Each pole of Ad inside the unit circle (not on it, as above)
/// is paired with the nearest pole of the stored matrix; when that one is on or outside the
/// circle, or decays more than kDecayTolerance apart, the plant is refused as above. Start-up only:
/// an eigen-decomposition of both matrices, O(n^3). @throws std::invalid_argument naming `who` and
/// the pole.
void require_dense_poles_kept_inside(const Eigen::MatrixXd& Ad, const Eigen::MatrixXd& stored,
                                     const std::string& who);

template <typename Scalar>
void require_dense_poles_kept_inside(const Eigen::MatrixXd& Ad, const std::string& who) {
  if constexpr (!std::is_same_v<Scalar, double>) {
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(Ad.rows(), Ad.cols());
    require_dense_poles_kept_inside(Ad, I + (Ad - I).cast<Scalar>().template cast<double>(), who);
  }
}

}  // namespace flexloop::plant::runtime
