# A one-node Slurm cluster on 127.0.0.1 in a folder, for tests and benchmarks (sourced by bash).
#   slurm_cluster_check              prints why a cluster cannot start here and returns 1, or 0
#   slurm_cluster_start DIR          munged, slurmctld, slurmd; exports SLURM_CONF; 1 on failure
#                                    (DIR's parents must be world-searchable, as munged wants)
#   slurm_cluster_stop               stops exactly the daemons slurm_cluster_start started
# No systemd is assumed: the daemons run in the foreground (-F, -D) as background jobs whose
# PIDs are recorded at start (the daemons delete their own pid files on exit). As root with
# SlurmUser=root; munged wants its socket folder world-searchable (0755) and its key 0400.
# batch_sched_delay=0: the default 3 s makes an array start in waves. MinJobAge keeps finished
# tasks visible to scontrol (no accounting database).
slurm_daemons=()

slurm_cluster_check() {
    if [ "$(id -u)" != 0 ]; then
        echo "needs root to start munged, slurmctld and slurmd"
        return 1
    fi
    local tool
    for tool in /usr/sbin/munged /usr/sbin/slurmctld /usr/sbin/slurmd sbatch squeue scontrol scancel sinfo; do
        command -v "$tool" >/dev/null || {
            echo "$tool not found (Debian packages slurm-wlm and munge)"
            return 1
        }
    done
}

slurm_port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }

slurm_cluster_start() {
    local dir=$1 i node port
    node=$(hostname -s)
    port=$((20000 + ($$ % 2000) * 10))
    while ! slurm_port_free "$port" || ! slurm_port_free $((port + 1)); do port=$((port + 2)); done
    mkdir -p "$dir/munge" "$dir/state" "$dir/spool"
    chmod 0755 "$dir" "$dir/munge"
    head -c 1024 /dev/urandom >"$dir/munge/key"
    chmod 0400 "$dir/munge/key"
    /usr/sbin/munged -F -S "$dir/munge/socket" --key-file="$dir/munge/key" \
        --log-file="$dir/munged.log" --pid-file="$dir/munge/pid" --seed-file="$dir/munge/seed" \
        >"$dir/munged.out" 2>&1 &
    slurm_daemons+=($!)
    for i in $(seq 50); do [ -S "$dir/munge/socket" ] && break; sleep 0.1; done
    [ -S "$dir/munge/socket" ] || { echo "munged did not start: $(tail -3 "$dir/munged.out")"; return 1; }
    cat >"$dir/slurm.conf" <<EOF
ClusterName=rigflowtest
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$dir/munge/socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/builtin
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MinJobAge=600
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=rigflow Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
    export SLURM_CONF="$dir/slurm.conf"
    /usr/sbin/slurmctld -D -i >"$dir/slurmctld.out" 2>&1 &
    slurm_daemons+=($!)
    /usr/sbin/slurmd -D -N "$node" >"$dir/slurmd.out" 2>&1 &
    slurm_daemons+=($!)
    for i in $(seq 100); do
        [ "$(sinfo -h -o %t 2>/dev/null)" = idle ] && { slurm_port=$port; return 0; }
        sleep 0.1
    done
    echo "the one-node cluster did not come up: $(tail -3 "$dir/slurmctld.log" "$dir/slurmd.log")"
    return 1
}

slurm_alive() { case "$(ps -o stat= -p "$1" 2>/dev/null)" in "" | Z*) return 1 ;; esac; }

slurm_cluster_stop() {
    local p i left
    for ((i = ${#slurm_daemons[@]} - 1; i >= 0; i--)); do kill "${slurm_daemons[i]}" 2>/dev/null; done
    for i in $(seq 50); do # up to 5 s for them to go
        left=0
        for p in "${slurm_daemons[@]}"; do slurm_alive "$p" && left=1; done
        [ "$left" = 0 ] && break
        sleep 0.1
    done
    for p in "${slurm_daemons[@]}"; do slurm_alive "$p" && kill -9 "$p" 2>/dev/null; done
    slurm_daemons=()
}
