#!/usr/bin/env bash
# tests/campaign/slurm_submit_options.sh FLEXLOOP REPO: `campaign submit --engine slurm`'s options
# as a user gives them (issue 54, 2.4), against fake sbatch / squeue / scontrol on PATH (no
# cluster: the fakes record their arguments, sbatch keeps the script it is given and answers
# "JOBID;far" as for a job sent to another cluster, scontrol shows MaxArraySize = 1001):
#   1. without --shards the array has one element per 2000 of the plan's evaluations (4100: 3),
#      whatever the cores of the machine that submits;
#   2. each --sbatch-arg is its own #SBATCH line, verbatim; the job on cluster "far" is followed
#      with squeue -M far and scontrol -M far;
#   3. an --sbatch-arg with a newline, or one setting --array, and --shards above MaxArraySize
#      exit 2 naming the option and value, and nothing is submitted.
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 root=$2
tmp=$(mktemp -d /tmp/flexloop-slurm-options.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

bin=$tmp/bin
mkdir -p "$bin"
record='{ echo "$(basename "$0")"; printf "%s\n" "$@"; echo --; } >> "$(dirname "$0")/calls.txt"'
# sbatch: keeps the script, writes the (empty) shard files of its array, as elements would.
cat > "$bin/sbatch" <<EOF
#!/bin/bash
$record
script=\${@: -1}
cp "\$script" "\$(dirname "\$0")/submitted.sbatch"
last=\$(sed -n 's/^#SBATCH --array=0-\([0-9]*\)\$/\1/p' "\$script")
dir=\$(sed -n 's/^#SBATCH --chdir="\(.*\)"\$/\1/p' "\$script")
for ((k = 0; k <= last; ++k)); do : > "\$dir/shard-\$k.jsonl"; done
echo \$((last + 1)) > "\$(dirname "\$0")/elements"
echo '77;far'
EOF
cat > "$bin/squeue" <<EOF
#!/bin/bash
$record
for ((k = 0; k < \$(cat "\$(dirname "\$0")/elements"); ++k)); do echo "77_\$k COMPLETED"; done
EOF
cat > "$bin/scontrol" <<EOF
#!/bin/bash
$record
if [ "\$*" = 'show config' ]; then echo 'MaxArraySize            = 1001'; exit 0; fi
[ "\$*" = '-M far show job 77 -o' ] || { echo "fake scontrol: \$*" >&2; exit 1; }
for ((k = 0; k < \$(cat "\$(dirname "\$0")/elements"); ++k)); do
  echo "JobId=\$((100 + k)) ArrayJobId=77 ArrayTaskId=\$k JobState=COMPLETED ExitCode=0:0"
done
EOF
chmod +x "$bin"/*
export PATH="$bin:$PATH"

scene=$root/tests/fixtures/one_strut_campaign.toml
u=$root/tests/fixtures/one_strut_uncertain.toml
"$flexloop" campaign plan "$scene" -u "$u" -n 4100 --design random -o "$tmp/plan.json" >/dev/null ||
  fail "campaign plan"

# 1 and 2.
out=$("$flexloop" campaign submit "$tmp/plan.json" --engine slurm --work-dir "$tmp/work" \
  --sbatch-arg=--mem=2G --sbatch-arg=--qos=long --sbatch-arg='-M far' 2>&1) ||
  fail "submit with fake clients: $out"
script=$(cat "$bin/submitted.sbatch")
grep -qx -- '#SBATCH --array=0-2' <<<"$script" ||
  fail "not 3 elements for 4100 evaluations ($(nproc) cores here): $(grep -- --array <<<"$script")"
[[ $out == *"3 shards: the default (one per 2000 of the plan's 4100 evaluations)"* ]] ||
  fail "the default shard count is not said: $out"
for line in '#SBATCH --mem=2G' '#SBATCH --qos=long' '#SBATCH -M far' '#SBATCH --requeue' \
  '#SBATCH --open-mode=append'; do
  grep -qxF -- "$line" <<<"$script" || fail "no line '$line' in the script"
done
calls=$(tr '\n' ' ' < "$bin/calls.txt")
[[ $calls == *"squeue -M far -h -r -t all -j 77 "* ]] || fail "squeue without -M far: $calls"
[[ $calls == *"scontrol -M far show job 77 -o "* ]] || fail "scontrol without -M far: $calls"
[[ $out == *"scancel -M far 77"* ]] || fail "no scancel for the job on far: $out"
[[ $(grep -c '^shard: ' <<<"$out") -eq 3 ]] || fail "not 3 shard files: $out"

# 3. Refused before anything is submitted, exit 2.
rm -f "$bin/calls.txt"
refused() {
  local expect=$1
  shift
  out=$("$flexloop" campaign submit "$tmp/plan.json" --engine slurm --work-dir "$tmp/w2" "$@" 2>&1)
  local rc=$?
  [[ $rc -eq 2 && $out == *"$expect"* ]] || fail "$* : exit $rc, wanted 2 and '$expect': $out"
  ! grep -qx sbatch "$bin/calls.txt" 2>/dev/null || fail "$* : sbatch was run"
}
refused "--sbatch-arg: '--mem=1G\\necho owned' holds a newline" --sbatch-arg=$'--mem=1G\necho owned'
refused "--sbatch-arg: '--array=0-9' sets --array" --sbatch-arg=--array=0-9
refused "--shards: 5000 is more than this cluster's MaxArraySize = 1001" --shards 5000
echo "slurm submit options: ok"
