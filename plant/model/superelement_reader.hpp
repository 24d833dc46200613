// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// [[superelement]] tables of a model file (doc/model_format.md): each body's FE files read and
// reduced (plant/superelement), and its interface nodes as model nodes. The model reader adds the
// nodes and places the interface rows on their coordinates.
#include <toml++/toml.h>
#include <string>
#include <vector>

#include "common/toml_reader.hpp"
#include "plant/model/model.hpp"

namespace flexloop::plant::model {

struct SuperelementTable {
  Superelement body;  // interface_coordinates left for the model reader to fill
  std::vector<Node> interface_nodes;
  // Per reduced interface row: the index in interface_nodes and the coordinate's offset in the
  // node (0 x, 1 y, 2 z; a pad's rotations: 4..6, its Euler parameters l1..l3).
  std::vector<std::pair<int, int>> interface_rows;
};

/// The band (Hz) up to which this process's reductions also keep what they leave out (the unkept
/// modes' moments, plant/superelement/residual_moments.hpp: a few more solves on the reduction's
/// factor), for `analyse`'s reduction error; 0, the default: nothing, at no cost. Returns the
/// band before.
double set_reduction_error_band_hz(double band_hz);

/// The [[superelement]] tables in file order (none when the model has none).
/// @throws common::InputError naming the model file's entry, or the FE file and line.
std::vector<SuperelementTable> read_superelement_tables(const toml::table& root,
                                                        const common::TomlReader& top,
                                                        const Model& m);

}  // namespace flexloop::plant::model
