#!/usr/bin/env bash
# The command line's contract: good input writes the artefact and exits 0; bad input exits 2
# with "file:line: what is wrong" (or the channel name) and leaves no file behind.
set -uo pipefail
flexloop=$1
root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$flexloop" linearise "$root/tools/models/cart.toml" -i acc:x.1 -i vel:x.1 -i pos:x.1 -O pos:x.2 -o "$tmp/cart.json" >/dev/null ||
  fail "linearise cart"
grep -q '"natural_frequencies_hz"' "$tmp/cart.json" || fail "cart.json lacks natural_frequencies_hz"
grep -q '"source_sha256"' "$tmp/cart.json" || fail "cart.json lacks provenance"

printf '[model]\ndimension = 2\n[[node]]\nid = "1"\nposition = [0.0]\n' >"$tmp/bad.toml"
out=$("$flexloop" linearise "$tmp/bad.toml" -o "$tmp/bad.json" 2>&1); rc=$?
[[ $rc -eq 2 ]] || fail "bad model: exit $rc, expected 2 ($out)"
[[ "$out" == *"bad.toml:5"* && "$out" == *"position"* ]] || fail "bad model message: $out"
[[ ! -e "$tmp/bad.json" ]] || fail "bad model left an output file"

out=$("$flexloop" linearise "$root/tools/models/cart.toml" -i force:nowhere -o "$tmp/x.json" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"force:nowhere"* ]] || fail "bad channel: exit $rc ($out)"
[[ ! -e "$tmp/x.json" ]] || fail "bad channel left an output file"

for cmd in version linearise analyse discretise; do
  "$flexloop" $cmd --help | grep -q "Example" || fail "$cmd --help has no example"
done
echo "cli contract: 8 checks passed"
