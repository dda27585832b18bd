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
# RUNS runs of each (output to /dev/null), each timed by /usr/bin/time:
# the best and the worst wall time, with the best's lines/s; the best CPU
# time (user + system, which a busy machine inflates less than wall time,
# the figure the ratios compare) and the largest resident set.
cpu_of=()
measure() {
    local name=$1
    shift
    local best="" worst="" cpu="" rss=0 t c m i
    for ((i = 0; i < RUNS; i++)); do
        /usr/bin/time -o target/decoder-bench/time -f "%e %U %S %M" "$@" >/dev/null
        read -r t u s m < <(tail -n 1 target/decoder-bench/time)
        c=$(awk -v u="$u" -v s="$s" 'BEGIN { printf "%.2f", u + s }')
        best=$(awk -v a="${best:-$t}" -v b="$t" 'BEGIN { print (b < a) ? b : a }')
        worst=$(awk -v a="${worst:-$t}" -v b="$t" 'BEGIN { print (b > a) ? b : a }')
        cpu=$(awk -v a="${cpu:-$c}" -v b="$c" 'BEGIN { print (b < a) ? b : a }')
        ((m > rss)) && rss=$m
    done
    cpu_of+=("$name=$cpu")
    awk -v n="$name" -v b="$best" -v w="$worst" -v l="$LINES" -v r="$rss" -v k="$RUNS" -v c="$cpu" \
        'BEGIN { printf "%-34s %6.2f M lines/s  wall best %.2f s, worst %.2f s of %d; CPU best %.2f s; max resident %s KB\n", n, l / (b > 0 ? b : 0.01) / 1e6, b, w, k, c, r }'
}
cpu() {
    local e
    for e in "${cpu_of[@]}"; do
        [[ ${e%%=*} == "$1" ]] && echo "${e#*=}"
    done
}
roles=(--charger-node 10 --battery-node 1)
measure "canopen-decode (words)" "$bin" "${roles[@]}" "$log"
measure "canopen-decode --json" "$bin" "${roles[@]}" --json "$log"
measure "canopen-decode --output csv" "$bin" "${roles[@]}" --output csv "$log"
measure "canopen-decode --summary" "$bin" "${roles[@]}" --summary "$log"
measure "canopen-decode --summary-only" "$bin" "${roles[@]}" --summary-only "$log"
if command -v canopen-lens >/dev/null; then
    # canopen-lens's outputs: its summary on the terminal, its messages
    # (one CSV row per frame with its meaning in words) and its JSON data
    # (-s FILE; the file's extension chooses).
    lens=target/decoder-bench/lens
    measure "canopen-lens (summary)" canopen-lens "$log" --no-color
    measure "canopen-lens -s messages.csv" canopen-lens "$log" --no-color -s "$lens.csv"
    measure "canopen-lens -s data.json" canopen-lens "$log" --no-color -s "$lens.json"
    ratio() {
        awk -v n="$1" -v a="$(cpu "$2")" -v b="$(cpu "$3")" \
            'BEGIN { printf "%-34s %5.1fx (CPU %.2f s against %.2f s)\n", n, (a > 0 ? b / a : 0), a, b }'
    }
    echo "canopen-lens CPU time / canopen-decode CPU time (best of $RUNS each):"
    ratio "words / lens messages" "canopen-decode (words)" "canopen-lens -s messages.csv"
    ratio "words / lens summary" "canopen-decode (words)" "canopen-lens (summary)"
    ratio "JSON / lens JSON" "canopen-decode --json" "canopen-lens -s data.json"
else
    echo "canopen-lens is not installed (pip install canopen-lens): no side-by-side figure"
fi
