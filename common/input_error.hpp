// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The one error type for bad user input (model, scene, artefact files): it carries the place
// (file:line or file:field) so the command line can print `place: what is wrong` and exit 2.
#include <stdexcept>
#include <string>

namespace flexloop::common {

class InputError : public std::runtime_error {
 public:
  InputError(std::string place, const std::string& what)
      : std::runtime_error(place.empty() ? what : place + ": " + what), place_(std::move(place)) {}
  const std::string& place() const { return place_; }

 private:
  std::string place_;
};

}  // namespace flexloop::common
