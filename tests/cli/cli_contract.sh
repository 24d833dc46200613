#!/usr/bin/env bash
# The command line's contract: good input writes the artefact and exits 0; bad input exits 2
# with "file:line: what is wrong" (or the channel name) and leaves no file behind.
# SPDX-License-Identifier: BSD-3-Clause
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

# The metrology frame's fit reruns and reproduces the committed model file: the same text, every
# number to 1e-12 relative (the last digit of a 17-digit number depends on whether the building
# machine fuses multiply-adds).
"$flexloop" fit-metrology -o "$tmp/metrology_frame.toml" >/dev/null || fail "fit-metrology"
python3 - "$tmp/metrology_frame.toml" "$root/tools/models/metrology_frame.toml" <<'PY' ||
import re, sys
number = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
a, b = (open(f).read().splitlines() for f in sys.argv[1:3])
ok = len(a) == len(b)
for x, y in zip(a, b):
    xs, ys = number.split(x), number.split(y)
    xn, yn = [float(v) for v in number.findall(x)], [float(v) for v in number.findall(y)]
    if xs != ys or len(xn) != len(yn) or any(abs(u - v) > 1e-12 * max(abs(u), abs(v), 1e-300)
                                              for u, v in zip(xn, yn)):
        print(f"differs:\n  {x}\n  {y}")
        ok = False
sys.exit(0 if ok else 1)
PY
  fail "fit-metrology does not reproduce tools/models/metrology_frame.toml (to 1e-12)"

# A scene: analyse writes its report; a bad scene exits 2 naming file:line, writing nothing.
"$flexloop" analyse "$root/tools/scenes/metrology_frame.toml" --points 40 --out-dir "$tmp/metro" >/dev/null ||
  fail "analyse metrology scene"
for f in analysis.json singular_values.csv singular_values.png transmissibility.png; do
  [[ -s "$tmp/metro/$f" ]] || fail "analyse scene did not write $f"
