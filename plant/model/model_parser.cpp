// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/model_parser.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/input_error.hpp"
#include "common/toml_reader.hpp"
#include "plant/model/element_properties.hpp"
#include "plant/model/model_from_toml.hpp"
#include "plant/model/superelement_reader.hpp"

namespace flexloop::plant::model {

int Model::coordinate_index(const std::string& label) const {
  auto it = std::find(coordinate_labels.begin(), coordinate_labels.end(), label);
  return it == coordinate_labels.end() ? -1 : static_cast<int>(it - coordinate_labels.begin());
}

int Model::deformation_index(const std::string& label) const {
  auto it = std::find(deformation_labels.begin(), deformation_labels.end(), label);
  return it == deformation_labels.end() ? -1 : static_cast<int>(it - deformation_labels.begin());
}

void mark_inert_deformations(Model& m) {
  // Rigid deformations that involve fixed coordinates only are identities, not equations.
  for (auto& role : m.deformation_roles)
    if (role == DeformationRole::kInert) role = DeformationRole::kRigid;
  auto all_fixed = [&](const Node& n, int first, int count) {
    for (int c = first; c < first + count; ++c)
      if (m.coordinate_roles[n.first_coordinate + c] != CoordinateRole::kFixed) return false;
    return true;
  };
  for (const auto& n : m.nodes)
    if (n.euler_deformation >= 0 && all_fixed(n, 3, 4) &&
        m.deformation_roles[n.euler_deformation] == DeformationRole::kRigid)
      m.deformation_roles[n.euler_deformation] = DeformationRole::kInert;
  for (const auto& el : m.elements) {
    const Node& p = m.nodes[el.nodes[0]];
    const Node& q = m.nodes[el.nodes[1]];
    if (!all_fixed(p, 0, p.coordinate_count) || !all_fixed(q, 0, q.coordinate_count)) continue;
    for (int k = 0; k < el.deformation_count(); ++k)
      if (m.deformation_roles[el.first_deformation + k] == DeformationRole::kRigid)
        m.deformation_roles[el.first_deformation + k] = DeformationRole::kInert;
  }
}

namespace {

DeformationKind parse_kind(const common::TomlReader& r, const std::string& s, const toml::node* n) {
  if (s == "rigid") return DeformationKind::kRigid;
  if (s == "flexible") return DeformationKind::kFlexible;
  if (s == "released") return DeformationKind::kReleased;
  r.fail("deformation mode '" + s + "' is not one of rigid, flexible, released", n);
}

void require_positive(const common::TomlReader& r, const char* key, double v) {
  if (!(v > 0)) r.fail("'" + std::string(key) + "' must be positive", r.get(key));
}

// Keeps only the stiffness/damping of flexible modes (rigid and released carry none from S).
void mask_modes(Element& el) {
  for (int k = 0; k < el.deformation_count(); ++k) {
    if (el.kinds[k] != DeformationKind::kFlexible) {
      el.stiffness.row(k).setZero();
      el.stiffness.col(k).setZero();
    }
    if (el.kinds[k] == DeformationKind::kRigid) {
      el.damping.row(k).setZero();
      el.damping.col(k).setZero();
    }
  }
}

void read_modes_and_damping(const common::TomlReader& r, Element& el, int n) {
  el.kinds.assign(n, DeformationKind::kFlexible);
  if (r.has("modes")) {
    auto modes = r.strings("modes");
    if (static_cast<int>(modes.size()) != n)
      r.fail("'modes' must list " + std::to_string(n) + " modes", r.get("modes"));
    for (int k = 0; k < n; ++k) el.kinds[k] = parse_kind(r, modes[k].first, modes[k].second);
  }
  el.damping = Eigen::MatrixXd::Zero(n, n);
  if (r.has("damping")) el.damping.diagonal() = r.vector("damping", n);
  el.actuated.assign(n, false);
  if (r.has("actuated")) {
    auto* arr = r.get("actuated")->as_array();
    if (!arr || static_cast<int>(arr->size()) != n)
      r.fail("'actuated' must list " + std::to_string(n) + " booleans", r.get("actuated"));
    for (int k = 0; k < n; ++k) {
      auto b = (*arr)[k].value<bool>();
      if (!b) r.fail("'actuated' must list booleans", r.get("actuated"));
      el.actuated[k] = *b;
    }
  }
}

// The readers of a model file's tables, one per table, in the order parse_model runs them (each
// needs what the ones before it read: the elements the nodes, the partition both).

using NodeIndex = std::map<std::string, int>;  // node id -> its index in Model::nodes

// [model]: name, dimension (2 or 3) and gravity.
void read_model_table(const toml::table& root, const common::TomlReader& top, Model& m) {
  const auto* model_tbl = root["model"].as_table();
  if (!model_tbl) top.fail("missing [model] table");
  common::TomlReader mr(*model_tbl, m.file, "[model]");
  mr.allow_only({"name", "dimension", "gravity"});
  m.name = mr.string("name", std::string("unnamed"));
  const double dim = mr.number("dimension", 3.0);
  if (dim != 2.0 && dim != 3.0) mr.fail("'dimension' must be 2 or 3", mr.get("dimension"));
  m.dim = static_cast<int>(dim);
  m.gravity = mr.has("gravity") ? mr.vector("gravity", m.dim) : Eigen::VectorXd::Zero(m.dim);
}

// A node's rotational inertia: 2-D the scalar about z; 3-D [Ixx, Iyy, Izz] or the full tensor
// [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]; positive semi-definite either way.
void read_inertia(const common::TomlReader& r, int dim, Node& n) {
  if (dim == 2) {
    n.inertia(2, 2) = r.number("inertia");
  } else {
    const auto* in = r.get("inertia");
    const auto* arr = in->as_array();
    if (arr && arr->size() == 3) {
      n.inertia.diagonal() = r.vector("inertia", 3);
    } else if (arr && arr->size() == 6) {  // Ixx Iyy Izz Ixy Ixz Iyz
      Eigen::VectorXd v = r.vector("inertia", 6);
      n.inertia << v(0), v(3), v(4), v(3), v(1), v(5), v(4), v(5), v(2);
    } else {
      r.fail("'inertia' must be [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]", in);
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(n.inertia);
  if (es.eigenvalues().minCoeff() < 0)
    r.fail("'inertia' must be positive semi-definite", r.get("inertia"));
}

// One [[node]]: position, orientation (an angle in 2-D, unit Euler parameters in 3-D), mass,
// inertia and applied force.
Node read_node(const common::TomlReader& r, const Model& m, const NodeIndex& node_index) {
  r.allow_only(
      {"id", "position", "rotational", "angle", "orientation", "mass", "inertia", "force"});
  Node n;
  n.id = r.string("id");
  n.source = r.source();
  if (const auto first = node_index.find(n.id); first != node_index.end())
    r.fail("duplicate node id '" + n.id + "' (first at " + m.nodes[first->second].source.str() +
           ")");
  n.position = r.vector("position", m.dim);
  n.rotational =
      r.boolean("rotational", r.has("angle") || r.has("orientation") || r.has("inertia"));
  n.phi = r.number("angle", 0.0);
  if (r.has("orientation")) {
    if (m.dim != 3)
      r.fail("'orientation' (Euler parameters) is for 3-D models; use 'angle' in 2-D",
             r.get("orientation"));
    n.lambda = r.vector("orientation", 4);
    if (std::abs(n.lambda.norm() - 1.0) > 1e-9)
      r.fail("'orientation' Euler parameters must have unit norm", r.get("orientation"));
  }
  n.mass = r.number("mass", 0.0);
  if (n.mass < 0) r.fail("'mass' must not be negative", r.get("mass"));
  if (r.has("inertia")) read_inertia(r, m.dim, n);
  n.force = r.has("force") ? r.vector("force", m.dim) : Eigen::VectorXd::Zero(m.dim);
  return n;
}

// The node's coordinates in x: its translations x, y (, z), then phi (2-D) or l0..l3 (3-D).
void add_node(Model& m, Node n, NodeIndex& node_index) {
  static const char* const axes = "xyz";
  n.first_coordinate = static_cast<int>(m.coordinate_labels.size());
  for (int a = 0; a < m.dim; ++a)
    m.coordinate_labels.push_back(std::string(1, axes[a]) + "." + n.id);
  if (n.rotational) {
    if (m.dim == 2) {
      m.coordinate_labels.push_back("phi." + n.id);
    } else {
      for (int a = 0; a < 4; ++a)
        m.coordinate_labels.push_back("l" + std::to_string(a) + "." + n.id);
    }
  }
  n.coordinate_count = static_cast<int>(m.coordinate_labels.size()) - n.first_coordinate;
  node_index[n.id] = static_cast<int>(m.nodes.size());
  m.nodes.push_back(std::move(n));
}

// [[node]]: the nodes and their coordinates (none is allowed when superelements bring theirs).
NodeIndex read_nodes(const toml::table& root, const common::TomlReader& top, Model& m) {
  NodeIndex node_index;
  const auto* nodes = root["node"].as_array();
  if ((!nodes || nodes->empty()) && !root["superelement"].as_array())
    top.fail("no [[node]] entries (and no [[superelement]])");
  if (!nodes) return node_index;
  for (const auto& item : *nodes) {
    const auto* t = item.as_table();
    if (!t) top.fail("[[node]] entries must be tables", &item);
    add_node(m, read_node(common::TomlReader(*t, m.file, "node"), m, node_index), node_index);
  }
  return node_index;
}

// [[superelement]]: each body's interface nodes become model nodes (their ids unique among all
// nodes) and its reduced interface rows land on their translations.
void read_superelements(const toml::table& root, const common::TomlReader& top, Model& m,
                        NodeIndex& node_index) {
  for (SuperelementTable& table : read_superelement_tables(root, top, m)) {
    std::vector<int> node_of;
    for (Node& n : table.interface_nodes) {
      if (const auto first = node_index.find(n.id); first != node_index.end())
        throw common::InputError(n.source.str(), "superelement '" + table.body.id +
                                                     "': interface node id '" + n.id +
                                                     "' is already a node (" +
                                                     m.nodes[first->second].source.str() + ")");
      node_of.push_back(static_cast<int>(m.nodes.size()));
      add_node(m, std::move(n), node_index);
    }
    for (const auto& [node, axis] : table.interface_rows)
      table.body.interface_coordinates.push_back(m.nodes[node_of[node]].first_coordinate + axis);
    m.superelements.push_back(std::move(table.body));
  }
}

// The reference configuration x_reference: positions, angles and Euler parameters as given.
void reference_configuration(Model& m) {
  m.x_reference.resize(m.nx());
  for (const auto& n : m.nodes) {
    m.x_reference.segment(n.first_coordinate, m.dim) = n.position;
    if (n.rotational) {
      if (m.dim == 2)
        m.x_reference(n.first_coordinate + 2) = n.phi;
      else
        m.x_reference.segment<4>(n.first_coordinate + 3) = n.lambda;
    }
  }
}

// A truss: e1 = |l| - l0 with stiffness k and damping d; flexible when it has either (or an
// actuator), else rigid, unless 'mode' says otherwise.
void read_truss(const common::TomlReader& r, Element& el) {
  r.allow_only(
      {"id", "type", "nodes", "stiffness", "damping", "actuator", "mode", "mass", "mass_model"});
  el.type = ElementType::kTruss;
  el.stiffness = Eigen::MatrixXd::Constant(1, 1, r.number("stiffness", 0.0));
  el.damping = Eigen::MatrixXd::Constant(1, 1, r.number("damping", 0.0));
  if (el.stiffness(0, 0) < 0 || el.damping(0, 0) < 0)
    r.fail("'stiffness' and 'damping' must not be negative");
  const std::string def =
      el.stiffness(0, 0) > 0 || el.damping(0, 0) > 0 || r.boolean("actuator", false) ? "flexible"
                                                                                     : "rigid";
  el.kinds = {parse_kind(r, r.string("mode", def), r.get("mode"))};
  el.actuated = {r.boolean("actuator", false)};
  el.mass = r.number("mass", 0.0);
}

// A planar beam (2-D, rotational nodes): S of E, A, I (element_properties.hpp), mass rho A l0.
void read_planar_beam(const common::TomlReader& r, int dim, const Node& p, const Node& q,
                      Element& el) {
  r.allow_only(
      {"id", "type", "nodes", "E", "A", "I", "rho", "modes", "damping", "actuated", "mass_model"});
  if (dim != 2) r.fail("planar_beam needs a 2-D model (dimension = 2)", r.get("type"));
  if (!p.rotational || !q.rotational)
    r.fail("planar_beam nodes must be rotational (give them 'rotational = true')");
  el.type = ElementType::kPlanarBeam;
  const double E = r.number("E"), A = r.number("A"), I = r.number("I");
  require_positive(r, "E", E), require_positive(r, "A", A), require_positive(r, "I", I);
  read_modes_and_damping(r, el, 3);
  el.stiffness = planar_beam_stiffness(E, A, I, el.length);
  el.mass = r.number("rho", 0.0) * A * el.length;
  el.rho_Iz = r.number("rho", 0.0) * I;
  el.planar_ref = make_planar_beam_reference(p.position, p.phi, q.position, q.phi);
}

// A spatial beam's section. A parameter is required only when a mode that uses it is flexible
// (e1: E A; e2: G J; e3..e6: E Iy, E Iz); the others default to 1 and carry no stiffness.
BeamSection read_beam_section(const common::TomlReader& r, const Element& el) {
  auto flexible = [&](std::initializer_list<int> ks) {
    return std::any_of(ks.begin(), ks.end(),
                       [&](int k) { return el.kinds[k] == DeformationKind::kFlexible; });
  };
  auto param = [&](const char* key, bool needed) {
    return needed ? r.number(key) : r.number(key, 1.0);
  };
  BeamSection s{};
  s.E = param("E", flexible({0, 2, 3, 4, 5}));
  s.A = param("A", flexible({0}));
  s.G = param("G", flexible({1}));
  s.J = param("J", flexible({1}));
  s.Iy = param("Iy", flexible({2, 3, 4, 5}));
  s.Iz = param("Iz", flexible({2, 3, 4, 5}));
  s.rho = r.number("rho", 0.0);
  for (double v : {s.E, s.A, s.G, s.J, s.Iy, s.Iz})
    if (!(v > 0)) r.fail("section properties E, G, A, Iy, Iz, J must be positive");
  return s;
}

// A spatial beam (3-D, rotational nodes): S of its section, mass rho A l0 (with the section's
// rotary inertia rho Iy, rho Iz for mass_model = "beam"), and the section axes from 'y_axis' (any
// axis not parallel to the beam when not given).
void read_spatial_beam(const common::TomlReader& r, int dim, const Node& p, const Node& q,
                       Element& el) {
  r.allow_only({"id", "type", "nodes", "E", "G", "A", "Iy", "Iz", "J", "rho", "modes", "damping",
                "actuated", "y_axis", "mass_model"});
  if (dim != 3) r.fail("beam needs a 3-D model; use planar_beam in 2-D", r.get("type"));
  if (!p.rotational || !q.rotational)
    r.fail("beam nodes must be rotational (give them 'rotational = true')");
  el.type = ElementType::kSpatialBeam;
  read_modes_and_damping(r, el, 6);
  const BeamSection s = read_beam_section(r, el);
  el.stiffness = spatial_beam_stiffness(s, el.length);
  el.mass = s.rho * (r.has("A") ? s.A : 0.0) * el.length;
  if (el.mass_model == MassModel::kBeam) {  // the section's rotation needs its inertia
    if (!r.has("A") || !r.has("Iy") || !r.has("Iz"))
      r.fail("mass_model = \"beam\" needs the section's A, Iy and Iz", r.get("mass_model"));
    el.rho_Iy = s.rho * s.Iy;
    el.rho_Iz = s.rho * s.Iz;
  }
  Eigen::Vector3d hint =
      r.has("y_axis") ? Eigen::Vector3d(r.vector("y_axis", 3)) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d axis = (q.position - p.position).normalized();
  if (!r.has("y_axis")) {  // any axis not parallel to the beam
    hint = std::abs(axis.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
    hint = hint.cross(axis);
  }
  try {
    el.spatial_ref = make_spatial_beam_reference(p.position, p.lambda, q.position, q.lambda, hint);
  } catch (const std::exception& e) {
    r.fail(e.what(), r.get("y_axis"));
  }
}

// What every element has: id, two known nodes at a distance (l0 > 0), a mass model.
void read_element_common(const common::TomlReader& r, const Model& m, const NodeIndex& node_index,
                         const std::string& type, Element& el) {
  const auto node_refs = r.strings("nodes");
  if (node_refs.size() != 2) r.fail("'nodes' must list two node ids", r.get("nodes"));
  for (const auto& [id, n] : node_refs) {
    auto it = node_index.find(id);
    if (it == node_index.end()) r.fail("unknown node '" + id + "'", n);
    el.nodes.push_back(it->second);
  }
  const Node& p = m.nodes[el.nodes[0]];
  const Node& q = m.nodes[el.nodes[1]];
  el.length = (q.position - p.position).norm();
  if (!(el.length > 1e-12))
    r.fail("zero-length element: nodes '" + p.id + "' and '" + q.id + "' coincide");
  const std::string mass_model = r.string("mass_model", std::string("lumped"));
  if (mass_model != "lumped" && mass_model != "consistent" && mass_model != "beam")
    r.fail("'mass_model' must be lumped, consistent or beam", r.get("mass_model"));
  el.mass_model = mass_model == "beam"         ? MassModel::kBeam
                  : mass_model == "consistent" ? MassModel::kConsistent
                                               : MassModel::kLumped;
  if (el.mass_model == MassModel::kBeam && type == "truss")
    r.fail("mass_model = \"beam\" is the mass of a beam element; a truss has lumped or consistent",
           r.get("mass_model"));
}

// One [[element]]: what every element has, then what its type reads.
Element read_element(const common::TomlReader& r, const Model& m, const NodeIndex& node_index,
                     std::set<std::string>& element_ids) {
  Element el;
  el.id = r.string("id");
  el.source = r.source();
  if (!element_ids.insert(el.id).second)
    r.fail("duplicate element id '" + el.id + "'", r.get("id"));
  const std::string type = r.string("type");
  read_element_common(r, m, node_index, type, el);
  const Node& p = m.nodes[el.nodes[0]];
  const Node& q = m.nodes[el.nodes[1]];
  if (type == "truss")
    read_truss(r, el);
  else if (type == "planar_beam")
    read_planar_beam(r, m.dim, p, q, el);
  else if (type == "beam")
    read_spatial_beam(r, m.dim, p, q, el);
  else
    r.fail("unknown element type '" + type + "' (truss, planar_beam or beam)", r.get("type"));
  if (el.mass < 0) r.fail("'mass' must not be negative", r.get("mass"));
  mask_modes(el);
  return el;
}

// [[element]] (optional): the elements and their deformations e1.<id>, e2.<id>, ... in e; then
// the always-rigid euler.<node> of each 3-D rotational node (lambda . lambda - 1).
void read_elements(const toml::table& root, const common::TomlReader& top, Model& m,
                   const NodeIndex& node_index) {
  std::set<std::string> element_ids;
  if (const auto* elements = root["element"].as_array()) {
    for (const auto& item : *elements) {
      const auto* t = item.as_table();
      if (!t) top.fail("[[element]] entries must be tables", &item);
      Element el =
          read_element(common::TomlReader(*t, m.file, "element"), m, node_index, element_ids);
      el.first_deformation = static_cast<int>(m.deformation_labels.size());
      for (int k = 0; k < el.deformation_count(); ++k)
        m.deformation_labels.push_back("e" + std::to_string(k + 1) + "." + el.id);
      m.elements.push_back(std::move(el));
    }
  }
  for (auto& n : m.nodes) {
    if (m.dim == 3 && n.rotational) {
      n.euler_deformation = static_cast<int>(m.deformation_labels.size());
      m.deformation_labels.push_back("euler." + n.id);
    }
  }
}

// The partition before [coordinates]: every nodal coordinate dependent, every deformation
// dependent but the rigid modes and the Euler constraints.
void initial_roles(Model& m) {
  m.coordinate_roles.assign(m.nx(), CoordinateRole::kDependent);
  m.deformation_roles.assign(m.ne(), DeformationRole::kDependent);
  for (const auto& el : m.elements)
    for (int k = 0; k < el.deformation_count(); ++k)
      if (el.kinds[k] == DeformationKind::kRigid)
        m.deformation_roles[el.first_deformation + k] = DeformationRole::kRigid;
  for (const auto& n : m.nodes)
    if (n.euler_deformation >= 0)
      m.deformation_roles[n.euler_deformation] = DeformationRole::kRigid;
}

// Each coordinate is listed once in [coordinates].
struct Claims {
  const common::TomlReader& cr;
  std::set<std::string> assigned;
  void operator()(const std::string& label, const toml::node* n) {
    if (!assigned.insert(label).second) cr.fail("'" + label + "' is listed twice", n);
  }
};

// [coordinates] fixed_nodes and fixed: the coordinates x(o) held at their reference.
void read_fixed(const common::TomlReader& cr, Model& m, const NodeIndex& node_index,
                Claims& claim) {
  for (const auto& [id, n] : cr.strings("fixed_nodes")) {
    auto it = node_index.find(id);
    if (it == node_index.end()) cr.fail("unknown node '" + id + "'", n);
    const Node& node = m.nodes[it->second];
    for (int i = 0; i < node.coordinate_count; ++i) {
      claim(m.coordinate_labels[node.first_coordinate + i], n);
      m.coordinate_roles[node.first_coordinate + i] = CoordinateRole::kFixed;
    }
  }
  for (const auto& [label, n] : cr.strings("fixed")) {
    const int i = m.coordinate_index(label);
    if (i < 0)
      cr.fail("unknown coordinate '" + label +
                  "' (coordinates are x.<node>, y.<node>, z.<node>, phi.<node>, l0..l3.<node>)",
              n);
    claim(label, n);
    m.coordinate_roles[i] = CoordinateRole::kFixed;
  }
}

// What a superelement brings unless [coordinates] lists it: its interface translations dynamic
// (those the FE tool holds, fixed), a pad node's l1..l3 dynamic (its l0 dependent, from
// euler.<pad>), then its modal amplitudes, always dynamic.
void superelement_defaults(Model& m, const std::set<std::string>& listed) {
  for (const auto& body : m.superelements) {
    const std::set<int> carried(body.interface_coordinates.begin(),
                                body.interface_coordinates.end());
    for (const Node& n : m.nodes) {
      const int first = n.first_coordinate;
      if (!std::any_of(carried.begin(), carried.end(),
                       [&](int c) { return c >= first && c < first + m.dim; }))
        continue;
      for (int i = first; i < first + n.coordinate_count; ++i) {
        const bool rotation = i >= first + m.dim;
        if (listed.count(m.coordinate_labels[i]) || (rotation && !carried.count(i))) continue;
        m.coordinate_roles[i] =
            carried.count(i) ? CoordinateRole::kDynamic : CoordinateRole::kFixed;
        if (carried.count(i)) m.generalised.push_back(m.coordinate_labels[i]);
      }
    }
    m.generalised.insert(m.generalised.end(), body.mode_labels.begin(), body.mode_labels.end());
  }
}

// [coordinates] dynamic and prescribed: the generalised coordinates q = (q_d, q_r), each a nodal
// coordinate x(m) or a flexible or released deformation e(m).
void read_generalised(const common::TomlReader& cr, Model& m, Claims& claim) {
  std::vector<std::string> prescribed;
  for (const char* key : {"dynamic", "prescribed"}) {
    const bool dynamic = std::string(key) == "dynamic";
    for (const auto& [label, n] : cr.strings(key)) {
      claim(label, n);
      if (const int i = m.coordinate_index(label); i >= 0) {
        m.coordinate_roles[i] = dynamic ? CoordinateRole::kDynamic : CoordinateRole::kPrescribed;
      } else if (const int k = m.deformation_index(label); k >= 0) {
        if (m.deformation_roles[k] == DeformationRole::kRigid)
          cr.fail("'" + label +
                      "' is a rigid deformation (always zero); declare the mode flexible or "
                      "released to use it as a coordinate",
                  n);
        m.deformation_roles[k] = dynamic ? DeformationRole::kDynamic : DeformationRole::kPrescribed;
      } else {
        cr.fail("unknown coordinate or deformation '" + label + "'", n);
      }
      (dynamic ? m.generalised : prescribed).push_back(label);
    }
  }
  superelement_defaults(m, claim.assigned);
  m.dynamic_count = static_cast<int>(m.generalised.size());
  m.generalised.insert(m.generalised.end(), prescribed.begin(), prescribed.end());
  if (m.dynamic_count == 0) cr.fail("no dynamic coordinates: list at least one in 'dynamic'");
}

// [coordinates]: the partition x = (x(o) fixed, x(c) dependent, x(m) generalised), each
// coordinate listed once.
void read_coordinates(const toml::table& root, const common::TomlReader& top, Model& m,
                      const NodeIndex& node_index) {
  static const toml::table none;  // a model of superelements alone may leave the table out
  const auto* coords = root["coordinates"].as_table();
  if (!coords && m.superelements.empty())
    top.fail("missing [coordinates] table (which coordinates are fixed, dynamic, prescribed)");
  common::TomlReader cr(coords ? *coords : none, m.file, "[coordinates]");
  cr.allow_only({"fixed", "fixed_nodes", "dynamic", "prescribed"});
  Claims claim{cr, {}};
  read_fixed(cr, m, node_index, claim);
  read_generalised(cr, m, claim);
}

// [configuration] (optional): the operating point, { label = value } tables for q, qd, qdd.
void read_configuration(const toml::table& root, Model& m) {
  const auto* cfg = root["configuration"].as_table();
  if (!cfg) return;
  common::TomlReader fr(*cfg, m.file, "[configuration]");
  fr.allow_only({"q", "qd", "qdd"});
  for (const auto& [key, out] :
       {std::pair{"q", &m.op_q}, std::pair{"qd", &m.op_qd}, std::pair{"qdd", &m.op_qdd}}) {
    const auto* n = fr.get(key);
    if (!n) continue;
    const auto* t = n->as_table();
    if (!t)
      fr.fail("'" + std::string(key) + "' must be a table of generalised coordinate = value", n);
    for (const auto& [label, value] : *t) {
      const std::string l(label.str());
      if (std::find(m.generalised.begin(), m.generalised.end(), l) == m.generalised.end())
        fr.fail("'" + l + "' is not a generalised coordinate (dynamic or prescribed)", &value);
      const auto v = value.value<double>();
      if (!v || !std::isfinite(*v)) fr.fail("'" + l + "' must be a finite number", &value);
      out->emplace_back(l, *v);
    }
  }
}

// The dependent coordinates x(c) are solved from [D_o(x); D_m(x)] = [0; e_m(q)]: as many rigid
// and generalised deformations as dependent coordinates. Reported at [coordinates], where the
// fix goes.
void check_dependent_count(const toml::table& root, const Model& m) {
  int n_dependent = 0, n_equations = 0;
  for (auto r : m.coordinate_roles) n_dependent += r == CoordinateRole::kDependent;
  for (auto r : m.deformation_roles)
    n_equations += r == DeformationRole::kRigid || r == DeformationRole::kDynamic ||
                   r == DeformationRole::kPrescribed;
  if (n_dependent == n_equations) return;
  std::ostringstream os;
  os << n_dependent << " dependent nodal coordinates but " << n_equations
     << " rigid or generalised deformations determine them; "
     << (n_dependent > n_equations ? "the mechanism has free coordinates: fix them, make them "
                                     "generalised, or make more deformations rigid"
                                   : "it is over-constrained: release or free some rigid "
                                     "deformations, or make fewer deformations generalised");
  static const toml::table none;
  const auto* coords = root["coordinates"].as_table();
  common::TomlReader(coords ? *coords : none, m.file, "[coordinates]").fail(os.str());
}

}  // namespace

Model parse_model(const std::string& text, const std::string& file) {
  return model_from_toml(common::parse_toml(text, file), file);
}

Model model_from_toml(const toml::table& root, const std::string& file) {
  common::TomlReader top(root, file, "model file");
  top.allow_only({"model", "node", "superelement", "element", "coordinates", "configuration"});
  Model m;
  m.file = file;
  read_model_table(root, top, m);
  NodeIndex node_index = read_nodes(root, top, m);
  read_superelements(root, top, m, node_index);
  reference_configuration(m);
  read_elements(root, top, m, node_index);
  initial_roles(m);
  read_coordinates(root, top, m, node_index);
  mark_inert_deformations(m);
  read_configuration(root, m);
  check_dependent_count(root, m);
  return m;
}

Model load_model(const std::string& path) {
  return parse_model(common::read_input_file(path, "model file"), path);
}

}  // namespace flexloop::plant::model
