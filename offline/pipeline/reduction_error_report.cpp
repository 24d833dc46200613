// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/reduction_error_report.hpp"

#include <cstdio>

#include "plant/model/superelement_reader.hpp"

namespace flexloop::pipeline {

namespace {

namespace lti = plant::lti;

struct Worst {
  std::size_t output = 0, input = 0;
  bool any = false;
};

// The compared pair with the largest relative error, among the inputs of one output or of all.
Worst worst_pair(const lti::ReductionError& e, std::size_t first_output, std::size_t outputs) {
  Worst w;
  double largest = -1;
  for (std::size_t o = first_output; o < first_output + outputs; ++o)
    for (std::size_t i = 0; i < e.inputs.size(); ++i)
      if (e.pair(o, i).compared && e.pair(o, i).relative > largest) {
        largest = e.pair(o, i).relative;
        w = {o, i, true};
      }
  return w;
}

nlohmann::json bodies_json(const lti::ReductionError& e) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& b : e.bodies)
    out.push_back({{"id", b.id},
                   {"full_dofs", b.full_dofs},
                   {"interface_dofs", b.interface_dofs},
                   {"modes_up_to_hz", b.cut_off_hz},
                   {"modes_kept", b.modes_kept},
                   {"zeta", b.zeta},
                   {"zeta_from", b.zeta_is_the_body_s ? "damping_ratio" : "default"},
                   {"rayleigh_hz", {b.low_hz, b.high_hz}},
                   {"rayleigh_alpha", b.alpha},
                   {"rayleigh_beta", b.beta}});
  return out;
}

// One matrix (outputs x inputs) of a PairError field; null where the pair has no response.
template <class Field>
nlohmann::json pair_matrix(const lti::ReductionError& e, Field field) {
  nlohmann::json rows = nlohmann::json::array();
  for (std::size_t o = 0; o < e.outputs.size(); ++o) {
    nlohmann::json row = nlohmann::json::array();
    for (std::size_t i = 0; i < e.inputs.size(); ++i)
      row.push_back(e.pair(o, i).compared ? nlohmann::json(field(e.pair(o, i)))
                                          : nlohmann::json(nullptr));
    rows.push_back(row);
  }
  return rows;
}

std::vector<double> values_of(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

}  // namespace

nlohmann::json reduction_error_json(const lti::ReductionError& e) {
  using P = lti::PairError;
  nlohmann::json j = {
      {"bodies", bodies_json(e)},
      {"band_hz", e.band_hz},
      {"compared_hz", {e.lowest_hz, e.highest_hz}},
      {"points", e.points},
      {"series_remainder_bound", e.remainder},
      {"inputs", e.inputs},
      {"outputs", e.outputs},
      {"outputs_not_compared", e.left_out},
      {"relative", pair_matrix(e, [](const P& p) { return p.relative; })},
      {"relative_hz", pair_matrix(e, [](const P& p) { return p.relative_hz; })},
      {"of_peak", pair_matrix(e, [](const P& p) { return p.of_peak; })},
      {"of_peak_hz", pair_matrix(e, [](const P& p) { return p.of_peak_hz; })},
      {"natural_frequencies",
       {{"reduced_hz", values_of(e.reduced_hz)}, {"full_hz", values_of(e.full_hz)}}}};
  const Worst w = worst_pair(e, 0, e.outputs.size());
  j["largest"] = nullptr;
  if (w.any)
    j["largest"] = {{"relative", e.pair(w.output, w.input).relative},
                    {"at_hz", e.pair(w.output, w.input).relative_hz},
                    {"output", e.outputs[w.output]},
                    {"input", e.inputs[w.input]}};
  if (!e.frequencies_note.empty()) j["natural_frequencies"]["note"] = e.frequencies_note;
  return j;
}

namespace {

void print_bodies(const lti::ReductionError& e) {
  std::printf(
      "reduction error: the machine with each superelement reduced against it with the full FE "
      "body (both with Rayleigh damping; doc/superelements.md)\n");
  for (const auto& b : e.bodies)
    std::printf(
        "  body %s: %ld DOFs -> %d interface + %d modes below %g Hz; zeta %g (%s) at %.4g and %g "
        "Hz\n",
        b.id.c_str(), b.full_dofs, b.interface_dofs, b.modes_kept, b.cut_off_hz, b.zeta,
        b.zeta_is_the_body_s ? "its damping_ratio" : "the body has none: 0.01", b.low_hz,
        b.high_hz);
  std::printf(
      "  compared %.4g .. %.4g Hz (%d points, up to %g Hz: the grid's top, at most f_c / 2); "
      "series bound %.1e\n",
      e.lowest_hz, e.highest_hz, e.points, e.band_hz, e.remainder);
  if (!e.left_out.empty())
    std::printf("  not compared: %zu outputs on modal amplitudes (the full body has none)\n",
                e.left_out.size());
}

void print_pairs(const lti::ReductionError& e) {
  const Worst all = worst_pair(e, 0, e.outputs.size());
  if (!all.any) {
    std::printf("  no channel pair has a response on the grid\n");
    return;
  }
  const auto& p = e.pair(all.output, all.input);
  std::printf("  largest relative error %.2e at %.4g Hz (%s / %s); of the pair's peak %.2e\n",
              p.relative, p.relative_hz, e.outputs[all.output].c_str(), e.inputs[all.input].c_str(),
              p.of_peak);
  std::printf("  per output, its worst input: relative error, where; of the peak\n");
  for (std::size_t o = 0; o < e.outputs.size(); ++o) {
    const Worst w = worst_pair(e, o, 1);
    if (!w.any) continue;
    const auto& q = e.pair(w.output, w.input);
    std::printf("    %-18s %.2e at %9.4g Hz  (%s)  %.2e\n", e.outputs[o].c_str(), q.relative,
                q.relative_hz, e.inputs[w.input].c_str(), q.of_peak);
  }
}

void print_frequencies(const lti::ReductionError& e) {
  if (!e.frequencies_note.empty()) {
    std::printf("  natural frequencies: not compared (%s)\n", e.frequencies_note.c_str());
    return;
  }
  std::printf("  natural frequencies up to %g Hz, reduced -> full [Hz]:\n", e.band_hz);
  for (Eigen::Index k = 0; k < e.reduced_hz.size(); ++k) {
    const double r = e.reduced_hz(k), f = e.full_hz(k);
    std::printf("    %12.6f -> %12.6f  (%+.2e)\n", r, f, r > 0 ? (f - r) / r : 0.0);
  }
}

}  // namespace

ReductionErrorBand::ReductionErrorBand(double band_hz)
    : before_(plant::model::set_reduction_error_band_hz(band_hz)) {}

ReductionErrorBand::~ReductionErrorBand() {
  plant::model::set_reduction_error_band_hz(before_);
}

void print_reduction_error(const lti::ReductionError& e) {
  print_bodies(e);
  print_pairs(e);
  print_frequencies(e);
}

nlohmann::json report_reduction_error(const plant::model::Model& m,
                                      const plant::model::Linearisation& lin,
                                      const std::vector<std::string>& inputs,
                                      const std::vector<std::string>& outputs,
                                      const std::vector<double>& frequencies_hz, double up_to_hz) {
  if (m.superelements.empty()) return nullptr;
  const lti::ReductionError e =
      lti::reduction_error(m, lin, inputs, outputs, frequencies_hz, up_to_hz);
  print_reduction_error(e);
  return reduction_error_json(e);
}

}  // namespace flexloop::pipeline
