#!/usr/bin/env bash
# A sweep on a real single-node Slurm (docs/sweep.md, "On a Slurm cluster"):
# starts munged (as user munge), slurmctld and slurmd on this machine with a
# private configuration, runs the README's Slurm task as written (a plan's
# cases as an array through docs/sweep.sbatch with `sbatch --wait`, then the
# merge), and checks that the merged CSV equals the in-process sweep's
# (timing columns aside). It stops everything it started, whatever happens.
#
#   tests/slurm/test_slurm.sh EIGENMASS SOURCE_DIR WORK_DIR
#
# Exit 0 passed, 1 failed, 77 skipped (ctest's SKIP_RETURN_CODE), with the reason.
set -euo pipefail
eigenmass=$1 src=$2 work=$3
packages=(slurmctld slurmd slurm-client munge)

skip() { echo "SKIPPED: $*"; exit 77; }
fail() { echo "FAILED: $*" >&2; exit 1; }

# Daemons run as root without systemd (slurmd starts jobs as their user; munged's key is root's to read).
[ "$(id -u)" -eq 0 ] || skip "needs root: slurmd runs jobs as their user and munged's key is readable by root only"
missing=()
for p in "${packages[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then  # as every ./run step: Debian's packages, installed when missing
  echo "installing: ${missing[*]}"
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null ||
    fail "apt-get install ${missing[*]}"
fi

rm -rf "$work"
mkdir -p "$work"/{state,spool,log}
work=$(cd "$work" && pwd)
# munged runs as user munge, which must reach its socket, key, log and seed:
# the work folder may lie where munge cannot (a clone under /root, mode 0700),
# so munged's state lives in a fresh folder of its own that munge owns.
munge_dir=$(mktemp -d /tmp/eigenmass-munge.XXXXXX)
pids=() munged_pid=""
cleanup() {
  scancel --quiet --full --user=root 2>/dev/null || true
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  if [ -n "$munged_pid" ]; then
    kill "$munged_pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$munged_pid" 2>/dev/null || break; sleep 0.1; done
  fi
  rm -rf "$munge_dir"
}
trap cleanup EXIT

# munged as user munge on a private socket, with the key Debian's package made.
chown munge:munge "$munge_dir"
chmod 0755 "$munge_dir"  # munged: the socket's folder must be searchable by all
[ -s /etc/munge/munge.key ] || runuser -u munge -- mungekey --create --keyfile=/etc/munge/munge.key
runuser -u munge -- test -r /etc/munge/munge.key -a -w "$munge_dir" ||
  fail "user munge cannot read /etc/munge/munge.key or write $munge_dir (owner and modes: $(stat -c '%U %a' /etc/munge/munge.key "$munge_dir" | tr '\n' ' '))"
socket="$munge_dir/munge.socket"
runuser -u munge -- /usr/sbin/munged --socket="$socket" --pid-file="$munge_dir/munged.pid" \
  --log-file="$munge_dir/munged.log" --seed-file="$munge_dir/munged.seed" ||
  fail "munged (as user munge, state in $munge_dir) did not start: $(cat "$munge_dir/munged.log" 2>/dev/null)"
munged_pid=$(cat "$munge_dir/munged.pid")  # it runs on as a daemon: stopped by its pid
for _ in $(seq 50); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || fail "munged made no socket in $munge_dir: $(cat "$munge_dir/munged.log" 2>/dev/null)"

# One node: this machine as slurmd -C sees it; ports away from a real cluster's 6817/6818.
node=$(slurmd -C | head -1)
host=$(hostname -s)
cat >"$work/slurm.conf" <<EOF
ClusterName=eigenmass-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
ReturnToService=2
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$work/slurm.conf"
/usr/sbin/slurmctld -D -i -f "$SLURM_CONF" >"$work/log/slurmctld.out" 2>&1 &
pids+=($!)
/usr/sbin/slurmd -D -f "$SLURM_CONF" >"$work/log/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 300); do  # up to 60 s: the node may start slowly beside a loaded -j2 suite
  state=$(sinfo --noheader --format=%t 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.2
done
if [ "$state" != idle ]; then
  # slurmd exits at once where no cgroup filesystem is mounted: say so from its own lines, not only the node's state.
  if ! kill -0 "${pids[-1]}" 2>/dev/null && grep -qi cgroup "$work/log/slurmd.log" "$work/log/slurmd.out" 2>/dev/null; then
    fail "slurmd could not start: no usable cgroup filesystem (mount one: mount -t cgroup2 none /sys/fs/cgroup); slurmd said: $(grep -hi cgroup "$work/log/slurmd.log" "$work/log/slurmd.out" | tail -n 2 | tr '\n' ' ')"
  fi
  fail "the node is not idle (sinfo: '$state'); $(tail -n 5 "$work/log/slurmctld.log" "$work/log/slurmd.log" "$work/log/slurmd.out" 2>&1)"
fi
echo "slurm: $(sinfo --version), node $host idle: $node"

# The README's Slurm task, as written, in a folder that sees what the README's
# folder has (data/, docs/, build/bin/), then the same plan in one process.
"$src/tests/docs/readme_folder.sh" "$src" "$(dirname "$eigenmass")" "$work/readme"
block=$("$src/tests/docs/readme_block.sh" "$src/README.md" "Run a sweep on a Slurm cluster")
[ -n "$block" ] || fail "README.md has no block under '### Run a sweep on a Slurm cluster'"
cd "$work/readme"
start=$SECONDS
bash -euo pipefail -c "$block" >"$work/readme.log" 2>&1 || fail "the README's Slurm task: $(tail -n 5 "$work/readme.log")"
n=$(wc -l <out/cases.txt)
tasks=$(ls slurm-*_*.out | wc -l)
[ "$tasks" -eq "$n" ] || fail "expected $n array task outputs, got $tasks"
echo "the README's Slurm task: $n cases as one array, merged, in $((SECONDS - start)) s"
"$eigenmass" sweep data/plans/order-check.json --results "$work/local" -j 2 >/dev/null 2>&1

# The merged CSVs equal, timing columns (cpu_*) aside.
drop_timing() {
  /usr/bin/python3 -c '
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
keep = [i for i, h in enumerate(rows[0]) if not h.startswith("cpu_")]
for r in rows: print(",".join(r[i] for i in keep))' "$1"
}
drop_timing results/order-check-slurm/order-check.csv >"$work/cluster.csv"
drop_timing "$work/local/order-check.csv" >"$work/local.csv"
rows=$(($(wc -l <"$work/cluster.csv") - 1))
[ "$rows" -eq "$n" ] && [ "$n" -ge 10 ] || fail "expected $n (>= 10) rows in the merged CSV, got $rows"
diff "$work/cluster.csv" "$work/local.csv" >"$work/diff.txt" || fail "merged CSVs differ: $(head -5 "$work/diff.txt")"
echo "PASSED: $n cases through a Slurm array equal the in-process sweep's ($rows rows, timing aside)"
