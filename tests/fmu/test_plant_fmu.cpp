// SPDX-License-Identifier: BSD-3-Clause
// The exported plant FMU (`flexloop export-fmu`, issue 33), driven by a harness through the FMI
// 2.0 calls as a user's tool would drive it, equals `flexloop sim`'s plant: open loop from the
// stationary start on machines other than the reference (8 actuators; a 106-state modal arm; the
// frame with every effect), and closed by the built-in PI from rest, sample for sample.
#include <dlfcn.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "controller/fmu/fmu_archive.hpp"
#include "controller/fmu/fmu_description.hpp"
#include "controller/fmu/fmu_library.hpp"
#include "controller/runtime/general_pi_controller.hpp"
#include "offline/pipeline/plant_fmu_export.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/sim/scene_runs.hpp"
#include "tests/fmu/fmu_fixture.hpp"

namespace fs = std::filesystem;
using namespace flexloop;

namespace {

// The harness: the FMU unpacked, loaded and instantiated through its FMI calls.
class PlantFmuHarness {
 public:
  PlantFmuHarness(const std::string& fmu, bool start_at_rest)
      : dir_(fmu),
        description_(controller::fmu::read_fmu_description(dir_.path(), fmu)),
        library_(dir_.path(), description_.model_identifier, fmu) {
    const auto& f = library_.calls();
    const std::string resources = "file://" + (dir_.path() / "resources").string();
    instance_ = f.instantiate("harness", fmi2CoSimulation, description_.guid.c_str(),
                              resources.c_str(), &callbacks_, fmi2False, fmi2False);
    REQUIRE(instance_);
    // The boolean parameter is not among the calls the controller loader resolves.
    const std::string so =
        (dir_.path() / "binaries/linux64" / (description_.model_identifier + ".so")).string();
    void* handle = dlopen(so.c_str(), RTLD_NOW | RTLD_NOLOAD);
    REQUIRE(handle);
    using SetBoolean =
        fmi2Status(fmi2Component, const fmi2ValueReference[], size_t, const fmi2Boolean[]);
    auto* set_boolean = reinterpret_cast<SetBoolean*>(dlsym(handle, "fmi2SetBoolean"));
    dlclose(handle);
    REQUIRE(set_boolean);
    const fmi2ValueReference rest_reference = 0;
    const fmi2Boolean rest = start_at_rest ? fmi2True : fmi2False;
    REQUIRE(set_boolean(instance_, &rest_reference, 1, &rest) == fmi2OK);
    REQUIRE(f.setup_experiment(instance_, fmi2False, 0, 0, fmi2False, 0) == fmi2OK);
    REQUIRE(f.enter_initialization_mode(instance_) == fmi2OK);
    REQUIRE(f.exit_initialization_mode(instance_) == fmi2OK);
  }
  ~PlantFmuHarness() {
    library_.calls().terminate(instance_);
    library_.calls().free_instance(instance_);
  }

  /// The real variable's value reference by name.
  fmi2ValueReference reference(const std::string& name, const char* causality) const {
    return description_.real(name, causality, "harness").value_reference;
  }
  std::vector<double> get(const std::vector<fmi2ValueReference>& vr) const {
    std::vector<double> v(vr.size());
    REQUIRE(library_.calls().get_real(instance_, vr.data(), vr.size(), v.data()) == fmi2OK);
    return v;
  }
  void step(const std::vector<fmi2ValueReference>& vr, const std::vector<double>& u, double t,
            double h) {
    REQUIRE(library_.calls().set_real(instance_, vr.data(), vr.size(), u.data()) == fmi2OK);
    REQUIRE(library_.calls().do_step(instance_, t, h, fmi2True) == fmi2OK);
  }
  fmi2Status raw_step(double t, double h) { return library_.calls().do_step(instance_, t, h, 1); }
  const controller::fmu::FmuDescription& description() const { return description_; }

