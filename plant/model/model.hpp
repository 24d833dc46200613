// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The finite-element multibody model (doc/design.md §3), as read from a model file.
//
// Coordinates. Every node carries its translations (x, y in 2-D; x, y, z in 3-D) and, when it
// is rotational, an angle phi (2-D) or four Euler parameters l0..l3 (3-D). They are stacked in
// node order into the vector x. Labels: "x.<node>", "y.<node>", "z.<node>", "phi.<node>",
// "l0.<node>".."l3.<node>".
//
// Deformations. Each element contributes its deformation parameters (truss 1, planar beam 3,
// spatial beam 6), labelled "e<k>.<element>"; each 3-D rotational node contributes the Euler
// parameter normalisation "euler.<node>" (always rigid). They are stacked into e = D(x).
//
// Partition (set by the model's [coordinates] table):
//   x(o) fixed, x(m) generalised (dynamic or prescribed), x(c) dependent (everything else);
//   e(o) rigid (zero), e(m) generalised, e(c) dependent (flexible or released, not generalised).
// The generalised coordinates q = (q_d dynamic, q_r prescribed), each an x(m) or an e(m).
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "common/source_ref.hpp"
#include "plant/model/element_kinematics.hpp"

namespace flexloop::plant::model {

/// Where something was written in the model file, for error messages.
using common::SourceRef;

enum class ElementType { kTruss, kPlanarBeam, kSpatialBeam };
enum class DeformationKind { kRigid, kFlexible, kReleased };
// Element mass: half at each end; linear interpolation of the translations; or a beam's
// consistent mass with rotary inertia (plant/model/beam_mass.hpp).
enum class MassModel { kLumped, kConsistent, kBeam };
enum class CoordinateRole { kFixed, kDependent, kDynamic, kPrescribed };
// kInert: a rigid deformation whose coordinates are all fixed (e.g. the Euler normalisation of a
// clamped node): identically satisfied, so it is not an equation for the dependent coordinates.
enum class DeformationRole { kRigid, kInert, kDependent, kDynamic, kPrescribed };

struct Node {
  std::string id;
  Eigen::VectorXd position;                    // dim entries, m
  bool rotational = false;                     // carries phi (2-D) or Euler parameters (3-D)
  double phi = 0.0;                            // initial angle (2-D), rad
  Eigen::Vector4d lambda{1.0, 0.0, 0.0, 0.0};  // initial Euler parameters (3-D)
  double mass = 0.0;                           // lumped translational mass, kg
  Eigen::Matrix3d inertia =
      Eigen::Matrix3d::Zero();  // body-frame rotational inertia, kg m^2 (2-D: (2,2))
  Eigen::VectorXd force;        // applied force on the translations (dim), N
  int first_coordinate = 0;     // index of the node's first coordinate in x
  int coordinate_count = 0;
  int euler_deformation = -1;  // index of "euler.<node>" in e (3-D rotational nodes)
  common::SourceRef source;
};

struct Element {
  std::string id;
  ElementType type = ElementType::kTruss;
  std::vector<int> nodes;              // node indices (p, q)
  std::vector<DeformationKind> kinds;  // one per deformation
  std::vector<bool> actuated;          // deformation has an actuator stress input sigma_a
  Eigen::MatrixXd stiffness;           // S (n_e x n_e); rows/cols of non-flexible modes are zero
  Eigen::MatrixXd damping;             // S_d (n_e x n_e)
  double mass = 0.0;                   // kg
  MassModel mass_model = MassModel::kLumped;
  double rho_Iy = 0.0, rho_Iz = 0.0;  // section inertia per length, kg m (planar: rho_Iz = rho I)
  double length = 0.0;                // undeformed length l0, m
  SpatialBeamReference spatial_ref{};
  PlanarBeamReference planar_ref{};
  int first_deformation = 0;  // index of "e1.<id>" in e
  common::SourceRef source;

  int deformation_count() const { return static_cast<int>(kinds.size()); }
};

// A linear FE body given by an FE tool's matrices and reduced by Craig-Bampton
// (plant/superelement, doc/design.md §3a): its interface translations are nodal coordinates of
// the model, its kept fixed-interface modes' amplitudes are generalised coordinates of their own,
// "eta<k>.<id>" (neither nodal nor deformations: the kinematics never see them). Linear: no
// preload, no gravity load, linearised at rest.
struct Superelement {
  std::string id;
  std::vector<int> interface_coordinates;  // x index of each reduced interface row
  Eigen::MatrixXd K, M;                    // reduced: interface rows, then the modes (unit mass)
  Eigen::MatrixXd D;  // damping: zeta on each of the reduced body's own modes (interface free)
  Eigen::VectorXd fixed_interface_hz;    // the kept modes' frequencies, ascending
  std::vector<std::string> mode_labels;  // "eta1.<id>", "eta2.<id>", ...
  double modes_up_to_hz = 0;             // the cut-off asked for
  Eigen::Index full_dofs = 0;            // rows of the FE tool's matrices
  std::vector<std::string> files;        // stiffness, mass, dofs, nodes, as opened
  // What the reduction leaves out: the unkept modes' moments nu_j, scaled by w_c^2 =
  // residual_cut_off_rad2 (plant/superelement/residual_moments.hpp; superelement_residual.hpp).
  std::vector<Eigen::MatrixXd> residual_moments;
  double residual_cut_off_rad2 = 0;
  common::SourceRef source;

  int mode_count() const { return static_cast<int>(mode_labels.size()); }
};

struct Model {
  std::string file;
  std::string name;
  int dim = 3;              // 2 (planar) or 3 (spatial)
  Eigen::VectorXd gravity;  // dim entries, m/s^2
  std::vector<Node> nodes;
  std::vector<Element> elements;
  std::vector<Superelement> superelements;

  std::vector<std::string> coordinate_labels;   // x
  std::vector<std::string> deformation_labels;  // e
  std::vector<CoordinateRole> coordinate_roles;
  std::vector<DeformationRole> deformation_roles;
  std::vector<std::string> generalised;  // q labels, dynamic first, then prescribed
  int dynamic_count = 0;                 // number of q_d
  Eigen::VectorXd x_reference;           // the undeformed configuration
  // The operating point from the [configuration] table: values per generalised coordinate label
  // (q: absolute nodal value or deformation; qd, qdd: rates). Unlisted: reference, zero, zero.
  std::vector<std::pair<std::string, double>> op_q, op_qd, op_qdd;

  int nx() const { return static_cast<int>(coordinate_labels.size()); }
  int ne() const { return static_cast<int>(deformation_labels.size()); }
  int nq() const { return static_cast<int>(generalised.size()); }
  int nd() const { return dynamic_count; }
  int nr() const { return nq() - dynamic_count; }

  int coordinate_index(const std::string& label) const;   // -1 when unknown
  int deformation_index(const std::string& label) const;  // -1 when unknown
};

}  // namespace flexloop::plant::model
