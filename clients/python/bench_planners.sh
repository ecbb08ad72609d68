#!/usr/bin/env bash
# Request → schedule latency of a Python planner (examples/own-planner/gather.py) and
# the Rust one (examples/own-planner/gather.rs), same rig,
# alternated A B A B, measured from the side by examples/measure.py.
#   UPM_PYTHON=python-with-iceoryx2 clients/python/bench_planners.sh [SECONDS] [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
secs=${1:-20}; rounds=${2:-2}; py=${UPM_PYTHON:-python3}
cargo build --release -q -p upm-cli --bin upm
cargo build --release -q -p upm-planner --example gather
export PYTHONPATH=clients/python
for r in $(seq 1 "$rounds"); do
    for who in python rust; do
        prefix="upm_bench_${who}_$$_${r}_"
        if [ "$who" = python ]; then cmd="exec $py examples/own-planner/gather.py"
        else cmd="exec target/release/examples/gather --prefix \$UPM_PREFIX"; fi
        target/release/upm run local --duration "$((secs + 4))" --quiet --prefix "$prefix" \
            --planner-cmd "$cmd" --out "out/bench_planners/$who-$r" > /dev/null &
        run=$!
        sleep 3
        echo "$who round $r: $($py clients/python/examples/measure.py --prefix "$prefix" --duration "$secs" --json)"
        wait "$run"
    done
done
