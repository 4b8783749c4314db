#!/usr/bin/env bash
# Prints how many cores this process can really use: the CPUs it may run on (nproc), bounded by
# the cgroup's CPU quota (a container limited to 2 cores of a 64-core host sees 64 CPUs; starting
# 64 builds or tests there makes everything many times slower).
# Usage: scripts/cpu-count.sh             the number
#        scripts/cpu-count.sh --describe  one line: CPU model, nproc, quota, the number
set -euo pipefail
cpus=$(nproc)
quota=""
if [ -r /sys/fs/cgroup/cpu.max ]; then  # cgroup v2: "max 100000" or "200000 100000"
  read -r q p < /sys/fs/cgroup/cpu.max || true
  if [ "${q:-max}" != max ] && [ "${p:-0}" -gt 0 ]; then quota="$q/$p"; fi
elif [ -r /sys/fs/cgroup/cpu/cpu.cfs_quota_us ] && [ -r /sys/fs/cgroup/cpu/cpu.cfs_period_us ]; then
  q=$(cat /sys/fs/cgroup/cpu/cpu.cfs_quota_us)
  p=$(cat /sys/fs/cgroup/cpu/cpu.cfs_period_us)
  if [ "$q" -gt 0 ] && [ "$p" -gt 0 ]; then quota="$q/$p"; fi
fi
n=$cpus
if [ -n "$quota" ]; then
  limit=$(((${quota%/*} + ${quota#*/} - 1) / ${quota#*/}))  # rounded up
  [ "$limit" -lt 1 ] && limit=1
  [ "$limit" -lt "$n" ] && n=$limit
fi
if [ "${1:-}" = --describe ]; then
  model=$(grep -m1 -E '^(model name|Model name|Hardware)' /proc/cpuinfo 2>/dev/null | cut -d: -f2- |
    sed 's/^ *//')
  echo "$(uname -m) ${model:-unknown CPU}, nproc $cpus, CPU quota ${quota:-none}, using $n" \
    "(load average $(cut -d' ' -f1-3 /proc/loadavg))"
else
  echo "$n"
fi
