// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The tail as a rehearsal (`flexloop campaign report --worst K`, doc/campaign.md "Worst samples"):
// the K worst machines of a campaign written as a scene and its model variant (the drawn values
// in them) that analyse, sim and hil run as they are.
// Worst first: when any sample is unstable, the unstable ones, by the sampled loop's spectral
// radius (largest first); then the stable ones by spectral radius too. When every evaluated
// sample is stable: by the worst performance RMS relative to the nominal machine's (max over the
// performance channels of rms / nominal rms). Refused and failed samples are not machines that
// run: they are left out. Ties: the lower index first.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "offline/campaign/parameter_paths.hpp"

namespace flexloop::campaign {

/// The k worst as the samples stream by, in any order, each once: per ordering (unstable first
/// by spectral radius; by the worst RMS ratio) a heap of the k worst so far, the one that applies
/// chosen at the end. k entries held, whatever the number of samples.
class WorstSamples {
 public:
  WorstSamples(const nlohmann::json& nominal, std::size_t k);
  /// A sample and its position (the order of ties: the lower first).
  void add(long position, const nlohmann::json& sample);
  /// The positions of the k worst, worst first.
  std::vector<long> worst() const;

  struct Candidate {
    double key_first, key_second;
    long position;
  };

 private:
  void keep(std::vector<Candidate>& heap, const Candidate& c) const;
  nlohmann::json nominal_;
  std::size_t k_;
  bool any_unstable_ = false;
  std::vector<Candidate> by_radius_, by_rms_;  // heaps, the least bad of the kept on top
};

/// Indices into `samples` (sorted by index, as merged) of the `k` worst, worst first.
std::vector<std::size_t> worst_samples(const std::vector<nlohmann::json>& samples,
                                       const nlohmann::json& nominal, std::size_t k);

/// The scene and model TOML texts of one sample: the scene names the model file
/// `model_file_name` beside it, a controller file by its absolute path; a header comment says
/// which plan and index they come from.
struct SampleScene {
  std::string scene_text, model_text;
};
SampleScene sample_scene(const MachineDocuments& docs, const nlohmann::json& plan,
                         const nlohmann::json& sample, const std::string& model_file_name);
/// The same for any machine of the plan's documents with `values`: `what` heads the comment
/// ("sample 12 of plan ..."), `name_suffix` is appended to the scene's name.
SampleScene machine_scene(const MachineDocuments& docs, const nlohmann::json& plan,
                          const ParameterValues& values, const std::string& what,
                          const std::string& name_suffix, const std::string& model_file_name);

/// Writes DIR/worst/sample-<index>.toml and sample-<index>_model.toml for each of `worst` (the
/// worst samples, worst first); returns the scene files written.
std::vector<std::string> write_sample_scenes(const MachineDocuments& docs,
                                             const nlohmann::json& plan,
                                             const std::vector<nlohmann::json>& worst,
                                             const std::string& out_dir);

/// write_sample_scenes of the `k` worst of `samples`.
std::vector<std::string> write_worst_samples(const MachineDocuments& docs,
                                             const nlohmann::json& plan,
                                             const std::vector<nlohmann::json>& samples,
                                             std::size_t k, const std::string& out_dir);

}  // namespace flexloop::campaign
