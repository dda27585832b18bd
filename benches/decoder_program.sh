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
RUNS=${RUNS:-3}
# Wall time of RUNS runs (output to /dev/null): the best and the worst,
# with the best's lines/s; then the CPU time (user + system, which a busy
# machine inflates less than wall time) and the largest resident set of
# one more run.
measure() {
    local name=$1
    shift
    local best="" worst="" start end t i
    for ((i = 0; i < RUNS; i++)); do
        start=$(date +%s.%N)
        "$@" >/dev/null
        end=$(date +%s.%N)
        t=$(awk -v s="$start" -v e="$end" 'BEGIN { printf "%.3f", e - s }')
        best=$(awk -v a="${best:-$t}" -v b="$t" 'BEGIN { print (b < a) ? b : a }')
        worst=$(awk -v a="${worst:-$t}" -v b="$t" 'BEGIN { print (b > a) ? b : a }')
    done
    local rss="-"
    if command -v /usr/bin/time >/dev/null; then
        /usr/bin/time -o target/decoder-bench/rss -f "%M %U %S" "$@" >/dev/null 2>&1
        read -r rss user sys < <(tail -n 1 target/decoder-bench/rss)
    fi
    awk -v n="$name" -v b="$best" -v w="$worst" -v l="$LINES" -v r="$rss" -v k="$RUNS" \
        -v c="$(awk -v u="${user:-0}" -v s="${sys:-0}" 'BEGIN { print u + s }')" \
        'BEGIN { printf "%-30s %6.2f M lines/s  best %.3f s, worst %.3f s of %d; CPU %.2f s; max resident %s KB\n", n, l / b / 1e6, b, w, k, c, r }'
}
roles=(--charger-node 10 --battery-node 1)
measure "canopen-decode (words)" "$bin" "${roles[@]}" "$log"
measure "canopen-decode --json" "$bin" "${roles[@]}" --json "$log"
measure "canopen-decode --output csv" "$bin" "${roles[@]}" --output csv "$log"
measure "canopen-decode --summary" "$bin" "${roles[@]}" --summary "$log"
measure "canopen-decode --summary-only" "$bin" "${roles[@]}" --summary-only "$log"
if command -v canopen-lens >/dev/null; then
    measure "canopen-lens (summary)" canopen-lens "$log" --no-color
else
    echo "canopen-lens is not installed (pip install canopen-lens): no side-by-side figure"
fi
