// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/superelement_provenance.hpp"

#include <sys/stat.h>

#include <ctime>

namespace flexloop::pipeline {

namespace {

nlohmann::json file_identity(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return {{"path", path}};
  char when[32];
  std::tm utc{};
  ::gmtime_r(&st.st_mtim.tv_sec, &utc);
  std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return {{"path", path}, {"bytes", static_cast<long long>(st.st_size)}, {"modified", when}};
}

}  // namespace

nlohmann::json superelement_provenance(const plant::model::Model& m) {
  if (m.superelements.empty()) return nullptr;
  nlohmann::json out = nlohmann::json::array();
  for (const auto& body : m.superelements) {
    nlohmann::json files = nlohmann::json::array();
    for (const auto& f : body.files) files.push_back(file_identity(f));
    const auto& hz = body.fixed_interface_hz;
    out.push_back({{"id", body.id},
                   {"full_dofs", static_cast<long long>(body.full_dofs)},
                   {"interface_dofs", body.interface_coordinates.size()},
                   {"modes_up_to_hz", body.modes_up_to_hz},
                   {"modes_kept", body.mode_count()},
                   {"fixed_interface_hz", {hz.minCoeff(), hz.maxCoeff()}},
                   {"files", files}});
  }
  return out;
}

}  // namespace flexloop::pipeline
