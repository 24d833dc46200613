// SPDX-License-Identifier: BSD-3-Clause
#include "online/loop/private_network.hpp"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <linux/ethtool.h>
#include <linux/sockios.h>
#include <net/if.h>
#include <net/route.h>
#include <netinet/in.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "rt/loopback_guard.hpp"

namespace flexloop::loop {

namespace {

constexpr const char* kLinkLcmUrl = "udpm://239.255.76.67:7667?ttl=1";

std::runtime_error system_error(const std::string& what) {
  return std::runtime_error(what + ": " + std::strerror(errno));
}

// An AF_INET datagram socket for interface ioctls, closed on scope exit.
struct IoctlSocket {
  int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ~IoctlSocket() {
    if (fd >= 0) close(fd);
  }
};

std::string driver_of(const std::string& iface) {
  IoctlSocket s;
  ethtool_drvinfo info{};
  info.cmd = ETHTOOL_GDRVINFO;
  ifreq req{};
  std::strncpy(req.ifr_name, iface.c_str(), IFNAMSIZ - 1);
  req.ifr_data = reinterpret_cast<char*>(&info);
  if (s.fd < 0 || ioctl(s.fd, SIOCETHTOOL, &req) != 0) return "";
  return info.driver;
}

bool is_private_ipv4(in_addr_t address_network_order) {
  const std::uint32_t a = ntohl(address_network_order);
  return (a >> 24) == 10 || (a >> 20) == (172u << 4 | 1u) || (a >> 16) == (192u << 8 | 168u);
}

// Every IPv4 address on `iface` that is not private, as text.
std::string public_addresses_of(const std::string& iface) {
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) throw system_error("getifaddrs");
  std::string bad;
  for (const ifaddrs* it = list; it != nullptr; it = it->ifa_next) {
    if (it->ifa_addr == nullptr || iface != it->ifa_name) continue;
    if (it->ifa_addr->sa_family == AF_INET6) {  // only link-local (fe80::/10) may stay
      const auto* in6 = reinterpret_cast<const sockaddr_in6*>(it->ifa_addr);
      if (!IN6_IS_ADDR_LINKLOCAL(&in6->sin6_addr)) bad += " (an IPv6 address beyond the link)";
      continue;
    }
    if (it->ifa_addr->sa_family != AF_INET) continue;
    const auto* in = reinterpret_cast<const sockaddr_in*>(it->ifa_addr);
    if (!is_private_ipv4(in->sin_addr.s_addr)) bad += std::string(" ") + inet_ntoa(in->sin_addr);
  }
  freeifaddrs(list);
  return bad;
}

int url_ttl(const std::string& url) {
  const auto at = url.find("ttl=");
  return at == std::string::npos ? 0 : std::atoi(url.c_str() + at + 4);
}

}  // namespace

void enter_private_loopback_namespace() {
  if (unshare(CLONE_NEWNET) != 0) throw system_error("cannot enter a new network namespace");
  IoctlSocket s;
  if (s.fd < 0) throw system_error("socket");
  ifreq req{};
  std::strncpy(req.ifr_name, "lo", IFNAMSIZ - 1);
  if (ioctl(s.fd, SIOCGIFFLAGS, &req) != 0) throw system_error("lo: get flags");
  req.ifr_flags = static_cast<short>(req.ifr_flags | IFF_UP | IFF_MULTICAST);
  if (ioctl(s.fd, SIOCSIFFLAGS, &req) != 0) throw system_error("lo: up, multicast");
  rtentry route{};
  auto* dst = reinterpret_cast<sockaddr_in*>(&route.rt_dst);
  auto* mask = reinterpret_cast<sockaddr_in*>(&route.rt_genmask);
  dst->sin_family = mask->sin_family = AF_INET;
  dst->sin_addr.s_addr = htonl(0xE0000000u);   // 224.0.0.0
  mask->sin_addr.s_addr = htonl(0xF0000000u);  // /4
  char lo[] = "lo";
  route.rt_dev = lo;
  route.rt_flags = RTF_UP;
  if (ioctl(s.fd, SIOCADDRT, &route) != 0) throw system_error("route 224.0.0.0/4 dev lo");
  setenv("LCM_DEFAULT_URL", rt::kPrivateLoopbackLcmUrl, 1);
  rt::require_private_loopback_namespace("flexloop hil --netns");
}

void require_private_network(const std::string& who, const std::string& link) {
  if (link.empty()) return rt::require_private_loopback_namespace(who);
  const auto refuse = [&](const std::string& why) {
    throw std::runtime_error(who + ": refusing to send LCM traffic over " + link + ": " + why);
  };
  std::string list;
  for (const auto& n : rt::network_interfaces()) {
    list += " " + n;
    if (n != "lo" && n != link) refuse("other interfaces are visible:" + list);
  }
  if (list != " " + link + " lo" && list != " lo " + link) refuse("interfaces:" + list);
  if (driver_of(link) != "veth") refuse("it is not a veth link");
  if (const std::string bad = public_addresses_of(link); !bad.empty())
    refuse("addresses that are not private:" + bad);
}

std::string loop_lcm_url(const std::string& given, const std::string& link) {
  std::string url = given;
  if (url.empty())
    if (const char* env = std::getenv("LCM_DEFAULT_URL")) url = env;
  if (url.empty()) url = link.empty() ? rt::kPrivateLoopbackLcmUrl : kLinkLcmUrl;
  const int max_ttl = link.empty() ? 0 : 1;
  if (url_ttl(url) > max_ttl)
    throw std::runtime_error("LCM URL " + url + " has ttl " + std::to_string(url_ttl(url)) +
                             ", at most " + std::to_string(max_ttl) + " is allowed here");
  return url;
}

}  // namespace flexloop::loop