 private:
  static void logger(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String,
                     ...) {}
  fmi2CallbackFunctions callbacks_{logger, nullptr, nullptr, nullptr, nullptr};
  controller::fmu::FmuDirectory dir_;
  controller::fmu::FmuDescription description_;
  controller::fmu::FmuLibrary library_;
  fmi2Component instance_ = nullptr;
};

struct Channels {
  std::vector<fmi2ValueReference> actuators, sensors, performance;
};

Channels channels_of(const artefact::LoopArtefact& a, const PlantFmuHarness& h) {
  Channels c;
  for (const auto& n : a.names(a.channels.actuators))
    c.actuators.push_back(h.reference("actuator." + n, "input"));
  for (const auto& n : a.names(a.channels.sensors))
    c.sensors.push_back(h.reference("sensor." + n, "output"));
  for (const auto& n : a.names(a.channels.performance))
    c.performance.push_back(h.reference("performance." + n, "output"));
  return c;
}

std::string exported(const artefact::LoopArtefact& a, const fs::path& dir) {
  const fs::path fmu = dir / (a.name + ".fmu");
  pipeline::export_plant_fmu(a, FLEXLOOP_PLANT_FMU_LIBRARY, fmu);
  return fmu.string();
}

sim::RunSettings settings(const artefact::LoopArtefact& a, long steps) {
  sim::RunSettings s;
  s.dt = a.dt();
  s.steps = steps;
  s.log_every = 1;
  return s;
}

// Largest |fmu - sim| over the run against the largest |sim|, for the sensors and the
// performance sensors (the log's columns: t, floor, performance, performance sensors, sensors,
// commands).
struct Agreement {
  double sensors = 0, performance = 0, largest_sensor = 0, largest_performance = 0;
  void add(const std::vector<double>& fmu, const Eigen::VectorXd& sim, bool sensor) {
    for (std::size_t i = 0; i < fmu.size(); ++i) {
      const double d = std::abs(fmu[i] - sim(static_cast<Eigen::Index>(i)));
      const double m = std::abs(sim(static_cast<Eigen::Index>(i)));
      (sensor ? sensors : performance) = std::max(sensor ? sensors : performance, d);
      (sensor ? largest_sensor : largest_performance) =
          std::max(sensor ? largest_sensor : largest_performance, m);
    }
  }
};

void check_open_loop(const std::string& scene, std::optional<artefact::PlantForm> form,
                     long steps) {
  const auto a = scene::load_loop(scene, {.rate_hz = 0, .form = form, .duration_s = 0});
  test::TemporaryDirectory dir;
  PlantFmuHarness fmu(exported(a, dir.path), false);
  const Channels c = channels_of(a, fmu);
  sim::SceneRunOptions o;
  o.log_off = true;
  const auto off = sim::run_artefact(a, settings(a, steps), o).off;
  const Eigen::Index nw = a.disturbances(), nz = a.performance(), ns = a.sensors();
  const std::vector<double> zero(c.actuators.size(), 0.0);
  Agreement agree;
  for (long k = 0; k < steps; ++k) {
    if (k > 0) fmu.step(c.actuators, zero, static_cast<double>(k - 1) * a.dt(), a.dt());
    const Eigen::VectorXd row = off.log.matrix().row(k).transpose();
    agree.add(fmu.get(c.sensors), row.segment(1 + nw + 2 * nz, ns), true);
    agree.add(fmu.get(c.performance), row.segment(1 + nw + nz, nz), false);
  }
  INFO(scene << ": sensors " << agree.sensors << " of " << agree.largest_sensor << ", performance "
             << agree.performance << " of " << agree.largest_performance);
  CHECK(agree.largest_sensor > 0);
  CHECK(agree.largest_performance > 0);
  CHECK(agree.sensors <= 1e-12 * agree.largest_sensor);
  CHECK(agree.performance <= 1e-12 * agree.largest_performance);
}

}  // namespace

TEST_CASE("The exported plant FMU equals sim's open loop from its stationary start", "[fmu]") {
  check_open_loop("tools/scenes/payload_bipods.toml", std::nullopt, 5000);  // 8 actuators
  check_open_loop("tools/scenes/flexible_arm.toml", artefact::PlantForm::kModal, 5000);
  check_open_loop("tools/scenes/metrology_frame_all_effects.toml", std::nullopt, 5000);
}

