#!/usr/bin/env bash
# Instructions per frame of every adapter on every stream, counted by
# callgrind inside the adapter (callees included): stable on a busy machine
# where wall-clock figures are not. Needs valgrind.
#
#   bash callgrind.sh [PASSES]      (default 20 passes over each stream)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
PASSES=${1:-20}
cargo build --release --example count --quiet
BIN=target/release/examples/count
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

ir_per_frame() { # adapter stream
    local log
    log=$(valgrind --tool=callgrind --callgrind-out-file="$OUT/cg.out" \
        --toggle-collect="canopen_codec_peers::$1" "$BIN" "$1" "$2" "$PASSES" 2>&1)
    local ir frames
    ir=$(sed -n 's/.*Collected : *\([0-9]*\).*/\1/p' <<<"$log")
    frames=$(sed -n 's/.*: \([0-9]*\) frames x.*/\1/p' <<<"$log")
    awk -v ir="$ir" -v n="$frames" -v p="$PASSES" 'BEGIN { printf "%.1f", ir / (n * p) }'
}

echo "instructions per frame (callgrind, $PASSES passes)"
printf '| %-11s | %6s | %13s | %10s | %13s | %11s |\n' stream copy canopen-codec canopen-rs zencan-common oze-canopen
printf '|%s|%s|%s|%s|%s|%s|\n' -------------  -------- --------------- ------------ --------------- -------------
for s in mixed sdo_upload heartbeats; do
    printf '| %-11s |' "$s"
    for a in copy ours canopen_rs zencan oze; do
        printf ' %s |' "$(ir_per_frame "$a" "$s")"
    done
    echo
done
printf '| %-11s | %6s | %13s | %10s | %13s | %11s |\n' pdo_unpack - \
    "$(ir_per_frame ours_pdo mixed)" "$(ir_per_frame canopen_rs_pdo mixed)" - -