done
# Every shipped scene, with a controller or without one: analyse exits 0 and reports the numerical
# health (printed and in analysis.json).
for scene in "$root"/tools/scenes/*.toml; do
  grep -q '^\[scene\]' "$scene" || continue  # not a scene: a campaign's uncertain parameters
  name=$(basename "$scene" .toml)
  out=$("$flexloop" analyse "$scene" --points 20 --out-dir "$tmp/analyse_$name" 2>&1) || fail "analyse $name: $out"
  [[ "$out" == *"numerical health:"* ]] || fail "analyse $name prints no numerical health: $out"
  grep -q '"numerical_health"' "$tmp/analyse_$name/analysis.json" || fail "analyse $name: analysis.json lacks numerical_health"
  # Every shipped scene is stable: a negative damping could only be an integrator's round-off
  # (plant/lti/pole_text.hpp prints those as integrators).
  [[ "$out" != *"damping -"* ]] || fail "analyse $name prints a negative damping: $out"
done
# A column beyond buckling: build refuses it at the scene's model line, naming the buckling
# multiplier, and writes nothing; analyse reports it.
column="$root/tests/fixtures/buckled_column.toml"
line=$(grep -n '^model' "$column" | cut -d: -f1)
out=$("$flexloop" build "$column" -o "$tmp/column.json" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"buckled_column.toml:$line"* && "$out" == *"buckling multiplier"* && "$out" == *"statically unstable"* ]] ||
  fail "column beyond buckling: exit $rc ($out)"
[[ ! -e "$tmp/column.json" ]] || fail "column beyond buckling left an artefact"
out=$("$flexloop" analyse "$column" --points 20 --out-dir "$tmp/column" 2>&1) || fail "analyse column: $out"
[[ "$out" == *"passive plant: UNSTABLE"* ]] || fail "analyse column does not report the instability: $out"
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
# The same log in binary (.mat): the same rows and columns, read back by scipy; another
# extension is refused before the run.
out=$("$flexloop" sim "$root/tools/scenes/metrology_frame.toml" --duration 1 --log "$tmp/sim/log.mat" 2>&1) ||
  fail "sim --log .mat: $out"
[[ ! -e "$tmp/sim/log.mat.tmp" ]] || fail "sim --log .mat left its staged file"
/usr/bin/python3 - "$tmp/sim/log.csv" "$tmp/sim/log.mat" <<'PY' || fail "sim .mat log differs from its CSV"
import sys, numpy, scipy.io
csv = numpy.genfromtxt(sys.argv[1], delimiter=",", skip_header=1)
mat = scipy.io.loadmat(sys.argv[2])
header = open(sys.argv[1]).readline().strip().split(",")
names = [str(c[0]) for c in mat["columns"][0]]
assert mat["data"].shape == csv.shape, (mat["data"].shape, csv.shape)
assert names == [h.strip('"') for h in header], (names[:3], header[:3])
assert numpy.array_equal(mat["data"], csv), abs(mat["data"] - csv).max()
PY
# flexloop log converts either table into the other, every sample and every column: the .mat
# back to text byte for byte the sim's own CSV, the CSV back to binary bit for bit its .mat
# (10 000 rows: 1 s at 10 kHz, none dropped); a row that is not numbers is refused at its line.
out=$("$flexloop" log "$tmp/sim/log.mat" -o "$tmp/sim/back.csv" 2>&1) || fail "flexloop log .mat: $out"
[[ "$out" == *"10000 rows, 31 columns"* ]] || fail "flexloop log .mat rows: $out"
cmp -s "$tmp/sim/log.csv" "$tmp/sim/back.csv" || fail "flexloop log .mat -> .csv differs from sim's CSV"
out=$("$flexloop" log "$tmp/sim/log.csv" -o "$tmp/sim/back.mat" 2>&1) || fail "flexloop log .csv: $out"
/usr/bin/python3 - "$tmp/sim/log.mat" "$tmp/sim/back.mat" <<'PY' || fail "flexloop log .csv -> .mat differs from sim's .mat"
import sys, numpy, scipy.io
a, b = scipy.io.loadmat(sys.argv[1]), scipy.io.loadmat(sys.argv[2])
assert a["data"].shape == b["data"].shape == (10000, 31), (a["data"].shape, b["data"].shape)
assert numpy.array_equal(a["data"].view(numpy.uint64), b["data"].view(numpy.uint64))
assert [str(c[0]) for c in a["columns"][0]] == [str(c[0]) for c in b["columns"][0]]
PY
printf 't_s,x\n0,1\n0.1,one\n' >"$tmp/sim/bad.csv"
out=$("$flexloop" log "$tmp/sim/bad.csv" -o "$tmp/sim/bad.mat" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"bad.csv:3"* && ! -e "$tmp/sim/bad.mat" ]] || fail "flexloop log bad.csv: exit $rc ($out)"
out=$("$flexloop" sim "$root/tools/scenes/metrology_frame.toml" --duration 1 --log "$tmp/sim/log.txt" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"log.txt"* && "$out" == *".mat"* ]] || fail "sim --log .txt: exit $rc ($out)"
# Outputs that cannot be written are refused before the run (here: a directory under a file),
# and a duration or rate that is not a finite number is refused, not replaced by the scene's.
touch "$tmp/a_file"
for opt in "--log $tmp/a_file/log.csv" "--plots $tmp/a_file/plots"; do
  out=$("$flexloop" sim "$root/tools/scenes/metrology_frame.toml" --duration 1 $opt 2>&1); rc=$?
  [[ $rc -eq 2 && "$out" == *"a_file"*"cannot be written"* && "$out" != *"real time"* ]] ||
    fail "sim $opt: exit $rc ($out)"
done
# Every command that writes refuses an output it cannot write before its work (exit 2), and a
# folder in a file's place too (it would end in a failed rename).
for cmd in "linearise $root/tools/models/cart.toml -o $tmp/a_file/x.json" \
  "analyse $root/tools/models/cart.toml --out-dir $tmp/a_file/an" \
  "build $root/tools/scenes/cart.toml -o $tmp/a_file/x.json" \
  "discretise $tmp/cart.json --method zoh --rate 1000 -o $tmp/a_file/x.json" \
  "reduce $tmp/cart.json --method modal --order 1 -o $tmp/a_file/x.json" \
  "fit-metrology -o $tmp/a_file/x.toml" \
  "log $tmp/cart.json -o $tmp/a_file/x.csv" \
  "export-fmu $root/tools/scenes/cart.toml -o $tmp/a_file/x.fmu" \
  "baseline timer --duration 1 --json $tmp/a_file/t.json" \
  "campaign worst $root/tools/scenes/metrology_frame.toml -u $root/tools/scenes/metrology_frame_uncertain.toml --figure rms --out-dir $tmp/a_file/w"; do
  out=$("$flexloop" $cmd 2>&1); rc=$?
  [[ $rc -eq 2 && "$out" == *"a_file"*"cannot be written"* ]] || fail "$cmd: exit $rc ($out)"
done
mkdir "$tmp/a_folder"
out=$("$flexloop" build "$root/tools/scenes/cart.toml" -o "$tmp/a_folder" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"a_folder: cannot be written: Is a directory"* && "$out" != *"wrote"* ]] ||
  fail "build -o a folder: exit $rc ($out)"
for bad in nan inf -1; do
  out=$("$flexloop" sim "$root/tools/scenes/metrology_frame.toml" --duration "$bad" 2>&1); rc=$?
  [[ $rc -eq 2 && "$out" == *"--duration"* && "$out" != *"real time"* ]] || fail "sim --duration $bad: exit $rc ($out)"
done
# A log that would not fit in memory is refused before the run, saying which --log-every would.
out=$("$flexloop" sim "$root/tools/scenes/metrology_frame.toml" --duration 1e9 --log "$tmp/huge.mat" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"GB"*"--log-every"* && ! -e "$tmp/huge.mat" ]] || fail "sim huge log: exit $rc ($out)"
# A .mat log beyond MAT 5's 2 GB a variable (1000 s x 31 columns: 2.5 GB) is refused before the run.
out=$("$flexloop" sim "$root/tools/scenes/metrology_frame.toml" --duration 1000 --log "$tmp/big.mat" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"big.mat"*"MAT 5"*"--log-every"* && ! -e "$tmp/big.mat" ]] || fail "sim .mat above 2 GB: exit $rc ($out)"
out=$("$flexloop" build "$root/tools/scenes/metrology_frame.toml" --rate 1e9 -o "$tmp/fast.json" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"--rate"* && ! -e "$tmp/fast.json" ]] || fail "build --rate 1e9: exit $rc ($out)"

# The all-effects scene (gravity preload with a leak, every effect) simulates; the same scene
# without the leak is refused at its leak_hz line, saying which leak would make the loop stable.
out=$("$flexloop" sim "$root/tools/scenes/metrology_frame_all_effects.toml" --duration 0.5 2>&1) ||
  fail "sim all-effects scene: $out"
[[ "$out" == *"24 states"* && "$out" == *"dB"* ]] || fail "sim all-effects summary: $out"
sed 's/^leak_hz = .*/leak_hz = 0.0/' "$root/tools/scenes/metrology_frame_all_effects.toml" >"$tmp/no_leak.toml"
sed -i "s#\.\./models/#$root/tools/models/#" "$tmp/no_leak.toml"
line=$(grep -n '^leak_hz' "$tmp/no_leak.toml" | cut -d: -f1)
out=$("$flexloop" sim "$tmp/no_leak.toml" --duration 0.5 --log "$tmp/no_leak/log.csv" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"no_leak.toml:$line: [controller]: the closed loop is unstable"* &&
   "$out" == *"a leak_hz of at least"* ]] || fail "unstable scene: exit $rc ($out)"
