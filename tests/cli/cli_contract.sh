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

# The metrology frame's fit reruns and reproduces the committed model file exactly.
"$flexloop" fit-metrology -o "$tmp/metrology_frame.toml" >/dev/null || fail "fit-metrology"
diff -q "$tmp/metrology_frame.toml" "$root/tools/models/metrology_frame.toml" >/dev/null ||
  fail "fit-metrology does not reproduce tools/models/metrology_frame.toml"

# A scene: analyse writes its report; a bad scene exits 2 naming file:line, writing nothing.
"$flexloop" analyse "$root/tools/scenes/metrology_frame.toml" --points 40 --out-dir "$tmp/metro" >/dev/null ||
  fail "analyse metrology scene"
for f in analysis.json singular_values.csv singular_values.png transmissibility.png; do
  [[ -s "$tmp/metro/$f" ]] || fail "analyse scene did not write $f"
done
sed 's/^zeta = 0.5/zeta = -1/' "$root/tools/scenes/metrology_frame.toml" >"$tmp/bad_scene.toml"
sed -i "s#\.\./models/#$root/tools/models/#" "$tmp/bad_scene.toml"
out=$("$flexloop" analyse "$tmp/bad_scene.toml" --out-dir "$tmp/bad_scene" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"bad_scene.toml:"* && "$out" == *"zeta"* ]] || fail "bad scene: exit $rc ($out)"
[[ ! -e "$tmp/bad_scene/analysis.json" ]] || fail "bad scene left an output file"

# sim on the default scene: prints the isolation (controller off vs on), writes the log and PNGs.
out=$("$flexloop" sim "$root/tools/scenes/metrology_frame.toml" --duration 1 --log "$tmp/sim/log.csv" --plots "$tmp/sim" 2>&1) ||
  fail "sim default scene: $out"
[[ "$out" == *"controller off   controller on"* && "$out" == *"dB"* ]] || fail "sim summary: $out"
for f in log.csv time_series.png spectra.png; do [[ -s "$tmp/sim/$f" ]] || fail "sim did not write $f"; done

for cmd in version linearise analyse discretise fit-metrology sim hil plant controller baseline; do
  "$flexloop" $cmd --help | grep -q "Example" || fail "$cmd --help has no example"
done
echo "cli contract: 14 checks passed"
