// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/superelement_reader.hpp"

#include <atomic>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"
#include "numeric/constants.hpp"
#include "plant/superelement/superelement_files.hpp"

namespace flexloop::plant::model {

namespace {

namespace se = plant::superelement;

std::atomic<double> reduction_error_band_hz{0.0};

std::string number_text(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// A path in the model file, relative to the model file's folder.
std::string beside_model(const Model& m, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  return (std::filesystem::path(m.file).parent_path() / p).string();
}

// interface = { name = mesh node number, ... }: the flexloop node ids and their mesh nodes.
std::map<std::string, long> read_interface(const common::TomlReader& r) {
  const auto* n = r.get("interface");
  const auto* t = n ? n->as_table() : nullptr;
  if (!t || t->empty())
    r.fail("'interface' must be a table { node id = mesh node number, ... } with one entry or more",
           n);
  std::map<std::string, long> out;
  std::set<long> seen;
  for (const auto& [key, value] : *t) {
    const auto number = value.value<int64_t>();
    if (!number || *number < 1)
      r.fail("interface node '" + std::string(key.str()) + "' must be a mesh node number (>= 1)",
             &value);
    if (!seen.insert(*number).second)
      r.fail("mesh node " + std::to_string(*number) + " is named twice in 'interface'", &value);
    out[std::string(key.str())] = static_cast<long>(*number);
  }
  return out;
}

se::SuperelementFiles read_files(const common::TomlReader& r, const Model& m,
                                 const std::map<std::string, long>& interface) {
  se::SuperelementFiles f;
  const std::string format = r.string("format");
  if (format != "calculix" && format != "matrix_market")
    r.fail("'format' must be \"calculix\" or \"matrix_market\"", r.get("format"));
  f.format = format == "calculix" ? se::FileFormat::kCalculix : se::FileFormat::kMatrixMarket;
  f.stiffness = beside_model(m, r.string("stiffness"));
  f.mass = beside_model(m, r.string("mass"));
  f.dofs = beside_model(m, r.string("dofs"));
  f.nodes = beside_model(m, r.string("nodes"));
  f.modes_up_to_hz = r.number("modes_up_to_hz");
  if (!(f.modes_up_to_hz > 0)) r.fail("'modes_up_to_hz' must be above 0", r.get("modes_up_to_hz"));
  for (const auto& [name, node] : interface) f.interface_nodes.push_back(node);
  f.residual_block_solves = se::residual_block_solves(reduction_error_band_hz, f.modes_up_to_hz);
  return f;
}

// D = M Phi diag(2 zeta w_j) Phi' M over the reduced body's own modes (K Phi = M Phi W^2,
// Phi' M Phi = I): every mode of the body, interface motion included, gets the ratio zeta (damping
// on the fixed-interface amplitudes alone would leave the modes the interface carries undamped);
// rigid-body modes (w = 0) get none.
Eigen::MatrixXd modal_damping(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, double zeta) {
  if (zeta == 0) return Eigen::MatrixXd::Zero(K.rows(), K.cols());
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(K, M);  // small, dense
  const Eigen::VectorXd w = modes.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  const Eigen::MatrixXd m_phi = M * modes.eigenvectors();
  const Eigen::MatrixXd D = m_phi * (2.0 * zeta * w).asDiagonal() * m_phi.transpose();
  return 0.5 * (D + D.transpose());
}

// The reduced body as the model holds it (its coordinates placed later by the model reader).
Superelement body_of(const common::TomlReader& r, const std::string& id,
                     const se::ReducedSuperelement& reduced, double cut_off_hz) {
  Superelement b;
  b.id = id;
  b.source = r.source();
  b.K = reduced.reduction.K;
  b.M = reduced.reduction.M;
  b.fixed_interface_hz = reduced.reduction.fixed_interface_hz;
  b.modes_up_to_hz = cut_off_hz;
  b.full_dofs = reduced.full_dofs;
  b.residual_moments = reduced.reduction.residual.scaled;
  b.residual_cut_off_rad2 = reduced.reduction.residual.cut_off_rad2;
  const double zeta = r.number("damping_ratio", 0.0);
  if (!(zeta >= 0 && zeta < 1)) r.fail("'damping_ratio' must be in [0, 1)", r.get("damping_ratio"));
  b.D = modal_damping(b.K, b.M, zeta);
  for (Eigen::Index k = 0; k < b.fixed_interface_hz.size(); ++k)
    b.mode_labels.push_back("eta" + std::to_string(k + 1) + "." + id);
  return b;
}

SuperelementTable read_table(const common::TomlReader& r, const Model& m) {
  r.allow_only({"id", "format", "stiffness", "mass", "damping", "dofs", "nodes", "modes_up_to_hz",
                "damping_ratio", "interface"});
  if (m.dim != 3) r.fail("a superelement is a 3-D body: give the model dimension = 3");
  if (r.has("damping"))
    r.fail("a damping matrix is not read: give the kept modes' 'damping_ratio' instead",
           r.get("damping"));
  const std::string id = r.string("id");
  const std::map<std::string, long> interface = read_interface(r);
  const se::SuperelementFiles files = read_files(r, m, interface);
  std::shared_ptr<const se::ReducedSuperelement> reduced;
  try {
    reduced = se::reduce_superelement(files);
  } catch (const std::domain_error& e) {
    r.fail(std::string(e.what()) + " (stiffness " + files.stiffness + ", mass " + files.mass + ")");
  }
  if (reduced->reduction.fixed_interface_hz.size() == 0)
    r.fail("modes_up_to_hz = " + number_text(files.modes_up_to_hz) +
               " keeps no fixed-interface mode: raise it above the body's first mode with its "
               "interface held",
           r.get("modes_up_to_hz"));
  SuperelementTable out{body_of(r, id, *reduced, files.modes_up_to_hz), {}, {}};
  out.body.files = {files.stiffness, files.mass, files.dofs, files.nodes};
  std::map<long, int> index_of;
  for (const auto& [name, node] : interface) {
    Node n;
    n.id = name;
    n.source = r.source();
    n.position = reduced->positions[out.interface_nodes.size()];
    n.force = Eigen::VectorXd::Zero(3);
    index_of[node] = static_cast<int>(out.interface_nodes.size());
    out.interface_nodes.push_back(std::move(n));
  }
  for (const auto& dof : reduced->interface_dofs)
    out.interface_rows.emplace_back(index_of.at(dof.node), dof.direction - 1);
  return out;
}

}  // namespace

double set_reduction_error_band_hz(double band_hz) {
  return reduction_error_band_hz.exchange(band_hz);
}

std::vector<SuperelementTable> read_superelement_tables(const toml::table& root,
                                                        const common::TomlReader& top,
                                                        const Model& m) {
  std::vector<SuperelementTable> out;
  const auto* tables = root["superelement"].as_array();
  if (!tables) return out;
  std::set<std::string> ids;
  for (const auto& item : *tables) {
    const auto* t = item.as_table();
    if (!t) top.fail("[[superelement]] entries must be tables", &item);
    const common::TomlReader r(*t, m.file, "superelement");
    out.push_back(read_table(r, m));
    if (!ids.insert(out.back().body.id).second)
      r.fail("duplicate superelement id '" + out.back().body.id + "'", r.get("id"));
  }
  return out;
}

}  // namespace flexloop::plant::model
