// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The last line of defence against a loop that diverges although its artefact passed the
// stability checks (a nonlinear effect, a plant at the edge of stability): the performance
// outputs z and the commands u of a sample leave the stated range
//   |[z; u]|_2 <= kDivergenceLimit   (and finite),
// in SI units (m/s², m, N). No machine this tool models comes near 1e12, and a diverging linear
// loop passes it long before double overflows. The per-sample test is one comparison on the sums
// of squares (allocation-free, no branch taken while the loop is bounded); where it diverged is
// found only once it did. `flexloop sim` and the real-time plant loop stop there and say when and
// where, and exit non-zero.
#include <Eigen/Core>
#include <cmath>
#include <sstream>
#include <string>

namespace flexloop::plant::runtime {

inline constexpr double kDivergenceLimit = 1e12;

/// Where a run left the range; step < 0: it did not.
struct Divergence {
  long step = -1;
  double t = 0;              ///< [s] of that sample
  bool command = false;      ///< false: a performance output
  Eigen::Index channel = 0;  ///< index among the performance outputs or the commands
  double value = 0;          ///< the value there (may be inf or nan)
  bool happened() const noexcept { return step >= 0; }
};

/// True when [z; u] left the range (NaN included).
template <typename Z, typename U>
bool beyond_range(const Eigen::MatrixBase<Z>& z, const Eigen::MatrixBase<U>& u) noexcept {
  return !(static_cast<double>(z.squaredNorm()) + static_cast<double>(u.squaredNorm()) <=
           kDivergenceLimit * kDivergenceLimit);
}

namespace detail {
// The first non-finite entry of v, else the largest in magnitude; -1 for an empty v.
template <typename V>
Eigen::Index worst_channel(const V& v) noexcept {
  Eigen::Index worst = -1;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(static_cast<double>(v(i)))) return i;
    if (worst < 0 || std::abs(v(i)) > std::abs(v(worst))) worst = i;
  }
  return worst;
}
inline double magnitude(double v) noexcept {
  return std::isfinite(v) ? std::abs(v) : HUGE_VAL;
}
}  // namespace detail

/// The sample `step` (at `dt` per sample) where beyond_range(z, u) held: its worst channel.
template <typename Z, typename U>
Divergence locate_divergence(long step, double dt, const Eigen::MatrixBase<Z>& z,
                             const Eigen::MatrixBase<U>& u) noexcept {
  Divergence d;
  d.step = step;
  d.t = static_cast<double>(step) * dt;
  const Eigen::Index zi = detail::worst_channel(z), ui = detail::worst_channel(u);
  d.command = zi < 0 || (ui >= 0 && detail::magnitude(static_cast<double>(u(ui))) >
                                        detail::magnitude(static_cast<double>(z(zi))));
  d.channel = d.command ? ui : zi;
  d.value = static_cast<double>(d.command ? u(ui) : z(zi));
  return d;
}

/// "diverged at t = 0.33 s (sample 3304): performance output acc:x.frame = 6e+11 m/s^2 (...)".
inline std::string describe(const Divergence& d, const std::string& channel,
                            const std::string& unit) {
  std::ostringstream os;
  os.precision(4);
  os << "diverged at t = " << d.t << " s (sample " << d.step
     << "): " << (d.command ? "command " : "performance output ") << channel << " = " << d.value
     << " " << unit
     << " (the performance outputs and commands left |[z; u]| <= " << kDivergenceLimit << ")";
  return os.str();
}

/// The same, naming the channel from a channel map with `performance` and `actuators` lists of
/// {name, unit} (artefact::ChannelMap).
template <typename ChannelMap>
std::string describe(const Divergence& d, const ChannelMap& channels) {
  const auto& c = d.command ? channels.actuators.at(static_cast<std::size_t>(d.channel))
                            : channels.performance.at(static_cast<std::size_t>(d.channel));
  return describe(d, c.name, c.unit);
}

}  // namespace flexloop::plant::runtime
