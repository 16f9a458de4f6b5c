#!/usr/bin/env bash
# Runs a benchmark in a session of its own whose CPU priority is the highest (Linux autogroups,
# nice -20; root), so that busy processes in other sessions take little of its time:
#   cpp/bench/with_priority.sh /usr/bin/python3 cpp/bench/pifs_speed.py
# results.py notes the priority beside the load in the section it writes.
set -euo pipefail
exec setsid -w bash -c 'echo -20 > /proc/self/autogroup && exec "$@"' with_priority "$@"
