// SPDX-License-Identifier: BSD-3-Clause
// `flexloop analyse MODEL [--input NAME]... [--output NAME]... [--out-dir DIR]`
// Modes, buckling multipliers and the frequency response of a linearised model: printed, and
// written as analysis.json, frequency_response.csv, singular_values.csv, bode.png and
// singular_values.png in DIR. A model without an input or an output channel has no frequency
// response: analysis.json alone, and one line saying which files were skipped and why.
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "offline/pipeline/analyse_scene.hpp"
#include "offline/pipeline/linearised_model.hpp"
#include "offline/pipeline/provenance.hpp"
#include "offline/pipeline/reduction_error_report.hpp"
#include "offline/report/csv_writer.hpp"
#include "offline/report/plot.hpp"
#include "offline/scene/scene.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/state_space_json.hpp"
#include "tools/flexloop/subcommands.hpp"

namespace flexloop::cli {

namespace {

namespace lti = plant::lti;

struct AnalyseArgs {
  std::string model, out_dir = "out/analyse";
  std::vector<std::string> inputs, outputs;
  double f_min = 0.01, f_max = 1000.0;
  int points = 400;
  bool no_reduction_error = false;
};

// The frequency response and the singular values of r.ss: CSV files and pictures in dir.
void write_response(const std::string& model_name, const pipeline::LinearisedModel& r,
                    const pipeline::FrequencyGrid& grid, const std::string& dir) {
  const auto& ss = r.ss;
  const auto f =
      lti::with_resonances(lti::log_frequency_grid_hz(grid.f_min_hz, grid.f_max_hz, grid.points),
                           r.natural_frequencies_hz);
  const auto G = lti::frequency_response(ss, f);
  const Eigen::MatrixXd sv = lti::singular_values(G);
  std::vector<std::string> header{"frequency_hz"};
  std::vector<std::vector<double>> cols{f};
  std::vector<report::BodeSeries> bode;
  for (Eigen::Index o = 0; o < ss.ny(); ++o) {
    for (Eigen::Index i = 0; i < ss.nu(); ++i) {
      const auto g = report::channel(G, o, i);
      const std::string name = ss.outputs[o] + " / " + ss.inputs[i];
      std::vector<double> mag, ph;
      for (const auto& c : g)
        mag.push_back(20 * std::log10(std::abs(c))), ph.push_back(std::arg(c) * 180 / M_PI);
      header.push_back(name + " [dB]");
      header.push_back(name + " [deg]");
      cols.push_back(mag);
      cols.push_back(ph);
      if (bode.size() < 8) bode.push_back({name, f, g, ""});
    }
  }
  report::write_csv_columns(dir + "frequency_response.csv", header, cols);
  std::vector<std::string> sv_header{"frequency_hz"};
  std::vector<std::vector<double>> sv_cols{f};
  for (Eigen::Index k = 0; k < sv.cols(); ++k) {
    sv_header.push_back("sigma" + std::to_string(k + 1) + " [dB]");
    std::vector<double> col;
    for (Eigen::Index i = 0; i < sv.rows(); ++i) col.push_back(20 * std::log10(sv(i, k)));
    sv_cols.push_back(col);
  }
  report::write_csv_columns(dir + "singular_values.csv", sv_header, sv_cols);
  report::plot_bode({model_name + ": frequency response", "", "", true, false}, bode,
                    dir + "bode.png");
  report::plot_singular_values({model_name + ": singular values", "", "", true, false},
                               {{model_name, f, sv, ""}}, dir + "singular_values.png");
}

// The superelement reduction's error at the response's grid (null: none to measure or asked).
nlohmann::json model_reduction_error(const AnalyseArgs& a, const pipeline::LinearisedModel& r) {
  if (a.no_reduction_error || r.model.superelements.empty()) return nullptr;
  const auto f = lti::with_resonances(lti::log_frequency_grid_hz(a.f_min, a.f_max, a.points),
                                      r.natural_frequencies_hz);
  return pipeline::report_reduction_error(r.model, r.lin, r.ss.inputs, r.ss.outputs, f, a.f_max);
}

void run(const AnalyseArgs& a) {
  if (!(a.f_min > 0 && a.f_max > a.f_min && a.points >= 2))
    throw common::InputError("--fmin/--fmax/--points",
                             "need 0 < fmin < fmax and at least 2 points");
  common::require_writable(std::filesystem::path(a.out_dir) / "analysis.json");
  if (scene::is_scene_file(a.model)) {
    if (!a.inputs.empty() || !a.outputs.empty())
      throw common::InputError(a.model,
                               "a scene names its channels in [plant]; drop --input/--output");
    pipeline::analyse_scene(a.model, a.out_dir, {a.f_min, a.f_max, a.points},
                            {.reduction_error = !a.no_reduction_error});
    return;
  }
  const pipeline::ReductionErrorBand band(a.no_reduction_error ? 0.0 : a.f_max);
  const pipeline::LinearisedModel r = pipeline::linearise_model_file(a.model, a.inputs, a.outputs);
  const auto& m = r.model;
  const auto& ss = r.ss;
  const int nd = m.nd();
  std::filesystem::create_directories(a.out_dir);
  const std::string dir = a.out_dir + "/";

  // Modes and buckling.
  std::printf("natural frequencies of %s (%d dynamic coordinates", m.name.c_str(), nd);
  if (r.massless_condensed) std::printf(", %d massless directions condensed", r.massless_condensed);
  std::printf("):\n");
  for (Eigen::Index i = 0; i < r.natural_frequencies_hz.size(); ++i)
    std::printf("  mode %2ld  %12.6g Hz\n", static_cast<long>(i + 1), r.natural_frequencies_hz(i));
  const Eigen::VectorXd& buckling = r.statics.buckling_multipliers;
  if (r.statics.preloaded) {
    std::printf("buckling multipliers (det(K + lambda G) = 0, load = lambda x present preload):");
    for (Eigen::Index i = 0; i < std::min<Eigen::Index>(buckling.size(), 6); ++i)
      std::printf(" %.6g", buckling(i));
    std::printf(buckling.size() == 0 ? " none finite and real\n" : "\n");
  } else {
    std::printf("no preload: geometric stiffness is zero, no buckling multipliers\n");
  }
  std::printf("%s%s\n", r.statics.stable() ? "" : "UNSTABLE: ", lti::to_string(r.statics).c_str());

  // Frequency response and singular values: only of a model with at least one input and one
  // output channel. Without (e.g. no prescribed coordinate and no actuated deformation, so no
  // default input) there is nothing to draw: the modal analysis is still written, and the line
  // below says which files were skipped and why.
  const bool has_response = ss.nu() > 0 && ss.ny() > 0;
  if (has_response)
    write_response(m.name, r, {a.f_min, a.f_max, a.points}, dir);
  else
    std::printf(
        "skipped bode.png, singular_values.png and their CSVs: no %s channel, so no frequency "
        "response to draw (%s)\n",
        ss.nu() == 0 ? "input" : "output",
        ss.nu() == 0 ? "the model has no prescribed coordinate and no actuated deformation; name "
                       "an input with --input, e.g. force:<coordinate>"
                     : "name an output with --output");

  const nlohmann::json reduction = has_response ? model_reduction_error(a, r) : nullptr;
  nlohmann::json j = {
      {"natural_frequencies_hz",
       std::vector<double>(r.natural_frequencies_hz.data(),
                           r.natural_frequencies_hz.data() + r.natural_frequencies_hz.size())},
      {"buckling_multipliers",
       std::vector<double>(buckling.data(), buckling.data() + buckling.size())},
      {"static_stability", pipeline::static_stability_json(r.statics)},
      {"state_space", lti::to_json(ss)},
      {"provenance", pipeline::make_provenance(a.model, "flexloop analyse")}};
  nlohmann::json shapes = nlohmann::json::array();
  for (Eigen::Index c = 0; c < r.mode_shapes.cols(); ++c)
    shapes.push_back(std::vector<double>(r.mode_shapes.col(c).data(),
                                         r.mode_shapes.col(c).data() + r.mode_shapes.rows()));
  j["mode_shapes"] = shapes;
  if (!reduction.is_null()) j["reduction_error"] = reduction;
  j["mode_shape_coordinates"] =
      std::vector<std::string>(m.generalised.begin(), m.generalised.begin() + nd);
  nlohmann::json poles = nlohmann::json::array();
  for (const auto& p : lti::poles(ss)) poles.push_back({p.real(), p.imag()});
  j["poles"] = poles;
  lti::write_json_atomically(dir + "analysis.json", j);
  if (has_response)
    std::printf(
        "wrote %s{analysis.json, frequency_response.csv, singular_values.csv, bode.png, "
        "singular_values.png}\n",
        dir.c_str());
  else
    std::printf("wrote %sanalysis.json\n", dir.c_str());
}

}  // namespace

void register_analyse(CLI::App& app) {
  auto args = std::make_shared<AnalyseArgs>();
  auto* cmd =
      app.add_subcommand("analyse",
                         "Modes, buckling multipliers and frequency response of a model, or the "
                         "passive machine, PI design and closed loop of a scene");
  cmd->add_option("model", args->model, "Model file or scene file (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--input,-i", args->inputs, "Input channel (as for linearise)");
  cmd->add_option("--output,-O", args->outputs, "Output channel (as for linearise)");
  cmd->add_option("--out-dir", args->out_dir, "Directory for JSON, CSV and PNG files")
      ->capture_default_str();
  cmd->add_option("--fmin", args->f_min, "Lowest frequency, Hz")->capture_default_str();
  cmd->add_option("--fmax", args->f_max, "Highest frequency, Hz")->capture_default_str();
  cmd->add_option("--points", args->points, "Frequencies on the log grid")->capture_default_str();
  cmd->add_flag("--no-reduction-error", args->no_reduction_error,
                "Skip the superelement reduction's error against the full FE body");
  cmd->footer(
      "Example:\n  flexloop analyse tools/models/cart.toml -i acc:x.1 -O pos:x.2 --out-dir "
      "out/cart\n  flexloop analyse tools/scenes/metrology_frame.toml --out-dir out/metrology");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
