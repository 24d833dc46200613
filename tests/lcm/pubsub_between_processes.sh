#!/usr/bin/env bash
# Run inside tools/netns-run: one process listens, another publishes; the listener must get
# every sample intact.
# SPDX-License-Identifier: BSD-3-Clause
set -euo pipefail
probe=$1
n=200
fifo=$(mktemp -u); mkfifo "$fifo"
"$probe" listen "$n" 5000 >"$fifo" &
listener=$!
exec 3<"$fifo"; rm -f "$fifo"
read -r -t 5 line <&3 || { echo "listener did not start"; exit 1; }
[[ "$line" == ready ]] || { echo "unexpected: $line"; exit 1; }
"$probe" publish "$n"
status=0; wait "$listener" || status=$?
cat <&3
exit "$status"
