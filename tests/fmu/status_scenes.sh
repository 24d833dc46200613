# SPDX-License-Identifier: BSD-3-Clause
# Sourced by the tests of a controller FMU's statuses (fmu_statuses_sim.sh, fmu_hil_failures.sh):
# with $flexloop, $fmu, $root, $tmp and fail() set, writes the fixture PI's scene into $tmp
# (fmu_scene.py: the metrology frame's designed gains as the FMU's parameters) as $scene, and
# defines build_with_status CODE NAME STEP [RATE_HZ]: $tmp/NAME.json, the loop (at RATE_HZ, or the
# scene's 10 kHz) whose FMU answers its step STEP with the status CODE asks
# (tools/fmu/fixture_fmu.h: 1 fmi2Warning, 2 fmi2Discard, 5 fmi2Pending, 11 a crash).
"$flexloop" build "$root/tools/scenes/metrology_frame.toml" -o "$tmp/frame.json" >/dev/null ||
  fail "flexloop build metrology_frame"
scene=$(python3 "$root/tests/fmu/fmu_scene.py" "$root" "$fmu" "$tmp/frame.json" "$tmp") ||
  fail "fmu_scene.py"
build_with_status() {
  sed "s/^u_max = .*/&\nstep_status = $1\nstatus_at_step = $3/" "$scene" > "$tmp/$2.toml"
  "$flexloop" build "$tmp/$2.toml" -o "$tmp/$2.json" ${4:+--rate "$4"} >/dev/null ||
    fail "build ($2)"
}
