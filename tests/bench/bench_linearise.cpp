// SPDX-License-Identifier: BSD-3-Clause
// Cost of linearise + build_state_space (issue 3, "Performance"; doc/design.md §3).
//
//  - BM_LineariseMetrology: a hexapod-like metrology frame, 19 nodes and 18 spatial beams: a
//    platform node with mass and inertia on six struts, each strut a universal joint at the
//    base, a flexible axial spring (the dynamic coordinate) and a spherical joint at the top,
//    carried to the platform by a rigid link. 6 dynamic coordinates, gravity preload.
//    Target: <= 20 ms.
//  - BM_LineariseCantilever/n: an n-element spatial cantilever, every beam deformation flexible
//    and dynamic (6 n dynamic coordinates), node masses and inertias, gravity preload.
//    Target: >= 1000 DOFs in <= 10 s.
//  - BM_LinearisePhases/n: the same cantilever, one pass through the steps of linearise (as in
//    plant/model/linearisation.cpp, stationary case) and build_state_space, each timed; the
//    counters are the seconds per phase: configuration (partition, reference q, Newton solve),
//    jacobian (D_x D), DFx (geometric_transfer), DFe_JxDFx (DF(e) = J DF(x)), stresses (S e and
//    the reaction stresses), M/K/D_product (DF^T M DF, DF(e)^T S DF(e), DF(e)^T S_d DF(e)),
//    hessian (sum_k sigma_k Hess D_k), G_product (DF^T H DF), state_space (build_state_space).
//
// The model text is generated here and parsed once, outside the timed region.
#include <benchmark/benchmark.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "numeric/constants.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/model/configuration.hpp"
#include "plant/model/inertia.hpp"
#include "plant/model/kinematics.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"
#include "tests/bench/lap_timer.hpp"

using namespace flexloop::plant;

