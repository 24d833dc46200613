// SPDX-License-Identifier: BSD-3-Clause
// The loop artefact (artefact/loop_artefact.hpp): built from the metrology scene it survives a
// write/read round trip bit for bit (dense and modal, with every effect); a run from the file
// gives the run from the scene; and every kind of bad artefact is refused with the file and key.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "artefact/loop_artefact.hpp"
#include "common/input_error.hpp"
#include "common/json_document.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/sim/scene_runs.hpp"

using namespace flexloop;
using nlohmann::json;

namespace {

std::filesystem::path temp_file(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "flexloop_artefact_test";
  std::filesystem::create_directories(dir);
  return dir / name;
}

const artefact::LoopArtefact& all_effects() {
  static const artefact::LoopArtefact a =
      scene::load_loop("tools/scenes/metrology_frame_all_effects.toml");
  return a;
}

// The error a broken copy of the all-effects artefact gets; `edit` breaks its JSON.
template <class Edit>
std::string error_of(Edit edit) {
  json j = artefact::to_json(all_effects());
  edit(j);
  try {
    artefact::loop_artefact_from_json(j, "loop.json");
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("loop artefact: write and read give the same artefact, bit for bit", "[artefact]") {
  for (const auto form : {artefact::PlantForm::kDense, artefact::PlantForm::kModal}) {
    CAPTURE(artefact::to_string(form));
    const auto a = scene::load_loop("tools/scenes/metrology_frame.toml",
                                    {.rate_hz = 0, .form = form, .duration_s = 0});
    const auto file = temp_file("metrology_" + artefact::to_string(form) + ".json");
    artefact::write_loop_artefact(file, a);
    CHECK(artefact::is_loop_artefact_file(file));
    const auto b = artefact::read_loop_artefact(file);
    CHECK(b.plant.A == a.plant.A);
    CHECK(b.plant.B == a.plant.B);
    CHECK(b.plant.C == a.plant.C);
    CHECK(b.plant.D == a.plant.D);
    CHECK(b.plant.states == a.plant.states);
    CHECK(b.plant.modal.T == a.plant.modal.T);
    CHECK(b.plant.modal.Lambda_minus_I == a.plant.modal.Lambda_minus_I);
    CHECK(b.pi.K_P == a.pi.K_P);
    CHECK(b.pi.K_I == a.pi.K_I);
    CHECK(b.floor_filter.A == a.floor_filter.A);
    CHECK(b.floor_filter.motion == a.floor_filter.motion);
    CHECK(b.names(b.channels.sensors) == a.names(a.channels.sensors));
    CHECK(b.channels.performance[0].unit == "m/s^2");
    CHECK(b.channels.actuators[0].unit == "N");
    CHECK(b.provenance.scene_sha256.size() == 64);
    CHECK(b.provenance.model_sha256.size() == 64);
  }
  // Every effect, the gravity preload's floor states.
  const auto file = temp_file("all_effects.json");
  artefact::write_loop_artefact(file, all_effects());
  const auto b = artefact::read_loop_artefact(file);
  const auto& e = b.effects;
  CHECK(e.actuator.present);
  CHECK(e.actuator.lag_s == all_effects().effects.actuator.lag_s);
  CHECK(e.force_sensor.delay_samples == all_effects().effects.force_sensor.delay_samples);
  CHECK(e.accelerometer.seed == all_effects().effects.accelerometer.seed);
  CHECK(e.transport_delay_samples == all_effects().effects.transport_delay_samples);
  CHECK(b.pi.feedthrough_delay == all_effects().pi.feedthrough_delay);
  CHECK(b.pi.u_max == all_effects().pi.u_max);
}

TEST_CASE("loop artefact: a run from the file is the run from the scene", "[artefact]") {
  const auto file = temp_file("all_effects_run.json");
  artefact::write_loop_artefact(file, all_effects());
  sim::RunSettings s;
  s.dt = all_effects().dt();
  s.steps = 5000;
  const auto from_scene = sim::run_artefact(all_effects(), s, {});
  const auto from_file = sim::run_artefact(artefact::read_loop_artefact(file), s, {});
  CHECK(from_file.on.rms_performance == from_scene.on.rms_performance);
  CHECK(from_file.off.rms_performance == from_scene.off.rms_performance);
}

TEST_CASE("loop artefact: bad artefacts name the file, the key and what is wrong", "[artefact]") {
  using Catch::Contains;
  CHECK_THAT(error_of([](json& j) { j["version"] = 2; }),
             Contains("loop.json: key 'version': is 2; this flexloop reads version 1"));
  CHECK_THAT(error_of([](json& j) { j["format"] = "something else"; }), Contains("key 'format'"));
  // Sizes that do not close over the channel map.
  CHECK_THAT(error_of([](json& j) { j["plant"]["B"].erase(0); }),
             Contains("key 'plant': key 'B': has 23 rows, expected 24 (one per state)"));
  CHECK_THAT(error_of([](json& j) { j["channels"]["sensors"].erase(0); }),
             Contains("key 'C': has 12 rows, expected 11"));
  CHECK_THAT(error_of([](json& j) { j["channels"]["actuators"] = json::array(); }),
             Contains("key 'actuators': has 0 channels; each kind takes 1 .. 64"));
  // Non-finite and wrongly typed entries.
  CHECK_THAT(error_of([](json& j) { j["plant"]["A"][2][3] = "nan"; }),
             Contains("key 'A' row 3 column 4: expected a number, found string \"nan\""));
  CHECK_THAT(error_of([](json& j) { j["controller"]["K_P"][0][0] = nullptr; }),
             Contains("key 'K_P' row 1 column 1: expected a number, found null"));
  // Unknown kinds and out-of-range values.
  CHECK_THAT(error_of([](json& j) { j["controller"]["type"] = "lqg"; }),
             Contains("key 'type': is \"lqg\"; this flexloop knows"));
  CHECK_THAT(error_of([](json& j) { j["plant"]["form"] = "sparse"; }),
             Contains("key 'form': is \"sparse\""));
  CHECK_THAT(error_of([](json& j) { j["method"] = "rk4"; }),
             Contains("key 'method': is \"rk4\"; expected \"zoh\", \"foh\", \"tustin\", "
                      "\"euler\" or \"backward-euler\""));
  CHECK_THAT(error_of([](json& j) { j["floor"]["spectrum"] = "VC-F"; }),
             Contains("key 'spectrum': is \"VC-F\"; expected \"white\", \"VC-A\""));
  CHECK_THAT(error_of([](json& j) { j["effects"]["transport_delay_samples"] = 40; }),
             Contains("key 'transport_delay_samples': is 40, must be 0 .. 32"));
  CHECK_THAT(error_of([](json& j) { j["rate_hz"] = -10; }), Contains("key 'rate_hz': must be > 0"));
  // Both command limits are sized against the actuators (6 here), u_max as u_min.
  CHECK_THAT(error_of([](json& j) {
               j["controller"]["u_max"] = {100.0, 100.0};
             }),
             Contains("key 'controller': key 'u_max': has 2 values; expected none, one, or one "
                      "per actuator (6)"));
  CHECK_THAT(error_of([](json& j) {
               j["controller"]["u_min"] = {-100.0, -100.0};
             }),
             Contains("key 'controller': key 'u_min': has 2 values; expected none, one, or one "
                      "per actuator (6)"));
  CHECK_THAT(error_of([](json& j) { j.erase("floor"); }), Contains("key 'floor': is missing"));
  // A start covariance a hand edit broke: not symmetric, not positive semidefinite.
  CHECK_THAT(error_of([](json& j) {
               j["start"]["closed_loop"]["covariance"][0][1] =
                   2 * j["start"]["closed_loop"]["covariance"][0][1].get<double>() + 1;
             }),
             Contains("key 'closed_loop': key 'covariance': not symmetric: entry (1, 0)"));
  CHECK_THAT(error_of([](json& j) { j["start"]["open_loop"]["covariance"][0][0] = -1.0; }),
             Contains("key 'open_loop': key 'covariance': not positive semidefinite: eigenvalue"));
  // Not JSON at all: the file is named.
  const auto broken = temp_file("broken.json");
  std::ofstream(broken) << "{\"format\": ";
  CHECK_THROWS_WITH(artefact::read_loop_artefact(broken), Contains("broken.json: not valid JSON"));
  CHECK_FALSE(artefact::is_loop_artefact_file(broken));
}

TEST_CASE("loop artefact: the writer refuses what its reader would refuse, and writes nothing",
          "[artefact]") {
  using Catch::Contains;
  // A start whose covariance came out indefinite (the arm's before issue 57): build must fail
  // with the reader's reason instead of writing a file that every later command refuses.
  artefact::LoopArtefact a = all_effects();
  a.start.open_loop.covariance(0, 0) = -1;
  const auto file = temp_file("refused_by_its_reader.json");
  std::filesystem::remove(file);
  CHECK_THROWS_WITH(artefact::write_loop_artefact(file, a),
                    Contains("refused_by_its_reader.json: key 'start': key 'open_loop': key "
                             "'covariance': not positive semidefinite") &&
                        Contains("not written"));
  CHECK_FALSE(std::filesystem::exists(file));
  // An existing artefact is left as it was.
  artefact::write_loop_artefact(file, all_effects());
  const auto before = std::filesystem::file_size(file);
  CHECK_THROWS(artefact::write_loop_artefact(file, a));
  CHECK(std::filesystem::file_size(file) == before);
  CHECK(artefact::read_loop_artefact(file).start.open_loop.covariance ==
        all_effects().start.open_loop.covariance);
}
