// SPDX-License-Identifier: BSD-3-Clause
#include "tests/campaign/reference.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace flexloop::campaign::test {

nlohmann::json outside_reference(const nlohmann::json& request) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("flexloop_campaign_reference_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path in = dir / "request.json", out = dir / "answer.json";
  std::ofstream(in) << request.dump();
  fs::remove(out);
  const std::string command =
      "/usr/bin/python3 tests/campaign/reference.py '" + in.string() + "' '" + out.string() + "'";
  const int status = std::system(command.c_str());
  if (status != 0)
    throw std::runtime_error("tests/campaign/reference.py failed (status " +
                             std::to_string(status) + ") on task " + request["task"].dump());
  std::ifstream answer(out);
  nlohmann::json j = nlohmann::json::parse(answer);
  fs::remove_all(dir);
  return j;
}

}  // namespace flexloop::campaign::test