namespace {

using flexloop::numeric::kPi;

// Steel tube, 20 mm x 20 mm square section.
constexpr const char* kSection =
    "E = 2.1e11\nG = 8.1e10\nA = 4.0e-4\nIy = 1.3333e-8\nIz = 1.3333e-8\nJ = 2.25e-8\n";

std::string cantilever_toml(int n) {
  constexpr double kL = 2.0;
  std::ostringstream os;
  os.precision(17);
  os << "[model]\nname = \"cantilever3d\"\ndimension = 3\ngravity = [0.0, 0.0, -9.81]\n";
  for (int i = 0; i <= n; ++i) {
    os << "[[node]]\nid = \"" << i << "\"\nposition = [" << kL * i / n << ", 0.0, 0.0]\n";
    if (i == 0)
      os << "rotational = true\n";
    else
      os << "mass = 0.05\ninertia = [1.0e-5, 2.0e-5, 2.0e-5]\n";
  }
  for (int k = 1; k <= n; ++k)
    os << "[[element]]\nid = \"b" << k << "\"\ntype = \"beam\"\nnodes = [\"" << k - 1 << "\", \""
       << k << "\"]\n"
       << kSection << "rho = 7850.0\ny_axis = [0.0, 1.0, 0.0]\n";
  os << "[coordinates]\nfixed_nodes = [\"0\"]\ndynamic = [";
  for (int k = 1; k <= n; ++k)
    for (int d = 1; d <= 6; ++d) os << (k + d > 2 ? ", " : "") << "\"e" << d << ".b" << k << "\"";
  os << "]\n";
  return os.str();
}

std::string vec3(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os.precision(17);
  os << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return os.str();
}

// Six struts B_i - M_i - T_i, T_i rigidly tied to the platform P. Per strut: element s<i>a
// (B -> M) has e1 flexible and dynamic, torsion rigid, the bendings at B released (universal
// joint) and at M rigid; element s<i>b (M -> T) has e1 and the bendings at M rigid, the torsion
// and the bendings at T released (spherical joint). Element l<i> (P -> T_i) is rigid.
std::string metrology_toml() {
  std::ostringstream os;
  os.precision(17);
  os << "[model]\nname = \"metrology frame\"\ndimension = 3\ngravity = [0.0, 0.0, -9.81]\n";
  os << "[[node]]\nid = \"P\"\nposition = [0.0, 0.0, 0.45]\nmass = 20.0\n"
        "inertia = [0.4, 0.4, 0.7]\n";
  for (int i = 0; i < 6; ++i) {
    const double pair = 2.0 * kPi / 3.0 * (i / 2), side = (i % 2 == 0 ? -1.0 : 1.0);
    const double ab = pair + side * 0.2, at = pair + side * (kPi / 3.0 - 0.25);
    const Eigen::Vector3d B(0.3 * std::cos(ab), 0.3 * std::sin(ab), 0.0);
    const Eigen::Vector3d T(0.2 * std::cos(at), 0.2 * std::sin(at), 0.4);
    const std::string s = std::to_string(i);
    os << "[[node]]\nid = \"B" << s << "\"\nposition = " << vec3(B) << "\nrotational = true\n";
    os << "[[node]]\nid = \"M" << s << "\"\nposition = " << vec3(0.5 * (B + T))
       << "\nmass = 0.3\ninertia = [1.0e-4, 1.0e-4, 1.0e-4]\n";
    os << "[[node]]\nid = \"T" << s << "\"\nposition = " << vec3(T) << "\nrotational = true\n";
  }
  for (int i = 0; i < 6; ++i) {
    const std::string s = std::to_string(i);
    os << "[[element]]\nid = \"s" << s << "a\"\ntype = \"beam\"\nnodes = [\"B" << s << "\", \"M"
       << s << "\"]\n"
       << kSection
       << "modes = [\"flexible\", \"rigid\", \"released\", \"rigid\", \"released\", \"rigid\"]\n";
    os << "[[element]]\nid = \"s" << s << "b\"\ntype = \"beam\"\nnodes = [\"M" << s << "\", \"T"
       << s << "\"]\n"
       << kSection
       << "modes = [\"rigid\", \"released\", \"rigid\", \"released\", \"rigid\", \"released\"]\n";
    os << "[[element]]\nid = \"l" << s << "\"\ntype = \"beam\"\nnodes = [\"P\", \"T" << s << "\"]\n"
       << kSection
       << "modes = [\"rigid\", \"rigid\", \"rigid\", \"rigid\", \"rigid\", \"rigid\"]\n";
  }
  os << "[coordinates]\nfixed_nodes = [\"B0\", \"B1\", \"B2\", \"B3\", \"B4\", \"B5\"]\n"
        "dynamic = [\"e1.s0a\", \"e1.s1a\", \"e1.s2a\", \"e1.s3a\", \"e1.s4a\", \"e1.s5a\"]\n";
  return os.str();
}

const std::vector<std::string> kMetrologyInputs = {"force:x.P", "force:y.P", "force:z.P"};
const std::vector<std::string> kMetrologyOutputs = {"pos:x.P", "pos:y.P", "pos:z.P", "acc:z.P"};

std::vector<std::string> tip_inputs(int n) {
  const std::string t = std::to_string(n);
  return {"force:y." + t, "force:z." + t};
}
std::vector<std::string> tip_outputs(int n) {
  const std::string t = std::to_string(n);
  return {"pos:y." + t, "pos:z." + t, "acc:z." + t};
}

void BM_LineariseMetrology(benchmark::State& state) {
  const model::Model m = model::parse_model(metrology_toml(), "metrology.toml");
  for (auto _ : state) {
    const auto lin = model::linearise(m);
    const auto ss = lti::build_state_space(m, lin, kMetrologyInputs, kMetrologyOutputs);
    benchmark::DoNotOptimize(ss.A.data());
  }
  state.counters["nodes"] = static_cast<double>(m.nodes.size());
  state.counters["elements"] = static_cast<double>(m.elements.size());
  state.counters["DOFs"] = m.nd();
}
BENCHMARK(BM_LineariseMetrology)->Unit(benchmark::kMillisecond)->MinTime(0.5);

void BM_LineariseCantilever(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const model::Model m = model::parse_model(cantilever_toml(n), "cantilever.toml");
  for (auto _ : state) {
    const auto lin = model::linearise(m);
    const auto ss = lti::build_state_space(m, lin, tip_inputs(n), tip_outputs(n));
    benchmark::DoNotOptimize(ss.A.data());
  }
  state.counters["DOFs"] = m.nd();
  state.counters["nx"] = m.nx();
}
BENCHMARK(BM_LineariseCantilever)
    ->Arg(10)
    ->Arg(20)
    ->Arg(40)
    ->Arg(80)
    ->Arg(170)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

// One pass through the phases of linearise (stationary operating point) and the state-space
// build, each timed separately; counters in seconds.
void BM_LinearisePhases(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const model::Model m = model::parse_model(cantilever_toml(n), "cantilever.toml");
  double t_conf = 0, t_jac = 0, t_df = 0, t_dfe = 0, t_forces = 0, t_m = 0, t_k = 0, t_d = 0,
         t_hess = 0, t_g = 0, t_ss = 0;
  for (auto _ : state) {
    flexloop::bench::LapTimer timer;
    auto lap = [&timer](double& acc) { timer.lap(acc); };
    const auto p = model::make_partition(m);
    const auto blocks = model::deformation_blocks(m);
    const Eigen::VectorXd q = model::generalised_from_x(m, p, blocks, m.x_reference);
    const Eigen::VectorXd x = model::solve_configuration(m, p, blocks, q, m.x_reference);
    lap(t_conf);
    const Eigen::MatrixXd J = model::deformation_jacobian(m, blocks, x);
    lap(t_jac);
    const Eigen::MatrixXd DFx = model::geometric_transfer(m, p, J);
    lap(t_df);
    const Eigen::MatrixXd DFe = J * DFx;
    lap(t_dfe);
    Eigen::MatrixXd S, Sd;
    model::global_constitutive(m, S, Sd);
    const Eigen::MatrixXd Mx = model::mass_matrix(m, x);
    const Eigen::VectorXd f = model::applied_forces(m);
    Eigen::VectorXd sigma = S * model::deformations(m, blocks, x);
    // Reaction stresses of the rigid and generalised rows (as in linearise).
    Eigen::MatrixXd Jc(p.g_rows.size(), p.x_dependent.size());
    for (std::size_t i = 0; i < p.g_rows.size(); ++i)
      for (std::size_t j = 0; j < p.x_dependent.size(); ++j)
        Jc(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
            J(p.g_rows[i], p.x_dependent[j]);
    Eigen::VectorXd grad_c(p.x_dependent.size());
    for (std::size_t j = 0; j < p.x_dependent.size(); ++j)
      grad_c(static_cast<Eigen::Index>(j)) = -f(p.x_dependent[j]);
    const Eigen::VectorXd sg = -Jc.transpose().partialPivLu().solve(grad_c);
    for (std::size_t k = 0; k < p.g_rows.size(); ++k)
      sigma(p.g_rows[k]) = sg(static_cast<Eigen::Index>(k));
    lap(t_forces);
    Eigen::MatrixXd Mb = DFx.transpose() * Mx * DFx;
    lap(t_m);
    Eigen::MatrixXd Kb = DFe.transpose() * S * DFe;
    lap(t_k);
    Eigen::MatrixXd Db = DFe.transpose() * Sd * DFe;
    lap(t_d);
    const Eigen::MatrixXd H = model::weighted_deformation_hessian(m, blocks, x, sigma);
    lap(t_hess);
    Eigen::MatrixXd Gb = DFx.transpose() * H * DFx;
    lap(t_g);
    benchmark::DoNotOptimize(Mb.data());
    benchmark::DoNotOptimize(Kb.data());
    benchmark::DoNotOptimize(Db.data());
    benchmark::DoNotOptimize(Gb.data());
    // The state-space build on the real linearisation (not counted in the phases above).
    const auto lin = model::linearise(m);
    timer.restart();
    const auto ss = lti::build_state_space(m, lin, tip_inputs(n), tip_outputs(n));
    lap(t_ss);
    benchmark::DoNotOptimize(ss.A.data());
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["DOFs"] = m.nd();
  state.counters["configuration_s"] = t_conf / it;
  state.counters["jacobian_s"] = t_jac / it;
  state.counters["DFx_s"] = t_df / it;
  state.counters["DFe_JxDFx_s"] = t_dfe / it;
  state.counters["stresses_s"] = t_forces / it;
  state.counters["M_product_s"] = t_m / it;
  state.counters["K_product_s"] = t_k / it;
  state.counters["D_product_s"] = t_d / it;
  state.counters["hessian_s"] = t_hess / it;
  state.counters["G_product_s"] = t_g / it;
  state.counters["state_space_s"] = t_ss / it;
}
BENCHMARK(BM_LinearisePhases)
    ->Arg(10)
    ->Arg(20)
    ->Arg(40)
    ->Arg(80)
    ->Arg(170)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
