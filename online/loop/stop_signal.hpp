// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// SIGINT / SIGTERM as a request to finish the loop cleanly (and still report): the handler only
// sets a flag (async-signal-safe); the loop reads it once per cycle. Installed without
// SA_RESTART, so a blocking wait returns early (the waits retry on EINTR and then see the flag).
namespace flexloop::loop {

/// Installs the handlers and clears the flag (set-up).
void install_stop_handlers();
/// True once SIGINT or SIGTERM arrived. noexcept, allocation-free.
bool stop_requested() noexcept;

}  // namespace flexloop::loop