TEST_CASE("The exported plant FMU closed by the built-in PI from rest equals sim's closed loop",
          "[fmu]") {
  const auto a = scene::load_loop("tools/scenes/metrology_frame_all_effects.toml");
  REQUIRE(a.controller == artefact::ControllerKind::kPiForceFeedback);
  test::TemporaryDirectory dir;
  PlantFmuHarness fmu(exported(a, dir.path), true);
  const Channels c = channels_of(a, fmu);
  constexpr long kSteps = 10000;
  sim::SceneRunOptions o;
  o.start = sim::StartKind::kRest;
  o.log_on = true;
  const auto on = sim::run_artefact(a, settings(a, kSteps), o).on;
  auto pi = controller::runtime::GeneralPiController<double>::from_parameters(a.pi, a.actuators());
  const Eigen::Index nw = a.disturbances(), nz = a.performance(), ns = a.sensors(),
                     nc = a.actuators();
  Agreement agree;
  double commands = 0, largest_command = 0;
  for (long k = 0; k < kSteps; ++k) {
    const std::vector<double> y = fmu.get(c.sensors);
    const Eigen::VectorXd row = on.log.matrix().row(k).transpose();
    agree.add(y, row.segment(1 + nw + 2 * nz, ns), true);
    agree.add(fmu.get(c.performance), row.segment(1 + nw + nz, nz), false);
    const auto& u = pi.step(Eigen::Map<const Eigen::VectorXd>(y.data(), ns));
    const Eigen::VectorXd sim_u = row.tail(nc);
    commands = std::max(commands, (u - sim_u).cwiseAbs().maxCoeff());
    largest_command = std::max(largest_command, sim_u.cwiseAbs().maxCoeff());
    fmu.step(c.actuators, std::vector<double>(u.data(), u.data() + nc),
             static_cast<double>(k) * a.dt(), a.dt());
  }
  INFO("sensors " << agree.sensors << " of " << agree.largest_sensor << ", commands " << commands
                  << " of " << largest_command);
  CHECK(largest_command > 0);
  CHECK(agree.sensors <= 1e-12 * agree.largest_sensor);
  CHECK(agree.performance <= 1e-12 * agree.largest_performance);
  CHECK(commands <= 1e-12 * largest_command);
}

TEST_CASE("The plant FMU refuses a step other than its period and a wrong GUID", "[fmu]") {
  const auto a = scene::load_loop("tools/scenes/two_mass_chain.toml");
  test::TemporaryDirectory dir;
  const std::string file = exported(a, dir.path);
  {
    PlantFmuHarness fmu(file, false);
    CHECK(fmu.raw_step(0, 2 * a.dt()) == fmi2Error);
    CHECK(fmu.description().step_size == a.dt());
    CHECK_FALSE(fmu.description().variable_step);
  }
  {
    PlantFmuHarness fmu(file, false);  // a refused call leaves the instance in the error state
    CHECK(fmu.raw_step(0, a.dt()) == fmi2OK);
  }
  const controller::fmu::FmuDirectory unpacked(file);
  const controller::fmu::FmuLibrary library(unpacked.path(), "flexloop_plant", file);
  const fmi2CallbackFunctions callbacks{nullptr, nullptr, nullptr, nullptr, nullptr};
  const std::string resources = "file://" + (unpacked.path() / "resources").string();
  CHECK(library.calls().instantiate("wrong", fmi2CoSimulation, "{another-guid}", resources.c_str(),
                                    &callbacks, 0, 0) == nullptr);
  CHECK(library.calls().instantiate(
            "wrong", fmi2ModelExchange,
            controller::fmu::read_fmu_description(unpacked.path(), file).guid.c_str(),
            resources.c_str(), &callbacks, 0, 0) == nullptr);
}

TEST_CASE("export-fmu leaves nothing behind when it cannot write", "[fmu]") {
  const auto a = scene::load_loop("tools/scenes/two_mass_chain.toml");
  test::TemporaryDirectory dir;
  CHECK_THROWS_AS(pipeline::export_plant_fmu(a, dir.path / "missing.so", dir.path / "p.fmu"),
                  common::InputError);
  CHECK_THROWS_AS(
      pipeline::export_plant_fmu(a, FLEXLOOP_PLANT_FMU_LIBRARY, dir.path / "no/such/dir/p.fmu"),
      common::InputError);
  CHECK(fs::is_empty(dir.path));
}
