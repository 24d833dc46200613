// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// LCM traffic rule: test, demo and benchmark traffic runs only inside a private network
// namespace whose only interface is loopback, with ttl=0. These helpers let a program check
// that before it opens LCM, and give the URL to use there.
#include <string>
#include <vector>

namespace flexloop::rt {

/// LCM URL for the private loopback namespace: multicast that never leaves the host (ttl=0).
inline constexpr const char* kPrivateLoopbackLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

/// Names of the network interfaces visible to this process (in this process's network namespace).
std::vector<std::string> network_interfaces();

/// True when loopback is the only interface: i.e. we run inside the private namespace.
bool only_loopback_present();

/// Throws std::runtime_error naming the extra interfaces unless only loopback is present.
void require_private_loopback_namespace(const std::string& who);

}  // namespace flexloop::rt
