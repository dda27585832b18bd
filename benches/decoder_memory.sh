#!/usr/bin/env bash
# The release canopen-decode's largest resident set (/usr/bin/time's %M)
# reading the same frames in every format, from the file's path, from
# stdin, gzip-compressed from its path and gzip-compressed from stdin, at
# two sizes: the figures of docs/PERFORMANCE.md's "Memory".
#
#   bash benches/decoder_memory.sh [N ...]      (default: 100000 1000000)
#
# The logs are written under target/memory-bench (never committed) by
# benches/memory_logs.py (python-can for ASC, TRC, CSV, BLF and MF4).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
sizes=("$@")
((${#sizes[@]})) || sizes=(100000 1000000)
dir=target/memory-bench
cargo build --quiet --release --features cli --bin canopen-decode
bin=target/release/canopen-decode
rss() {
    /usr/bin/time -o "$dir/time" -f "%M" "$@" >/dev/null 2>"$dir/stderr" || true
    awk '{ printf "%.1f", $1 / 1024 }' "$dir/time"
}
echo "| format | frames | file | stdin | .gz file | .gz on stdin | file size |"
echo "|---|---|---|---|---|---|---|"
for n in "${sizes[@]}"; do
    [[ -f $dir/frames-$n.pcapng ]] || python3 benches/memory_logs.py "$n" "$dir" >&2
    for ext in log asc trc csv blf pcap pcapng mf4 dt.mf4; do
        f=$dir/frames-$n.$ext
        [[ -f $f.gz ]] || gzip -k -f "$f"
        a=$(rss "$bin" "$f")
        b=$(rss sh -c "cat '$f' | '$bin' -")
        c=$(rss "$bin" "$f.gz")
        d=$(rss sh -c "cat '$f.gz' | '$bin' -")
        size=$(stat -c %s "$f" | awk '{ printf "%.2f", $1 / 1e6 }')
        echo "| $ext | $n | $a MB | $b MB | $c MB | $d MB | $size MB |"
    done
done
