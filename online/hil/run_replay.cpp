// SPDX-License-Identifier: BSD-3-Clause
#include "online/hil/run_replay.hpp"

#include <flexloop_msgs/actuator_command_t.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "controller/fmu/fmu_from_artefact.hpp"
#include "online/loop/controller_station.hpp"
#include "online/loop/plant_station.hpp"
#include "online/loop/station_start.hpp"
#include "online/sim/loop_hardware.hpp"
#include "plant/runtime/plant_from_artefact.hpp"

namespace flexloop::hil {

namespace {

// Whether ascending seqs lie in a SampleRanges, in one pass over it.
class RangeCursor {
 public:
  explicit RangeCursor(const loop::SampleRanges& r) : ranges_(r.ranges()) {}
  bool contains(std::int64_t seq) {
    while (next_ < ranges_.size() && ranges_[next_].second < seq) ++next_;
    return next_ < ranges_.size() && ranges_[next_].first <= seq;
  }

 private:
  const std::vector<std::pair<std::int64_t, std::int64_t>>& ranges_;
  std::size_t next_ = 0;
};

nlohmann::json unavailable(const std::string& why) {
  return {{"unavailable", why}};
}

std::vector<double> values(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

// Cycle k (k = 0 .. samples) at t_k: the answer to sample k, unless the plant did not apply it,
// arrives a tenth of a period after the sample (a twentieth in transit each way); settle; then
// sample k + 1, which the controller answers unless it did not.
template <class Hardware, class Controller>
nlohmann::json replay_with(Hardware hw, Controller controller, const artefact::LoopArtefact& loop,
                           const loop::LoopOptions& o, const RunRecord& record) {
  const std::optional<sim::DrawnStart> start = loop::start_plant_hardware(loop, o.start, hw);
  const loop::PlantStationSettings settings = loop::plant_station_settings(loop, o, 1);
  loop::PlantStation<Hardware> plant(std::move(hw), settings);
  if (start) plant.start_command(typename Hardware::Command(start->last_command));
  loop::ControllerStation<Controller> station(std::move(controller), o.safe_after,
                                              loop::controller_start(loop, o.start));
  const std::int64_t period = settings.period_ns, transit = period / 20, compute = period / 10;
  RangeCursor unapplied(record.unapplied), unanswered(record.unanswered);
  std::vector<std::uint8_t> buffer;
  std::optional<flexloop_msgs::actuator_command_t> answer;  // to the newest sample
  for (std::int64_t k = 0; k <= record.samples; ++k) {
    const std::int64_t t = (k + 1) * period;
    if (k > 0 && !unapplied.contains(k)) {
      if (!answer)
        return unavailable("the plant applied an answer to sample " + std::to_string(k) +
                           ", which the controller process did not answer");
      rt::offer_encoded(plant.commands(), *answer, t - period + compute + transit, buffer);
    }
    answer.reset();
    plant.settle(t);
    if (k == record.samples) break;
    const auto& s = plant.sample(t);
    if (unanswered.contains(s.seq)) continue;
    rt::offer_encoded(station.samples(), s, t + transit, buffer);
    if (const auto* got = station.samples().take()) {
      auto& cmd = station.answer(*got);
      cmd.t_ns = t + compute;
      answer = cmd;
    }
  }
  if (plant.deadline_misses() != record.unapplied.count())
    return unavailable("the replay missed " + std::to_string(plant.deadline_misses()) +
                       " answers where the run missed " + std::to_string(record.unapplied.count()));
  nlohmann::json replay = {{"performance_rms", values(plant.rms_performance())},
                           {"command_rms", values(plant.rms_command())},
                           {"deadline_misses", plant.deadline_misses()},
                           {"safe_command_cycles", plant.safe_command_cycles()}};
  // A controller FMU that failed replays its failure (the same calls on the same samples) and
  // the safe command after it, as the run did.
  if (const auto c = station.report(); !c.failure.empty()) replay["controller_failure"] = c.failure;
  return replay;
}

}  // namespace

nlohmann::json replay_run(const artefact::LoopArtefact& loop, const loop::LoopOptions& o,
                          const RunRecord& record) {
  if (loop.controller == artefact::ControllerKind::kNone)
    return unavailable("no controller process ran");
  if (!record.unapplied.complete() || !record.unanswered.complete())
    return unavailable("the run's record of misses is incomplete (more than " +
                       std::to_string(loop::SampleRanges::kCapacity) +
                       " ranges, or the controller answered another plant run)");
  constexpr int kAny = Eigen::Dynamic;
  return plant::runtime::with_general_plant<double>(loop, [&](const auto& plant) {
    return sim::with_hardware<kAny, kAny, kAny>(loop, plant, [&](auto hw) {
      return controller::fmu::with_any_controller<double>(loop, [&](auto controller) {
        return replay_with(std::move(hw), std::move(controller), loop, o, record);
      });
    });
  });
}

}  // namespace flexloop::hil
