#include "tools/hil/plant_loop.hpp"

#include <string>

#include "plant/model/input_error.hpp"
#include "tools/hil/latency_json.hpp"
#include "tools/hil/loop_scene.hpp"
#include "tools/hil/plant_loop_run.hpp"
#include "tools/hil/private_network.hpp"
#include "tools/hil/stop_signal.hpp"

namespace flexloop::hil {

PlantLoopResult run_plant_loop(const LoopOptions& o) {
  require_private_network("flexloop plant", o.link);
  return run_plant_loop(o, load_loop_scene(o.scene_path, o.rate_hz));
}

PlantLoopResult run_plant_loop(const LoopOptions& o, const LoopScene& scene) {
  require_private_network("flexloop plant", o.link);
  const std::string url = loop_lcm_url(o.url, o.link);
  install_stop_handlers();
  PlantLoopResult r;
  // One translation unit per compiled plant size, each with every effect combination.
  const auto& d = scene.plant.sys;
  if (d.nx() == 12 && d.nu() == 2 * kChannels && d.ny() == 2 * kChannels)
    detail::run_plant_metrology(scene, o, url, r);
  else if (d.nx() == 24 && d.nu() == 2 * kChannels && d.ny() == 2 * kChannels)
    detail::run_plant_preloaded(scene, o, url, r);
  else
    throw InputError(scene.scene.file,
                     "[plant]: the real-time loop is compiled for the metrology frame (12 states, "
                     "6 + 6 inputs and outputs) and its gravity-preload variant (24 states); this "
                     "plant has " +
                         std::to_string(d.nx()) + " states");
  return r;
}

nlohmann::json plant_result_json(const PlantLoopResult& r, const LoopOptions& o, bool with_bins) {
  const LoopAccounts& a = r.accounts;
  nlohmann::json j = {{"rate_hz", r.rate_hz},
                      {"period_ns", static_cast<std::int64_t>(1e9 / r.rate_hz + 0.5)},
                      {"wait_mode", rt::to_string(o.wait)},
                      {"receive_path", rt::to_string(o.receive_path)},
                      {"spin_margin_ns", r.spin_margin_ns},
                      {"cycles", r.cycles},
                      {"periods", r.periods},
                      {"deadline_misses", r.deadline_misses},
                      {"late_answers", r.late_answers},
                      {"overruns", r.overruns},
                      {"skipped_periods", r.skipped_periods},
                      {"safe_command_cycles", r.safe_command_cycles},
                      {"safe_after", o.safe_after},
                      {"dropped_messages", drops_json(r.drops)},
                      {"round_trip_ns", summary_json(*a.round_trip)},
                      {"wakeup_lateness_ns", summary_json(*a.wakeup_lateness)},
                      {"plant_compute_ns", summary_json(*a.plant_compute)},
                      {"controller_compute_ns", summary_json(*a.controller_compute)},
                      {"stats_published", r.stats_published},
                      {"publish_failures", r.publish_failures},
                      {"cpu", o.realtime.cpu},
                      {"fifo", r.fifo},
                      {"plant_setup", r.setup}};
  if (with_bins)
    j["histograms"] = {{"round_trip_ns", bins_json(*a.round_trip)},
                       {"wakeup_lateness_ns", bins_json(*a.wakeup_lateness)}};
  return j;
}

}  // namespace flexloop::hil
