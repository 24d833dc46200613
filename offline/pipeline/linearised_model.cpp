// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/linearised_model.hpp"

#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/model/massless_condensation.hpp"
#include "plant/model/model_parser.hpp"

namespace flexloop::pipeline {

LinearisedModel linearise_model_file(const std::string& path, std::vector<std::string> inputs,
                                     std::vector<std::string> outputs) {
  namespace model = plant::model;
  LinearisedModel r{model::load_model(path), {}, {}, {}, {}, 0, {}, {}};
  const model::Model& m = r.model;
  if (inputs.empty()) {
    for (int i = m.nd(); i < m.nq(); ++i) inputs.push_back("acc:" + m.generalised[i]);
    for (const auto& el : m.elements)
      for (int k = 0; k < el.deformation_count(); ++k)
        if (el.actuated[k])
          inputs.push_back("stress:" + m.deformation_labels[el.first_deformation + k]);
  }
  if (outputs.empty())
    for (int i = 0; i < m.nd(); ++i) outputs.push_back("pos:" + m.generalised[i]);
  r.lin = model::linearise(m, model::model_operating_point(m));
  r.ss = plant::lti::build_state_space(m, r.lin, inputs, outputs, &r.condensation);
  // Frequencies of the linearised dynamics about the operating point (Kbar + Nbar + Gbar; at a
  // moving point the velocity terms C + D are carried as damping).
  const int nd = m.nd();
  const std::vector<std::string> labels(m.generalised.begin(), m.generalised.begin() + nd);
  auto dd = [nd](const Eigen::MatrixXd& A) { return Eigen::MatrixXd(A.topLeftCorner(nd, nd)); };
  const auto c = model::condense_massless(dd(r.lin.M), dd(r.lin.K + r.lin.N), dd(r.lin.C + r.lin.D),
                                          dd(r.lin.G), {}, labels);
  r.massless_condensed = c.massless_count;
  const auto modes = plant::lti::natural_modes(c.M, c.K + c.G);
  r.natural_frequencies_hz = modes.frequencies_hz;
  r.mode_shapes = c.T * modes.shapes;  // back from the massive coordinates to q_d
  r.statics = plant::lti::static_stability(modes, dd(r.lin.K), dd(r.lin.G));
  return r;
}

}  // namespace flexloop::pipeline
