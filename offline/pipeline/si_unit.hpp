// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The SI unit of a channel (artefact/loop_artefact.hpp's Channel::unit: "m/s^2", "N m", "rad")
// as the exponents of FMI 2.0's BaseUnit (kg, m, s, A, K, mol, cd and rad) and a name in
// Modelica's unit syntax ("m/s2", "N.m"), for the <UnitDefinitions> of an exported plant FMU.
//
// The strings read:   unit    = product { "/" ( factor | "(" product ")" ) }
//                     product = factor { (" " | "." | "*") factor }
//                     factor  = symbol [ ["^"] ["-"] digits ]
// with the symbols kg m s A K mol cd rad, the derived N Pa J W Hz V, and "1" for a dimensionless
// signal; no prefixes (a channel's unit is SI). Every unit flexloop's scenes produce reads
// (offline/scene/loop_artefact_builder.hpp's channel_unit: m, m/s, m/s^2, rad, rad/s, rad/s^2,
// N, N m).
#include <array>
#include <string>

namespace flexloop::pipeline {

struct SiUnit {
  /// FMI 2.0's BaseUnit attribute names, in the order of `exponents`.
  static constexpr std::array<const char*, 8> kBase = {"kg", "m",   "s",  "A",
                                                       "K",  "mol", "cd", "rad"};
  std::string name;  ///< Modelica unit syntax: "m/s2", "N.m", "rad"
  std::array<int, 8> exponents{};
};

/// @throws std::invalid_argument naming the part of `unit` that does not read (an unknown symbol,
/// a prefix, a stray character), with the grammar above.
SiUnit parse_si_unit(const std::string& unit);

}  // namespace flexloop::pipeline
