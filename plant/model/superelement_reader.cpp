// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/superelement_reader.hpp"

#include <algorithm>
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

// interface = { name = mesh node number, ... }: the flexloop node ids and their mesh nodes (the
// table may be left out when the body has pads).
std::map<std::string, long> read_interface(const common::TomlReader& r, bool has_pads) {
  const auto* n = r.get("interface");
  if (!n && has_pads) return {};
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

// A pad's nodes = [...]: mesh node numbers, each once.
std::vector<long> read_pad_nodes(const common::TomlReader& p) {
  const auto* n = p.get("nodes");
  const auto* arr = n->as_array();
  if (!arr || arr->empty()) p.fail("'nodes' must be an array of mesh node numbers", n);
  std::vector<long> out;
  std::set<long> seen;
  for (const auto& item : *arr) {
    const auto number = item.value<int64_t>();
    if (!number || *number < 1) p.fail("'nodes' entries must be mesh node numbers (>= 1)", &item);
    if (!seen.insert(*number).second)
      p.fail("mesh node " + std::to_string(*number) + " is listed twice in 'nodes'", &item);
    out.push_back(static_cast<long>(*number));
  }
  return out;
}

// One [[superelement.pad]]: kind, and nodes = [...] or within = { center, radius }.
se::PadRequest read_pad(const common::TomlReader& p, const std::string& file) {
  p.allow_only({"id", "nodes", "within", "kind"});
  se::PadRequest pad;
  const std::string kind = p.string("kind");
  if (kind != "rigid" && kind != "distributing")
    p.fail("unknown kind '" + kind +
               "': \"rigid\" (RBE2: the pad's nodes move as one rigid body with the pad node) or "
               "\"distributing\" (RBE3: the pad node moves with their mean)",
           p.get("kind"));
  pad.kind = kind == "rigid" ? se::PadKind::kRigid : se::PadKind::kDistributing;
  if (p.has("nodes") == p.has("within"))
    p.fail(
        "give either 'nodes' = [mesh node numbers] or 'within' = { center = [x, y, z], radius "
        "= r }");
  if (p.has("nodes")) {
    pad.nodes = read_pad_nodes(p);
    return pad;
  }
  const auto* table = p.get("within")->as_table();
  if (!table)
    p.fail("'within' must be a table { center = [x, y, z], radius = r }", p.get("within"));
  const common::TomlReader w(*table, file, "superelement.pad within");
  w.allow_only({"center", "radius"});
  pad.within = true;
  pad.ball.center = w.vector("center", 3);
  pad.ball.radius = w.number("radius");
  if (!(pad.ball.radius > 0)) w.fail("'radius' must be above 0 (m)", w.get("radius"));
  return pad;
}

struct PadTables {
  std::vector<std::string> ids;
  std::vector<se::PadRequest> requests;
  std::vector<common::TomlReader> readers;  // for errors found in the FE files
};

// [[superelement.pad]] entries: each id a new flexloop node (not an interface id, not twice).
PadTables read_pads(const common::TomlReader& r, const std::string& file,
                    const std::map<std::string, long>& interface) {
  PadTables out;
  const auto* n = r.get("pad");
  if (!n) return out;
  const auto* arr = n->as_array();
  if (!arr) r.fail("'pad' must be an array of tables: write [[superelement.pad]] entries", n);
  for (const auto& item : *arr) {
    const auto* t = item.as_table();
    if (!t) r.fail("[[superelement.pad]] entries must be tables", &item);
    const common::TomlReader p(*t, file, "superelement.pad");
    const std::string id = p.string("id");
    if (interface.count(id))
      p.fail("pad id '" + id + "' is also an 'interface' node id", p.get("id"));
    if (std::find(out.ids.begin(), out.ids.end(), id) != out.ids.end())
      p.fail("pad id '" + id + "' is given twice", p.get("id"));
    out.requests.push_back(read_pad(p, file));
    out.ids.push_back(id);
    out.readers.push_back(p);
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
                     const se::CraigBampton& reduction, double cut_off_hz) {
  Superelement b;
  b.id = id;
  b.source = r.source();
  b.K = reduction.K;
  b.M = reduction.M;
  b.fixed_interface_hz = reduction.fixed_interface_hz;
  b.modes_up_to_hz = cut_off_hz;
  b.residual_moments = reduction.residual.scaled;
  b.residual_cut_off_rad2 = reduction.residual.cut_off_rad2;
  const double zeta = r.number("damping_ratio", 0.0);
  if (!(zeta >= 0 && zeta < 1)) r.fail("'damping_ratio' must be in [0, 1)", r.get("damping_ratio"));
  b.D = modal_damping(b.K, b.M, zeta);
  for (Eigen::Index k = 0; k < b.fixed_interface_hz.size(); ++k)
    b.mode_labels.push_back("eta" + std::to_string(k + 1) + "." + id);
  return b;
}

// The reduced interface's rotation rows (rad) onto the pad nodes' Euler parameters l1..l3: at
// the pad node's reference orientation (1, 0, 0, 0), theta = 2 (l1, l2, l3) to first order
// (rotation.hpp: R = I + 2 [l]x), so u = S u_l with S = 2 on those rows, K_l = S K S, M_l = S M S.
void rotations_as_euler_parameters(Eigen::Index first_pad_row, std::size_t pads,
                                   se::CraigBampton& reduced) {
  Eigen::VectorXd s = Eigen::VectorXd::Ones(reduced.K.rows());
  for (std::size_t k = 0; k < pads; ++k)
    s.segment<3>(first_pad_row + 6 * static_cast<Eigen::Index>(k) + 3).setConstant(2.0);
  reduced.K = s.asDiagonal() * reduced.K * s.asDiagonal();
  reduced.M = s.asDiagonal() * reduced.M * s.asDiagonal();
  // The unkept modes' moments live on the interface rows too (residual_moments.hpp).
  for (Eigen::MatrixXd& nu : reduced.residual.scaled) {
    const Eigen::VectorXd sb = s.head(nu.rows());
    nu = sb.asDiagonal() * nu * sb.asDiagonal();
  }
}

// The reduction, its errors placed at the model file's entry (a pad's own, for a pad's).
std::shared_ptr<const se::ReducedSuperelement> reduced_body(const common::TomlReader& r,
                                                            const se::SuperelementFiles& files,
                                                            const PadTables& pads) {
  std::shared_ptr<const se::ReducedSuperelement> reduced;
  try {
    reduced = se::reduce_superelement(files);
  } catch (const se::PadError& e) {
    pads.readers[e.pad()].fail(e.what());
  } catch (const std::domain_error& e) {
    r.fail(std::string(e.what()) + " (stiffness " + files.stiffness + ", mass " + files.mass + ")");
  }
  if (reduced->reduction.fixed_interface_hz.size() == 0)
    r.fail("modes_up_to_hz = " + number_text(files.modes_up_to_hz) +
               " keeps no fixed-interface mode: raise it above the body's first mode with its "
               "interface held",
           r.get("modes_up_to_hz"));
  return reduced;
}

// The interface as model nodes: a pin per interface node (x, y, z), then a rotational node per
// pad at its centroid (x, y, z and l1..l3: offsets 4..6 after l0), and each reduced row's place.
void add_interface_nodes(const common::TomlReader& r, const std::map<std::string, long>& interface,
                         const PadTables& pads, const se::ReducedSuperelement& reduced,
                         SuperelementTable& out) {
  std::map<long, int> index_of;
  auto add = [&](const std::string& name, bool rotational) {
    Node n;
    n.id = name;
    n.source = r.source();
    n.rotational = rotational;
    n.position = reduced.positions[out.interface_nodes.size()];
    n.force = Eigen::VectorXd::Zero(3);
    out.interface_nodes.push_back(std::move(n));
  };
  for (const auto& [name, node] : interface) {
    index_of[node] = static_cast<int>(out.interface_nodes.size());
    add(name, false);
  }
  for (const auto& dof : reduced.interface_dofs)
    out.interface_rows.emplace_back(index_of.at(dof.node), dof.direction - 1);
  for (std::size_t k = 0; k < pads.ids.size(); ++k) {
    const int node = static_cast<int>(out.interface_nodes.size());
    add(pads.ids[k], true);
    out.interface_nodes.back().source = pads.readers[k].source();
    for (const int offset : {0, 1, 2, 4, 5, 6}) out.interface_rows.emplace_back(node, offset);
  }
}

SuperelementTable read_table(const common::TomlReader& r, const Model& m) {
  r.allow_only({"id", "format", "stiffness", "mass", "damping", "dofs", "nodes", "modes_up_to_hz",
                "damping_ratio", "interface", "pad"});
  if (m.dim != 3) r.fail("a superelement is a 3-D body: give the model dimension = 3");
  if (r.has("damping"))
    r.fail("a damping matrix is not read: give the kept modes' 'damping_ratio' instead",
           r.get("damping"));
  const std::string id = r.string("id");
  const std::map<std::string, long> interface = read_interface(r, r.has("pad"));
  const PadTables pads = read_pads(r, m.file, interface);
  se::SuperelementFiles files = read_files(r, m, interface);
  files.pads = pads.requests;
  const auto reduced = reduced_body(r, files, pads);
  se::CraigBampton reduction = reduced->reduction;
  rotations_as_euler_parameters(static_cast<Eigen::Index>(reduced->interface_dofs.size()),
                                pads.ids.size(), reduction);
  SuperelementTable out{body_of(r, id, reduction, files.modes_up_to_hz), {}, {}};
  out.body.files = {files.stiffness, files.mass, files.dofs, files.nodes};
  out.body.full_dofs = reduced->full_dofs;
  add_interface_nodes(r, interface, pads, *reduced, out);
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
