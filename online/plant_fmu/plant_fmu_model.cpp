// SPDX-License-Identifier: BSD-3-Clause
#include "online/plant_fmu/plant_fmu_model.hpp"

#include <utility>

#include "online/sim/loop_hardware.hpp"
#include "online/sim/loop_start.hpp"
#include "plant/runtime/plant_from_artefact.hpp"

namespace flexloop::plant_fmu {

namespace {

template <class Hardware>
class HardwareModel final : public PlantFmuModel {
 public:
  explicit HardwareModel(Hardware hw)
      : hw_(std::move(hw)), u_(Hardware::Command::Zero(hw_.actuators())) {}

  void sample(double* readings) noexcept override {
    const auto& r = hw_.sample();
    const Eigen::Index ns = r.sensors.size(), nz = r.performance.size();
    Eigen::Map<Eigen::VectorXd>(readings, ns) = r.sensors.template cast<double>();
    Eigen::Map<Eigen::VectorXd>(readings + ns, nz) = r.performance.template cast<double>();
  }

  void apply(const double* command) noexcept override {
    u_ = Eigen::Map<const Eigen::VectorXd>(command, u_.size())
             .template cast<typename Hardware::Scalar>();
    hw_.apply(u_);
  }

 private:
  Hardware hw_;
  typename Hardware::Command u_;
};

}  // namespace

std::unique_ptr<PlantFmuModel> PlantFmuModel::from_artefact(const artefact::LoopArtefact& a,
                                                            bool at_rest) {
  constexpr int kAny = Eigen::Dynamic;
  return plant::runtime::with_general_plant<double>(a, [&](auto plant) {
    return sim::with_hardware<kAny, kAny, kAny>(
        a, plant, [&](auto hw) -> std::unique_ptr<PlantFmuModel> {
          plant::runtime::NoEffect no_controller;
          sim::start_loop(a, a.start.open_loop,
                          at_rest ? sim::StartKind::kRest : sim::StartKind::kStationary, hw,
                          no_controller);
          return std::make_unique<HardwareModel<decltype(hw)>>(std::move(hw));
        });
  });
}

}  // namespace flexloop::plant_fmu
