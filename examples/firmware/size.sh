#!/usr/bin/env bash
# Builds the footprint firmware (examples/firmware: the battery module and
# the charger, each package with its own library features, for
# thumbv7em-none-eabihf, opt-level "z", LTO, panic=abort), prints each
# binary's sections and the size of the node's state (its static, from the
# symbol table), and gates both against their goals in budget.txt:
#
#   flash  .text + .rodata + .data (the vector table is printed beside it;
#          it comes on top and is not counted)
#   state  the node's static (llvm-nm --print-size of its symbol)
#
# A figure above its goal fails the run (exit 1) with a message naming the
# node, the measure, the figure and the goal. So does a binary that lacks
# one of the sections measured (.text, .rodata, .data, .bss,
# .vector_table) or the state symbol: a figure it cannot read is never
# taken as 0. budget.txt holds the goals, not measured figures: it
# changes only when a goal does.
#
#   bash examples/firmware/size.sh            build, print, gate
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
SELF=$(basename "${BASH_SOURCE[0]}")

for arg in "$@"; do
    case "$arg" in
        -h | --help) sed -n '2,19p' "$SELF"; exit 0 ;;
        *) echo "unknown argument: $arg (size.sh takes none)" >&2; exit 2 ;;
    esac
done

TARGET=thumbv7em-none-eabihf
rustup target add "$TARGET" >/dev/null 2>&1 || { echo "rustup target add $TARGET failed" >&2; exit 1; }
rustup component add llvm-tools >/dev/null 2>&1 || { echo "rustup component add llvm-tools failed" >&2; exit 1; }
BIN_DIR=$(echo "$(rustc --print sysroot)"/lib/rustlib/*/bin)
SIZE="$BIN_DIR/llvm-size"
NM="$BIN_DIR/llvm-nm"
for tool in "$SIZE" "$NM"; do
    [[ -x "$tool" ]] || { echo "missing $tool (rustup component add llvm-tools)" >&2; exit 1; }
done

# node binary and the symbol of its state (the static it is built in)
NODES=(
    "battery_module BATTERY_MODULE_STATE"
    "charger CHARGER_STATE"
)

# The goals file: `node flash state` per line (bytes), `#` comments.
GOALS=budget.txt
[[ -f "$GOALS" ]] || { echo "size.sh: examples/firmware/$GOALS (the goals) is missing" >&2; exit 1; }
goal() { # node column -> goal (empty when the node has no line)
    awk -v n="$1" -v c="$2" '!/^[[:space:]]*(#|$)/ && $1 == n { print $c; exit }' "$GOALS"
}
# Every goal line names a node this script measures, with two whole numbers.
known=" $(for row in "${NODES[@]}"; do printf '%s ' "${row%% *}"; done)"
while read -r node flash state extra; do
    [[ -z "$node" || "$node" == \#* ]] && continue
    if [[ "$known" != *" $node "* ]]; then
        echo "size.sh: $GOALS names an unknown node '$node' (this script measures:${known% })" >&2
        exit 1
    fi
    if ! [[ "$flash" =~ ^[0-9]+$ && "$state" =~ ^[0-9]+$ && -z "$extra" ]]; then
        echo "size.sh: $GOALS line for $node is not 'node flash state' in bytes" >&2
        exit 1
    fi
done <"$GOALS"

# Each node is its own package with its own library features (Cargo.toml):
# built one at a time so that their features do not unify.
for package in battery-module-firmware charger-firmware; do
    cargo build --release --locked --quiet -p "$package"
done

section() { # binary section -> size; a section the binary lacks fails the run
    local size
    size=$("$SIZE" -A "$1" | awk -v s="$2" '$1 == s { print $2; exit }')
    if [[ -z "$size" ]]; then
        echo "size.sh: $1 has no $2 section (llvm-size -A lists none), so it cannot be measured" >&2
        return 1
    fi
    echo "$size"
}
# check node measure figure goal: prints the verdict, records a failure
failures=()
check() {
    local node=$1 measure=$2 figure=$3 goal=$4
    if ((figure > goal)); then
        printf '  %-5s %6d B, goal %6d B: OVER by %d B\n' "$measure" "$figure" "$goal" "$((figure - goal))"
        failures+=("$node $measure is $figure B, over its goal of $goal B by $((figure - goal)) B")
    else
        printf '  %-5s %6d B, goal %6d B: met, %d B to spare\n' "$measure" "$figure" "$goal" "$((goal - figure))"
    fi
}

printf '%-15s %7s %7s %5s %5s %7s %9s %7s\n' node .text .rodata .data .bss flash "+vectors" state
for row in "${NODES[@]}"; do
    read -r node symbol <<<"$row"
    flash_goal=$(goal "$node" 2)
    state_goal=$(goal "$node" 3)
    if [[ -z "$flash_goal" || -z "$state_goal" ]]; then
        echo "size.sh: no goal for $node in examples/firmware/$GOALS" >&2
        exit 1
    fi
    elf="target/$TARGET/release/$node"
    [[ -f "$elf" ]] || { echo "size.sh: $elf was not built" >&2; exit 1; }
    text=$(section "$elf" .text) || exit 1
    rodata=$(section "$elf" .rodata) || exit 1
    data=$(section "$elf" .data) || exit 1
    bss=$(section "$elf" .bss) || exit 1
    vectors=$(section "$elf" .vector_table) || exit 1
    flash=$((text + rodata + data))
    state_hex=$("$NM" --print-size "$elf" | awk -v s="$symbol" '$4 == s { print $2 }')
    [[ -n "$state_hex" ]] || { echo "size.sh: $symbol not found in $elf" >&2; exit 1; }
    state=$((16#$state_hex))
    printf '%-15s %7d %7d %5d %5d %7d %9s %7d\n' "$node" "$text" "$rodata" "$data" "$bss" \
        "$flash" "(+$vectors)" "$state"
    check "$node" flash "$flash" "$flash_goal"
    check "$node" state "$state" "$state_goal"
done

if ((${#failures[@]} > 0)); then
    for f in "${failures[@]}"; do
        echo "size.sh: FAIL: $f (examples/firmware/$GOALS)" >&2
    done
    exit 1
fi
echo "size.sh: every node within its goals (examples/firmware/$GOALS)"
