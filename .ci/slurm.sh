#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, from Debian's packages
# (slurm-wlm 22.05, munge), for the tests of `holo farm`:
#
#   .ci/slurm.sh start    install if needed, write the configuration under
#                         target/slurm, start munged, slurmctld and slurmd
#                         (as root), and wait until `sinfo` answers
#   .ci/slurm.sh stop     stop what `start` started
#   .ci/slurm.sh env      print `export SLURM_CONF=...` for a shell
#   .ci/slurm.sh selftest start, run a 4-task job array and cancel a
#                         second one's task mid-run (what `holo farm` relies
#                         on), check both, stop
#   .ci/slurm.sh test     start, the selftest, then the tests of `holo farm`
#                         against the cluster (cli/tests/cli/farm.rs, ignored
#                         by a plain `cargo test`), stop
#
# The cluster: one node with this machine's CPUs and memory, one partition
# `ci`; processes tracked by /proc (no cgroups in containers), no task
# binding, consumable cores and memory.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
dir=$root/target/slurm
conf=$dir/slurm.conf

say() { echo "slurm.sh: $*"; }

install() {
    if command -v slurmctld >/dev/null && command -v munged >/dev/null && command -v sbatch >/dev/null; then
        return
    fi
    say "installing slurm-wlm and munge (apt-get)"
    apt-get update -q
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge
}

start_munge() {
    if [ ! -s /etc/munge/munge.key ]; then
        say "creating the munge key"
        mkdir -p /etc/munge
        dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
    fi
    chown munge:munge /etc/munge/munge.key
    chmod 0400 /etc/munge/munge.key
    mkdir -p /run/munge /var/log/munge /var/lib/munge
    chown munge:munge /run/munge /var/log/munge /var/lib/munge
    munge -n >/dev/null 2>&1 && return
    for _ in $(seq 50); do
        # A munged that is still exiting holds the socket's lock: try again.
        runuser -u munge -- /usr/sbin/munged 2>/dev/null || true
        munge -n >/dev/null 2>&1 && return
        sleep 0.1
    done
    say "munged did not start"
    exit 1
}

write_conf() {
    mkdir -p "$dir/state" "$dir/spool" "$dir/log"
    local host cpus memory
    host=$(hostname -s)
    cpus=$(nproc)
    # MiB, less a little for the system.
    memory=$(awk '/MemTotal/ {printf "%d", $2 / 1024 * 0.9}' /proc/meminfo)
    cat >"$conf" <<CONF
ClusterName=holo-ci
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MinJobAge=300
KillWait=5
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
    # slurmd reads the same file; cgroup.conf is not needed with these plugins.
}

start() {
    install
    start_munge
    write_conf
    export SLURM_CONF=$conf
    if [ -f "$dir/slurmctld.pid" ] && kill -0 "$(cat "$dir/slurmctld.pid")" 2>/dev/null; then
        say "slurmctld already running"
    else
        slurmctld -f "$conf"
    fi
    if [ -f "$dir/slurmd.pid" ] && kill -0 "$(cat "$dir/slurmd.pid")" 2>/dev/null; then
        say "slurmd already running"
    else
        slurmd -f "$conf"
    fi
    for _ in $(seq 100); do
        if sinfo -h -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
            say "up: $(sinfo -h -o '%P %D %c CPUs %m MiB %T')"
            return
        fi
        sleep 0.2
    done
    say "the node did not come up:"
    sinfo || true
    tail -20 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" || true
    exit 1
}

stop() {
    for daemon in slurmd slurmctld; do
        if [ -f "$dir/$daemon.pid" ]; then
            kill "$(cat "$dir/$daemon.pid")" 2>/dev/null || true
            rm -f "$dir/$daemon.pid"
        fi
    done
    pkill -x munged 2>/dev/null || true
    for _ in $(seq 50); do
        pgrep -x munged >/dev/null || break
        sleep 0.1
    done
    say "stopped"
}

selftest() {
    start
    export SLURM_CONF=$conf
    trap stop EXIT
    arrays
}

# A job array runs every task; a task cancelled mid-run stays cancelled.
arrays() {
    local out=$dir/selftest
    rm -rf "$out" && mkdir -p "$out"
    local job
    job=$(sbatch --parsable --array=0-3 --cpus-per-task=1 --mem=64M -o "$out/%A_%a.out" \
        --wrap 'echo "task $SLURM_ARRAY_TASK_ID of $SLURM_ARRAY_JOB_ID"')
    wait_for "$job"
    for task in 0 1 2 3; do
        grep -qx "task $task of $job" "$out/${job}_$task.out" || { say "task $task wrote nothing"; exit 1; }
    done
    say "array $job: 4 tasks ran"
    # A task cancelled mid-run ends CANCELLED and writes no marker.
    job=$(sbatch --parsable --array=0-1 --cpus-per-task=1 --mem=64M -o "$out/%A_%a.out" \
        --wrap 'sleep 2; echo done > '"$out"'/marker.$SLURM_ARRAY_TASK_ID')
    sleep 0.5
    scancel "${job}_1"
    wait_for "$job"
    [ -f "$out/marker.0" ] && [ ! -f "$out/marker.1" ] || { say "scancel of one task did not take"; exit 1; }
    say "array $job: task 1 cancelled, task 0 finished"
}

wait_for() {
    for _ in $(seq 300); do
        if [ -z "$(squeue -h -j "$1" 2>/dev/null)" ]; then
            return
        fi
        sleep 0.2
    done
    say "job $1 did not finish"
    squeue
    exit 1
}

farm_tests() {
    start
    export SLURM_CONF=$conf
    trap stop EXIT
    arrays
    say "the tests of holo farm against the cluster"
    # --workspace and the full profile: the same build as .ci/run's full run, so nothing is rebuilt.
    cargo test --workspace --profile full --test cli farm -- --ignored
}

case "${1:-}" in
start) start ;;
stop) stop ;;
selftest) selftest ;;
test) farm_tests ;;
env) echo "export SLURM_CONF=$conf" ;;
*)
    echo "usage: .ci/slurm.sh start|stop|env|selftest|test" >&2
    exit 2
    ;;
esac