[[ ! -e "$tmp/no_leak/log.csv" ]] || fail "unstable scene left a log"
# Its floor states start where the floor is, which needs the zero-order hold's coordinates.
sed 's/^method = .*/method = "tustin"/' "$root/tools/scenes/metrology_frame_all_effects.toml" >"$tmp/tustin.toml"
sed -i "s#\.\./models/#$root/tools/models/#" "$tmp/tustin.toml"
out=$("$flexloop" sim "$tmp/tustin.toml" --duration 0.5 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"tustin.toml: [discretisation]:"* && "$out" == *"zoh"* ]] ||
  fail "preloaded scene with tustin: exit $rc ($out)"

# An unstable sampled loop (one strut, omega_d = 100 Hz sampled at 200 Hz; the continuous loop is
# stable) is refused before any run at its rate_hz line, with the spectral radius and a rate and
# an omega_d that would work; analyse reports it.
strut="$root/tests/fixtures/one_strut_200hz.toml"
line=$(grep -n '^rate_hz' "$strut" | cut -d: -f1)
out=$("$flexloop" sim "$strut" --duration 0.5 --log "$tmp/strut/log.csv" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"one_strut_200hz.toml:$line: [discretisation]: the sampled loop is unstable"* &&
   "$out" == *"spectral radius"* && "$out" == *"stable: rate_hz = "* && "$out" == *"omega_d_hz <= "* ]] ||
  fail "unstable sampled loop: exit $rc ($out)"
