// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Where the loop's LCM traffic may go (the LCM traffic rule of doc/testing.md):
//   - the private loopback-only namespace of tools/netns-run, with ttl=0 (the default), or
//   - a private link: a namespace whose only interfaces are loopback and one veth (the two-host
//     test, tests/hil/veth_loop.sh), whose IPv4 addresses are all private (RFC 1918) and IPv6
//     ones link-local only, with
//     ttl <= 1 so that nothing is forwarded beyond the link.
// enter_private_loopback_namespace() does in-process what tools/netns-run does (for
// `flexloop hil --netns` and the timing tests): unshare(CLONE_NEWNET) -- the calling thread and
// the processes it forks afterwards -- then lo up with multicast on, 224.0.0.0/4 routed to lo,
// and LCM_DEFAULT_URL set to the ttl=0 URL. Needs CAP_SYS_ADMIN (root). Set-up only.
#include <string>

namespace flexloop::loop {

/// Throws std::runtime_error saying what failed (e.g. no permission to unshare).
void enter_private_loopback_namespace();

/// link empty: rt::require_private_loopback_namespace(who). Otherwise the interfaces must be
/// exactly lo and `link`, `link` a veth with only private IPv4 addresses. std::runtime_error
/// naming what is wrong otherwise.
void require_private_network(const std::string& who, const std::string& link);

/// The URL to use: `given`, else $LCM_DEFAULT_URL, else the ttl=0 loopback URL (no link) or the
/// same group with ttl=1 (link). std::runtime_error when its ttl is above 0 (no link) or 1 (link).
std::string loop_lcm_url(const std::string& given, const std::string& link);

}  // namespace flexloop::loop
