// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// `flexloop analyse`'s report of the superelement reduction's error (issue 58 item 3;
// plant/lti/reduction_error.hpp measures it): printed, and as analysis.json's "reduction_error".
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "plant/lti/reduction_error.hpp"

namespace flexloop::pipeline {

/// analysis.json's "reduction_error": the bodies (cut-off, modes kept, the damping compared at),
/// the band, per channel pair the largest relative error and where (outputs x inputs; null for a
/// pair without response), the largest of all, and the natural frequencies reduced vs full.
nlohmann::json reduction_error_json(const plant::lti::ReductionError& e);

/// The report on standard output: the bodies, the largest error, each output's worst input, the
/// natural frequencies table.
void print_reduction_error(const plant::lti::ReductionError& e);

/// While alive, this process's superelement reductions keep what they leave out up to `band_hz`
/// (plant/model/superelement_reader.hpp: a few more solves per reduction); then as before. Made
/// before the model is read.
class ReductionErrorBand {
 public:
  explicit ReductionErrorBand(double band_hz);
  ~ReductionErrorBand();
  ReductionErrorBand(const ReductionErrorBand&) = delete;
  ReductionErrorBand& operator=(const ReductionErrorBand&) = delete;

 private:
  double before_;
};

/// Measured on a model's linearisation for its channels at the analysis grid up to `up_to_hz`
/// (the model read under a ReductionErrorBand of it), printed, and its JSON; null (nothing
/// printed) for a model without a superelement.
nlohmann::json report_reduction_error(const plant::model::Model& m,
                                      const plant::model::Linearisation& lin,
                                      const std::vector<std::string>& inputs,
                                      const std::vector<std::string>& outputs,
                                      const std::vector<double>& frequencies_hz, double up_to_hz);

}  // namespace flexloop::pipeline
