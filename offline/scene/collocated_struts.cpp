// SPDX-License-Identifier: BSD-3-Clause
#include "offline/scene/collocated_struts.hpp"

#include <cmath>
#include <cstddef>
#include <string>

#include "common/input_error.hpp"
#include "common/toml_reader.hpp"
#include "numeric/constants.hpp"
#include "plant/lti/state_space_builder.hpp"

namespace flexloop::scene {

namespace {

constexpr const char* kStressPrefix = "stress:";

// "file:line" of entry `index` of [plant] `key` in the scene file (of the key, or the file alone,
// when the entry or the file cannot be found again, e.g. a scene parsed from text).
std::string plant_entry_place(const Scene& sc, const char* key, std::size_t index) {
  try {
    const toml::table root =
        common::parse_toml(common::read_input_file(sc.file, "scene file"), sc.file);
    const auto* plant = root.get("plant");
    if (!plant || !plant->as_table()) return sc.file;
    const common::TomlReader r(*plant->as_table(), sc.file, "[plant]");
    const auto entries = r.strings(key);
    return index < entries.size() ? r.place(entries[index].second) : r.place(r.get(key));
  } catch (const std::exception&) {
    return sc.file;
  }
}

// Refuses entry i of [plant] `key` (channel: its name), at its line.
[[noreturn]] void refuse_entry(const Scene& sc, const char* key, std::size_t i,
                               const std::string& channel, const std::string& what) {
  throw common::InputError(plant_entry_place(sc, key, i), "[plant]: " + std::string(key) +
                                                              " entry " + std::to_string(i + 1) +
                                                              " '" + channel + "': " + what);
}

bool is_stress(const std::string& channel) {
  return channel.rfind(kStressPrefix, 0) == 0;
}

std::string deformation_of(const std::string& channel) {
  return channel.substr(std::char_traits<char>::length(kStressPrefix));
}

// 1/m_i over the machine's modes up to ten times omega_d, where the loop acts: sum_j (phi_j' b_i)^2
// with phi_j mass-normalised and b_i the strut's generalised force. Above them a flexible body's
// modes add the local mass of the strut's attachment (a superelement's mesh node: grams), which
// b_i' Mdd^-1 b_i counts in full and which would tune the loop to a gain of 10^4. A machine whose
// every mode lies below (a rigid payload) keeps b_i' Mdd^-1 b_i, to the bit.
void suspension_inverse_mass(const plant::model::Model& m, const plant::model::Linearisation& lin,
                             const Scene& scene, Eigen::VectorXd& inverse_mass) {
  const int nd = m.nd();
  const Eigen::MatrixXd Mdd = lin.M.topLeftCorner(nd, nd);
  const Eigen::MatrixXd Kdd = (lin.K + lin.G + lin.N).topLeftCorner(nd, nd);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(
      0.5 * (Kdd + Kdd.transpose()), Mdd);
  if (modes.info() != Eigen::Success) return;  // massless directions: the full count stands
  const double limit = std::pow(10.0 * numeric::kTwoPi * scene.controller.omega_d_hz, 2);
  const Eigen::VectorXd& lambda = modes.eigenvalues();
  if (lambda.maxCoeff() <= limit) return;
  for (std::size_t i = 0; i < scene.actuators.size(); ++i) {
    const int k = m.deformation_index(deformation_of(scene.actuators[i]));
    const Eigen::VectorXd b = lin.DFe.row(k).head(nd).transpose();
    double sum = 0;
    for (Eigen::Index j = 0; j < lambda.size() && lambda(j) <= limit; ++j)
      sum += std::pow(modes.eigenvectors().col(j).dot(b), 2);
    inverse_mass(static_cast<Eigen::Index>(i)) = sum;
  }
}

}  // namespace

bool struts_are_the_coordinates(const Scene& scene, const plant::model::Model& m) {
  if (static_cast<int>(scene.actuators.size()) != m.nd()) return false;
  for (std::size_t i = 0; i < scene.actuators.size(); ++i)
    if (scene.actuators[i] != kStressPrefix + m.generalised[i]) return false;
  return true;
}

void require_collocated_pairs(const Scene& scene, const plant::model::Model& m) {
  for (std::size_t i = 0; i < scene.actuators.size(); ++i) {
    const std::string& a = scene.actuators[i];
    if (!is_stress(a) || m.deformation_index(deformation_of(a)) < 0)
      refuse_entry(scene, "actuators", i, a,
                   "PI force feedback drives strut stresses (stress:<deformation>), each with its "
                   "own force sensor; a state_space controller takes any actuator");
    if (i >= scene.sensors.size() || scene.sensors[i] != a)
      refuse_entry(scene, "sensors", i, i < scene.sensors.size() ? scene.sensors[i] : "",
                   "not the force sensor of actuators entry " + std::to_string(i + 1) +
                       "'s strut: integral force feedback closes each strut's loop on its own "
                       "force sensor, so this entry must be '" +
                       a + "' (or use a state_space controller)");
  }
}

std::vector<controller::design::CollocatedStrut> collocated_struts(
    const Scene& scene, const plant::model::Model& m, const plant::model::Linearisation& lin) {
  require_collocated_pairs(scene, m);
  std::vector<std::string> elongations;
  for (const auto& a : scene.actuators) elongations.push_back("pos:" + deformation_of(a));
  // e_i(s) / sigma_a_i(s) = C (sI - A)^-1 B + D = ... + (C A B) / s^2 + ...: C B = 0 (an
  // elongation is a position), so -(C A B)_ii = b_i^T Mdd^-1 b_i exactly, damping or not.
  const auto path = plant::lti::build_state_space(m, lin, scene.actuators, elongations);
  Eigen::VectorXd inverse_mass = -(path.C * (path.A * path.B)).diagonal();
  suspension_inverse_mass(m, lin, scene, inverse_mass);
  std::vector<controller::design::CollocatedStrut> struts;
  for (std::size_t i = 0; i < scene.actuators.size(); ++i) {
    const int k = m.deformation_index(deformation_of(scene.actuators[i]));
    const controller::design::CollocatedStrut c{lin.S(k, k),
                                                inverse_mass(static_cast<Eigen::Index>(i))};
    if (!(std::isfinite(c.stiffness) && c.stiffness > 0))
      refuse_entry(scene, "actuators", i, scene.actuators[i],
                   "the strut has no axial stiffness (a released deformation): integral force "
                   "feedback needs a strut whose force sensor reads its elongation");
    if (!(std::isfinite(c.inverse_mass) && c.inverse_mass > 0))
      refuse_entry(
          scene, "actuators", i, scene.actuators[i],
          "the strut's force accelerates no mass (1/m = " + std::to_string(c.inverse_mass) +
              "): its loop has nothing to tune against; give its ends mass");
    struts.push_back(c);
  }
  return struts;
}

}  // namespace flexloop::scene
