#pragma once
// TEMPORARY (campaign-core's branch): the declarations of CAMPAIGN.md, so that this branch
// compiles before campaign-stats' designs.* is merged. The lead takes campaign-stats' header.
#include <cstdint>
#include <string>
#include <vector>

namespace flexloop::campaign {

enum class DesignKind { kRandom, kLatinHypercube, kSobol, kSaltelli };
DesignKind design_kind_from_name(const std::string& name);
std::string design_name(DesignKind kind);
long evaluation_count(DesignKind kind, long n, int d);
std::vector<double> unit_point(DesignKind kind, long n, int d, std::uint64_t seed, long index);

}  // namespace flexloop::campaign
