// SPDX-License-Identifier: BSD-3-Clause
#include "rt/loopback_guard.hpp"

#include <net/if.h>

#include <algorithm>
#include <stdexcept>

namespace flexloop::rt {

std::vector<std::string> network_interfaces() {
  // if_nameindex asks the kernel over netlink, so it sees this process's network namespace
  // (sysfs would show the namespace that mounted it).
  std::vector<std::string> names;
  if (struct if_nameindex* list = if_nameindex()) {
    for (const struct if_nameindex* it = list; it->if_index != 0; ++it)
      names.emplace_back(it->if_name);
    if_freenameindex(list);
  }
  std::sort(names.begin(), names.end());
  return names;
}

bool only_loopback_present() {
  const auto names = network_interfaces();
  return names.size() == 1 && names.front() == "lo";
}

void require_private_loopback_namespace(const std::string& who) {
  if (only_loopback_present()) return;
  std::string list;
  for (const auto& n : network_interfaces()) list += (list.empty() ? "" : ", ") + n;
  throw std::runtime_error(
      who + ": refusing to send LCM traffic: interfaces other than loopback are visible (" + list +
      "); run inside the private namespace: tools/netns-run -- <command>");
}

}  // namespace flexloop::rt
