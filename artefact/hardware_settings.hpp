// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The simulated hardware a loop runs with (doc/design.md §6): the floor excitation and the effects
// a scene switches on. Written by the scene file (offline/scene), carried by the loop artefact
// (loop_artefact.hpp) to the online programs, which compose the hardware from it.
#include <cstdint>
#include <string>

#include "artefact/loop_schema.hpp"

namespace flexloop::artefact {

/// The order of the floor's discrete shaping filter an artefact carries (the online floor
/// generator is compiled for it).
inline constexpr int kFloorFilterOrder = 9;

/// Stationary random floor acceleration on every disturbance input.
struct FloorSettings {
  FloorSpectrum spectrum = FloorSpectrum::kWhite;
  double rms_mps2 = 1e-3;  ///< white only: per channel
  std::uint64_t seed = 1;
};

/// Piezo actuator: command -> force with gain, saturation and an optional first-order lag.
struct ActuatorEffect {
  bool present = false;
  double gain = 1.0;
  double force_limit_n = 0;  ///< |force| <= limit
  double lag_s = 0;          ///< time constant; 0: no lag
};

/// A sensor: gain error, white noise, ADC (bits over a full-scale range), delay in samples.
struct SensorEffect {
  bool present = false;
  double gain_error = 0;
  double noise_rms = 0;  ///< SI units of the signal
  int adc_bits = 16;
  double adc_range = 0;  ///< full-scale range (span), SI
  int delay_samples = 0;
  std::uint64_t seed = 2;
};

/// The simulated hardware; every effect is off unless present. `force_sensor` acts on the sensor
/// channels, `accelerometer` on the performance channels (the metrology frame's names).
struct EffectsSettings {
  ActuatorEffect actuator;
  SensorEffect force_sensor, accelerometer;
  int transport_delay_samples = 0;  ///< plant -> controller, in samples; 0: none
};

inline bool has_effects(const EffectsSettings& e) {
  return e.actuator.present || e.force_sensor.present || e.accelerometer.present ||
         e.transport_delay_samples > 0;
}

}  // namespace flexloop::artefact
