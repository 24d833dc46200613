// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/metrology_frame_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "numeric/constants.hpp"
#include "offline/report/csv_writer.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"

namespace flexloop::pipeline {

namespace {

using numeric::kPi;

std::string vec(std::initializer_list<double> v) {
  std::string s = "[";
  // Snap round-off of cos(-90 deg) and the like to exact zeros, keeping the symmetry exact.
  for (double x : v)
    s += (s.size() > 1 ? ", " : "") + report::format_number(std::abs(x) < 1e-14 ? 0.0 : x);
  return s + "]";
}

}  // namespace

std::string metrology_frame_toml(const MetrologyFrameParameters& p, const std::string& header) {
  const auto& g = p.geometry;
  const double r = g.triangle_side_m / std::sqrt(3.0);
  const double beta = g.strut_angle_deg * kPi / 180.0;
  const double horizontal = g.strut_height_m * std::tan(beta);
  std::ostringstream o;
  std::istringstream h(header);
  for (std::string line; std::getline(h, line);) o << (line.empty() ? "#" : "# " + line) << "\n";
  o << "[model]\nname = \"metrology_frame\"\ndimension = 3\n\n";
  o << "# Lens and frame: one rigid body, node 1 at its centre of gravity.\n";
  o << "[[node]]\nid = \"1\"\nposition = " << vec({0, 0, -p.cog_depth_m})
    << "\nrotational = true\nmass = " << report::format_number(p.mass_kg)
    << "               # kg\ninertia = "
    << vec({p.inertia_xx_kgm2, p.inertia_xx_kgm2, p.inertia_zz_kgm2}) << "  # kg m^2\n\n";
  struct Mount {
    const char* node;
    double angle_deg;
    const char* struts[2];
    const char* floors[2];
  };
  const Mount mounts[3] = {{"3", -90, {"4", "5"}, {"9", "11"}},
                           {"5", 30, {"6", "7"}, {"13", "15"}},
                           {"7", 150, {"8", "9"}, {"17", "19"}}};
  o << "# Mount nodes (frame plates, accelerometers) in the plane z = 0.\n";
  for (const auto& m : mounts) {
    const double a = m.angle_deg * kPi / 180.0;
    o << "[[node]]\nid = \"" << m.node
      << "\"\nposition = " << vec({r * std::cos(a), r * std::sin(a), 0})
      << "\nrotational = true\n\n";
  }
  o << "# Floor plates: one per strut, below and beside its mount along the mount's tangent.\n";
  for (const auto& m : mounts) {
    const double a = m.angle_deg * kPi / 180.0;
    const double tx = -std::sin(a), ty = std::cos(a);
    for (int s = 0; s < 2; ++s) {
      const double sign = s == 0 ? 1.0 : -1.0;
      o << "[[node]]\nid = \"" << m.floors[s] << "\"\nposition = "
        << vec({r * std::cos(a) + sign * horizontal * tx, r * std::sin(a) + sign * horizontal * ty,
                -g.strut_height_m})
        << "\n\n";
    }
  }
  o << "# Rigid frame: the body to each mount.\n";
  int e = 1;
  for (const auto& m : mounts)
    o << "[[element]]\nid = \"" << e++ << "\"\ntype = \"beam\"\nnodes = [\"1\", \"" << m.node
      << "\"]\nmodes = [\"rigid\", \"rigid\", \"rigid\", \"rigid\", \"rigid\", \"rigid\"]\n\n";
  o << "# Struts: hinge + force sensor + piezo actuator with parallel spring (a truss).\n";
  for (const auto& m : mounts)
    for (int s = 0; s < 2; ++s)
      o << "[[element]]\nid = \"" << m.struts[s] << "\"\ntype = \"truss\"\nnodes = [\"" << m.node
        << "\", \"" << m.floors[s]
        << "\"]\nstiffness = " << report::format_number(p.strut_stiffness_n_per_m)
        << "  # N/m\ndamping = " << report::format_number(p.strut_damping_ns_per_m)
        << "  # N s/m\nactuator = true\n\n";
  o << "[coordinates]\n"
       "fixed = [\"y.9\", \"z.9\", \"x.11\", \"y.11\", \"x.13\", \"z.13\", \"x.15\", \"y.15\",\n"
       "         \"x.17\", \"y.17\", \"x.19\", \"z.19\"]\n"
       "dynamic = [\"e1.4\", \"e1.5\", \"e1.6\", \"e1.7\", \"e1.8\", \"e1.9\"]\n"
       "prescribed = [\"x.9\", \"z.11\", \"y.13\", \"z.15\", \"z.17\", \"y.19\"]\n";
  return o.str();
}

std::array<double, 6> metrology_frame_frequencies(const MetrologyFrameParameters& p) {
  namespace model = plant::model;
  const model::Model m = model::parse_model(metrology_frame_toml(p, ""), "<metrology frame fit>");
  const model::Linearisation lin = model::linearise(m, model::model_operating_point(m));
  const int nd = m.nd();
  const auto modes =
      plant::lti::natural_modes(lin.M.topLeftCorner(nd, nd), (lin.K + lin.G).topLeftCorner(nd, nd));
  std::array<double, 6> f{};
  if (modes.frequencies_hz.size() != 6)
    throw std::runtime_error("metrology frame: expected 6 modes");
  for (int i = 0; i < 6; ++i) f[i] = modes.frequencies_hz(i);
  std::sort(f.begin(), f.end());
  return f;
}

namespace {

// The four distinct targets: both pairs by their mean.
Eigen::Vector4d distinct(const std::array<double, 6>& f) {
  return {0.5 * (f[0] + f[1]), f[2], 0.5 * (f[3] + f[4]), f[5]};
}

MetrologyFrameParameters closed_form(const MetrologyFrameGeometry& g, double m,
                                     const std::array<double, 6>& t) {
  const double r = g.triangle_side_m / std::sqrt(3.0);
  const double beta = g.strut_angle_deg * kPi / 180.0;
  auto w2 = [](double f) { return std::pow(2 * kPi * f, 2); };
  const double l1 = w2(0.5 * (t[0] + t[1])), lz = w2(t[2]), l2 = w2(0.5 * (t[3] + t[4])),
               lt = w2(t[5]);
  MetrologyFrameParameters p;
  p.geometry = g;
  p.mass_kg = m;
  const double kv = lz * m / 3.0;  // vertical stiffness per mount
  p.strut_stiffness_n_per_m = kv / (2 * std::cos(beta) * std::cos(beta));
  const double kt = 2 * p.strut_stiffness_n_per_m * std::sin(beta) * std::sin(beta);
  const double kappa = 1.5 * kt, tilt = 1.5 * kv * r * r;
  p.inertia_zz_kgm2 = 3 * kt * r * r / lt;
  p.inertia_xx_kgm2 = kappa * tilt / (m * l1 * l2);
  const double h2 = ((l1 + l2 - kappa / m) * p.inertia_xx_kgm2 - tilt) / kappa;
  if (!(h2 > 0))
    throw std::runtime_error(
        "metrology frame fit: these targets need the centre of gravity in "
        "the mount plane or above it (h^2 = " +
        report::format_number(h2) + ")");
  p.cog_depth_m = std::sqrt(h2);
  return p;
}

// The fitted quantities as a vector of logs, and back.
Eigen::Vector4d pack(const MetrologyFrameParameters& p) {
  return {std::log(p.strut_stiffness_n_per_m), std::log(p.inertia_xx_kgm2),
          std::log(p.inertia_zz_kgm2), std::log(p.cog_depth_m)};
}
MetrologyFrameParameters unpack(MetrologyFrameParameters p, const Eigen::Vector4d& v) {
  p.strut_stiffness_n_per_m = std::exp(v(0));
  p.inertia_xx_kgm2 = std::exp(v(1));
  p.inertia_zz_kgm2 = std::exp(v(2));
  p.cog_depth_m = std::exp(v(3));
  return p;
}

}  // namespace

MetrologyFrameFit fit_metrology_frame(const MetrologyFrameGeometry& geometry, double mass_kg,
                                      double vertical_damping_ratio,
                                      const std::array<double, 6>& targets_hz,
                                      const std::function<void(const std::string&)>& progress) {
  MetrologyFrameFit fit;
  fit.start = closed_form(geometry, mass_kg, targets_hz);
  const Eigen::Vector4d target = distinct(targets_hz);
  Eigen::Vector4d v = pack(fit.start);
  auto residual = [&](const Eigen::Vector4d& x) {
    return Eigen::Vector4d(distinct(metrology_frame_frequencies(unpack(fit.start, x))) - target);
  };
  Eigen::Vector4d r = residual(v);
  constexpr double kTolHz = 1e-9;
  for (fit.iterations = 0; r.cwiseAbs().maxCoeff() > kTolHz; ++fit.iterations) {
    if (fit.iterations == 20)
      throw std::runtime_error("metrology frame fit: no convergence in 20 Newton iterations");
    Eigen::Matrix4d J;
    for (int j = 0; j < 4; ++j) {
      const double step = 1e-6;
      Eigen::Vector4d vp = v, vm = v;
      vp(j) += step;
      vm(j) -= step;
      J.col(j) = (residual(vp) - residual(vm)) / (2 * step);
    }
    v -= J.partialPivLu().solve(r);
    r = residual(v);
    if (progress) {
      char line[160];
      std::snprintf(line, sizeof line, "  iteration %d: largest frequency error %.3e Hz",
                    fit.iterations + 1, r.cwiseAbs().maxCoeff());
      progress(line);
    }
  }
  fit.fitted = unpack(fit.start, v);
  // Strut damper for the vertical mode's damping ratio: c_v = 3 * 2 d cos^2(beta) = 2 zeta m w_z.
  const double beta = geometry.strut_angle_deg * kPi / 180.0;
  const double wz = 2 * kPi * targets_hz[2];
  fit.fitted.strut_damping_ns_per_m =
      2 * vertical_damping_ratio * mass_kg * wz / (6 * std::cos(beta) * std::cos(beta));
  fit.frequencies_hz = metrology_frame_frequencies(fit.fitted);
  return fit;
}

}  // namespace flexloop::pipeline
