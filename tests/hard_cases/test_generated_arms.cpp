// SPDX-License-Identifier: BSD-3-Clause
// Hard cases at size (issue 57): every flexible arm that tools/models/make_flexible_arm.py writes,
// 10 to 100 beams, builds, dense and modal, into an artefact that its own reader takes back, and
// runs. These plants carry the floor's double integrators and bending pairs that sit 1e-10 to 1e-7
// inside the unit circle at 10 kHz (the struts' damping at the root is all the arm has).
//
// References, none of them the code under test's own figure:
// - the Lyapunov equation itself: the start's covariance P of the part inside the circle and the
//   noise of that part G (the spectral projector times the noise) satisfy P = A P A^T + G G^T; its
//   normwise residual |A P A^T - P + G G^T| / (|A P A^T| + |P| + |G G^T|) is at most 1e-10;
// - positive semidefinite: the stored covariance (given the floor filters) has no eigenvalue
//   below -1e-12 of its largest (the reader refuses below -1e-9);
// - the modes on the circle: as many as Eigen's eigenvalues of the balanced loop matrix with
//   |1 - |lambda|| <= 1e-9 (an eigensolver other than the split's LAPACK dgees), and the note
//   says that many start at zero.
// Under the sanitizers three arms (10, 50, 100 beams) stand for the ten.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "artefact/loop_artefact.hpp"
#include "common/address_sanitizer.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/loop_start_builder.hpp"
#include "online/sim/scene_runs.hpp"
#include "plant/lti/frequency_response.hpp"

using namespace flexloop;

namespace {

std::filesystem::path generated_arm(int beams) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("flexloop_generated_arm_" + std::to_string(beams));
  const std::string command = "/usr/bin/python3 tools/models/make_flexible_arm.py --elements " +
                              std::to_string(beams) + " -o " + dir.string() + " > /dev/null";
  REQUIRE(std::system(command.c_str()) == 0);
  return dir / "scene.toml";
}

double lyapunov_residual(const scene::StationaryLoop& s) {
  const Eigen::MatrixXd& P = s.stable.P;
  const Eigen::MatrixXd APA = s.A * P * s.A.transpose();
  const Eigen::MatrixXd GG = s.stable.stable_noise * s.stable.stable_noise.transpose();
  return (APA - P + GG).norm() / (APA.norm() + P.norm() + GG.norm());
}

Eigen::Index modes_on_circle(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd t = plant::lti::balancing_scaling(A);
  const Eigen::EigenSolver<Eigen::MatrixXd> es(t.cwiseInverse().asDiagonal() * A * t.asDiagonal(),
                                               false);
  Eigen::Index count = 0;
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    if (std::abs(1 - std::abs(es.eigenvalues()(i))) <= 1e-9) ++count;
  return count;
}

double smallest_over_largest_eigenvalue(const Eigen::MatrixXd& P) {
  const Eigen::VectorXd l =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P, Eigen::EigenvaluesOnly).eigenvalues();
  return l(0) / l(l.size() - 1);
}

std::vector<int> arm_sizes() {
#if defined(FLEXLOOP_ADDRESS_SANITIZER)
  return {10, 50, 100};
#else
  return {10, 20, 30, 40, 50, 60, 70, 80, 90, 100};
#endif
}

}  // namespace

TEST_CASE("generated arms of 10 to 100 beams build, read back and run, dense and modal",
          "[hard_cases][size]") {
  for (const int beams : arm_sizes()) {
    CAPTURE(beams);
    const auto scene_file = generated_arm(beams);
    for (const auto form : {artefact::PlantForm::kDense, artefact::PlantForm::kModal}) {
      CAPTURE(artefact::to_string(form));
      const auto a = scene::load_loop(scene_file, {.rate_hz = 0, .form = form, .duration_s = 0});
      const auto file = scene_file.parent_path() / ("loop_" + artefact::to_string(form) + ".json");
      artefact::write_loop_artefact(file, a);
      const auto b = artefact::read_loop_artefact(file);
      REQUIRE(b.start.open_loop.exists());
      CHECK(b.start.open_loop.covariance == a.start.open_loop.covariance);
      CHECK(smallest_over_largest_eigenvalue(b.start.open_loop.covariance) >= -1e-12);
      sim::RunSettings settings;
      settings.dt = b.dt();
      settings.steps = 200;
      const auto runs = sim::run_artefact(b, settings, {});
      CHECK(runs.off.rms_performance.allFinite());
      CHECK(!runs.off.divergence.happened());
      if (form == artefact::PlantForm::kModal) continue;
      const auto s = scene::stationary_loop(a, false);
      CHECK(lyapunov_residual(s) <= 1e-10);
      const Eigen::Index on_circle = modes_on_circle(s.A);
      CHECK(s.stable.on_circle == on_circle);
      if (on_circle > 0)
        CHECK(b.start.open_loop.note.find(std::to_string(on_circle) +
                                          " modes on the unit circle") != std::string::npos);
    }
  }
}
