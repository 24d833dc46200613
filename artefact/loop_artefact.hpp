// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The discrete loop artefact: the one seam between the offline pipeline and the online programs
// (doc/design.md §1). `flexloop build SCENE -o LOOP.json` writes it once; `flexloop sim`, the plant
// and the controller processes run from it and never read a model or a scene. It holds
// everything a run needs: the discrete plant, the channel map (names, units, order), rate and
// method, the controller, the floor (with its discrete shaping filter), the hardware effects, the
// run's duration, and where it came from. The file format (plain JSON, versioned) is documented
// in doc/loop_artefact.md; readers in any language can use it.
//
// Sizes: nw disturbances, nc actuators, nz performance outputs, ns sensors (each 1 .. 64);
// the plant's inputs are [disturbances; actuators] and its outputs [performance; sensors].
#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "artefact/fmu_parameters.hpp"
#include "artefact/hardware_settings.hpp"
#include "artefact/loop_schema.hpp"
#include "artefact/loop_start.hpp"
#include "artefact/pi_parameters.hpp"
#include "artefact/state_space_parameters.hpp"
#include "numeric/channel_limits.hpp"

namespace flexloop::artefact {

/// The format this build reads and writes.
inline constexpr int kLoopArtefactVersion = 1;
inline constexpr const char* kLoopArtefactFormat = "flexloop loop artefact";

struct Channel {
  std::string name;  ///< the model's channel name, e.g. "acc:x.3", "stress:e1.4"
  std::string unit;  ///< SI unit of the signal, e.g. "m/s^2", "N"
};

struct ChannelMap {
  std::vector<Channel> disturbances, actuators, performance, sensors;
};

enum class ControllerKind { kNone, kPiForceFeedback, kStateSpace, kFmu };

/// "none", "pi_force_feedback", "state_space", "fmu".
std::string to_string(ControllerKind kind);

struct Provenance {
  std::string scene, scene_sha256, model, model_sha256;
  std::string flexloop_version, flexloop_git;
};

/// The discrete plant x+ = A x + B [w; u], [z; y] = C x + D [w; u], in the dense form, and the
/// modal form when the scene asks for it (modal_form.hpp of plant/lti made it).
struct DiscretePlant {
  PlantForm form = PlantForm::kDense;  ///< the form the online side steps
  Eigen::MatrixXd A, B, C, D;
  std::vector<std::string> states;
  double spectral_radius = 0;
  struct Modal {
    Eigen::MatrixXd Lambda_minus_I, B, C, D, T;
  } modal;  ///< filled for the modal form
};

/// The floor's shaping filter, discrete at the loop's rate (one per channel, driven by unit white
/// noise) and the rows that give the floor's velocity and displacement from its state.
struct FloorFilter {
  Eigen::MatrixXd A, B, C, D;
  Eigen::MatrixXd motion;  ///< 2 x order: velocity, displacement
};

struct LoopArtefact {
  std::string name;
  std::string source;  ///< where it came from (its file, or the scene it was built from): messages
  Provenance provenance;
  double rate_hz = 0;
  DiscretisationMethod method = DiscretisationMethod::kZeroOrderHold;
  double prewarp_hz = 0;
  ChannelMap channels;
  DiscretePlant plant;
  ControllerKind controller = ControllerKind::kNone;
  artefact::PiParameters pi;  ///< kPiForceFeedback: at dt = 1 / rate_hz
  /// kStateSpace: discrete at dt = 1 / rate_hz, sensors in, actuators out (channel map order)
  artefact::StateSpaceParameters state_space;
  artefact::FmuParameters fmu;  ///< kFmu: the FMU and how the loop connects it
  FloorSettings floor;
  FloorFilter floor_filter;  ///< empty for a white floor
  EffectsSettings effects;
  LoopStart start;  ///< the stationary starts (artefact/loop_start.hpp)
  double duration_s = 10;

  double dt() const { return 1.0 / rate_hz; }
  Eigen::Index disturbances() const {
    return static_cast<Eigen::Index>(channels.disturbances.size());
  }
  Eigen::Index actuators() const { return static_cast<Eigen::Index>(channels.actuators.size()); }
  Eigen::Index performance() const {
    return static_cast<Eigen::Index>(channels.performance.size());
  }
  Eigen::Index sensors() const { return static_cast<Eigen::Index>(channels.sensors.size()); }
  std::vector<std::string> names(const std::vector<Channel>& kind) const;
};

/// A plant state that is the floor's own motion: a gravity-preloaded plant has the floor's
/// position "pos:<c>" and velocity "vel:<c>" for a disturbance "acc:<c>" among its states.
struct FloorState {
  Eigen::Index state;    ///< row of the plant state
  Eigen::Index channel;  ///< the disturbance channel
  int motion_row;        ///< row of FloorFilter::motion: 0 velocity, 1 displacement
};
std::vector<FloorState> floor_states(const LoopArtefact& a);

/// Rows of a stationary start (loop_start.hpp) for this artefact.
Eigen::Index start_rows(const LoopArtefact& a, const StationaryStart& s);

/// The artefact as JSON (doc/loop_artefact.md). @throws std::invalid_argument for an artefact
/// that does not validate (validate()).
nlohmann::json to_json(const LoopArtefact& a);

/// @throws flexloop::InputError "<place>: key '...': what is wrong" for a wrong format or
/// version, sizes that do not close, non-finite entries, an unknown kind or out-of-range values.
LoopArtefact loop_artefact_from_json(const nlohmann::json& j, const std::string& place);

/// @throws flexloop::InputError naming the file (see loop_artefact_from_json).
LoopArtefact read_loop_artefact(const std::filesystem::path& file);

/// What a command line may ask of the loop it runs.
struct LoopOverrides {
  double rate_hz = 0;  ///< > 0: this rate (a scene is sampled at it; an artefact must have it)
  std::optional<PlantForm> form;  ///< none: dense (a scene), as built (an artefact)
  double duration_s = 0;          ///< > 0: instead of the scene's or artefact's duration
};

/// An artefact file for a command: read, with the duration overridden. An artefact's rate and
/// form are fixed: @throws flexloop::InputError naming the file when `o` asks for others (rebuild
/// it), or when the file is not a loop artefact (build one: flexloop build SCENE -o LOOP.json).
LoopArtefact read_loop_artefact(const std::filesystem::path& file, const LoopOverrides& o);

/// Writes atomically (a reader never sees half of it), after reading the JSON back with
/// loop_artefact_from_json: an artefact its own reader refuses is not written. @throws
/// std::runtime_error (the reader's reason, naming the file and key, for such an artefact).
void write_loop_artefact(const std::filesystem::path& file, const LoopArtefact& a);

/// True when the file is a loop artefact (a JSON object with "format" = kLoopArtefactFormat),
/// so a command can take a scene or an artefact.
bool is_loop_artefact_file(const std::filesystem::path& file);

/// Checks what the JSON reader checks, for artefacts built in memory.
/// @throws std::invalid_argument naming what is wrong.
void validate(const LoopArtefact& a);

}  // namespace flexloop::artefact