[[ ! -e "$tmp/strut/log.csv" ]] || fail "unstable sampled loop left a log"
out=$("$flexloop" analyse "$strut" --points 20 --out-dir "$tmp/strut_analyse" 2>&1) || fail "analyse one strut: $out"
[[ "$out" == *"sampled loop at 200 Hz"*"spectral radius"*"UNSTABLE"* && "$out" == *"closed loop: UNSTABLE as it runs"* ]] ||
  fail "analyse one strut does not report the sampled loop: $out"
grep -q '"spectral_radius"' "$tmp/strut_analyse/analysis.json" || fail "analysis.json lacks the sampled loop's spectral radius"

# reduce: a linearised model to fewer states, same format (discretise reads it); bad options exit 2.
"$flexloop" reduce "$tmp/cart.json" --method balanced --order 1 -o "$tmp/cart_1.json" >/dev/null ||
  fail "reduce cart"
"$flexloop" discretise "$tmp/cart_1.json" --method zoh --rate 1000 -o "$tmp/cart_1_d.json" >/dev/null ||
  fail "discretise a reduced model"
out=$("$flexloop" reduce "$tmp/cart.json" --method balanced -o "$tmp/r.json" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"--order"* && ! -e "$tmp/r.json" ]] || fail "reduce without order: exit $rc ($out)"
out=$("$flexloop" reduce "$tmp/cart.json" --method balanced --order 9 -o "$tmp/r.json" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"above the model"* && ! -e "$tmp/r.json" ]] || fail "reduce above order: exit $rc ($out)"

# tradeoff: a small sweep writes its three files; an unknown method or an unwritable directory
# exits 2 before any work.
three="$root/tests/fixtures/three_masses.toml"
out=$("$flexloop" tradeoff "$three" --methods zoh euler --rates 2000 --forms dense --scalars double float \
  --reductions balanced --orders 8 --repeats 1 --bench-steps 200 --run 0.05 --budget 0.5 -q \
  --out-dir "$tmp/tradeoff" 2>&1) || fail "tradeoff: $out"
[[ "$out" == *"ns/step"* && "$out" == *"cheapest"* ]] || fail "tradeoff output: $out"
for f in tradeoff.csv tradeoff.json pareto_front.png; do
  [[ -s "$tmp/tradeoff/$f" ]] || fail "tradeoff wrote no $f"
done
out=$("$flexloop" tradeoff "$three" --methods rk4 --out-dir "$tmp/t2" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"--methods"*"rk4"* ]] || fail "tradeoff --methods rk4: exit $rc ($out)"
out=$("$flexloop" tradeoff "$three" --out-dir /proc/flexloop 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"cannot be written"* ]] || fail "tradeoff unwritable: exit $rc ($out)"

for cmd in version linearise analyse discretise reduce build fit-metrology sim hil plant controller \
  baseline log tradeoff; do
  # Captured, not piped to grep -q: grep's early exit would SIGPIPE a long help under pipefail.
  out=$("$flexloop" $cmd --help) && [[ "$out" == *"Example"* ]] || fail "$cmd --help has no example"
done
# A machine of any size from the arm generator (beams with their consistent mass) simulates.
out=$("$root/tools/models/make_flexible_arm.py" --elements 4 -o "$tmp/arm4") || fail "make_flexible_arm: $out"
out=$("$flexloop" sim "$tmp/arm4/scene.toml" --duration 0.2 2>&1) || fail "sim of a generated arm: $out"
[[ "$out" == *"22 states"* && "$out" == *"real time"* ]] || fail "sim of a generated arm: $out"
out=$("$root/tools/models/make_flexible_arm.py" --help) && [[ "$out" == *"Example"* ]] ||
  fail "make_flexible_arm.py --help has no example"
# One BLAS thread per process whatever OPENBLAS_NUM_THREADS says (issue 54: spinning OpenBLAS
# threads halved a campaign's rate); FLEXLOOP_BLAS_THREADS asks for more.
if "$flexloop" version | grep -q "^blas     OpenBLAS"; then
  out=$(OPENBLAS_NUM_THREADS=2 "$flexloop" version)
  [[ "$out" == *", 1 thread"* ]] || fail "OPENBLAS_NUM_THREADS=2 gave more than one BLAS thread: $out"
  out=$(FLEXLOOP_BLAS_THREADS=2 "$flexloop" version)
  [[ "$out" == *", 2 threads"* ]] || fail "FLEXLOOP_BLAS_THREADS=2 not honoured: $out"
fi

echo "cli contract: 27 checks passed"
