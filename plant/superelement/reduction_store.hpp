// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A folder where reductions outlive their process (issue 58): a campaign's plan reduces a
// superelement once and its shards, local or on Slurm nodes sharing the folder, read the result
// instead of reducing again. One binary file per request, named by a hash of the request's key
// and carrying the key itself: a file whose key, format or sizes disagree is not used (the body is
// reduced again and the file written anew), so a stale or damaged file costs time, never a wrong
// body. Written atomically: a reader never sees half of one.
#include <memory>
#include <string>

#include "plant/superelement/superelement_files.hpp"

namespace flexloop::plant::superelement {

/// The process's store: reductions are looked up in and written to `folder` ("" : none, the
/// default). Set before models are read; not thread-safe against concurrent reads of models.
void set_reduction_store(const std::string& folder);
const std::string& reduction_store();

/// The stored reduction for `key`, or null when the store has none (or none that reads back whole
/// with this key).
std::shared_ptr<const ReducedSuperelement> load_stored_reduction(const std::string& key);

/// Stores `r` under `key` (nothing without a store, or for a reduction that carries the unkept
/// modes' moments: those are asked by `analyse` alone, which keeps no store). @throws
/// std::runtime_error when the file cannot be written.
void store_reduction(const std::string& key, const ReducedSuperelement& r);

}  // namespace flexloop::plant::superelement
