#!/usr/bin/env bash
# Builds the footprint firmware (examples/firmware: the battery module and
# the charger, each package with its own library features, for
# thumbv7em-none-eabihf, opt-level "z", LTO, panic=abort),
# prints each binary's sections and the size of the node's state (its
# static, from the symbol table), and fails when a node is more than 10%
# over the figures recorded in budget.txt.
#
#   bash examples/firmware/size.sh            build, print, compare
#   bash examples/firmware/size.sh --record   also write the figures to budget.txt
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

RECORD=0
for arg in "$@"; do
    case "$arg" in
        --record) RECORD=1 ;;
        *) echo "unknown argument: $arg" >&2; exit 2 ;;
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

# Each node is its own package with its own library features (Cargo.toml):
# built one at a time so that their features do not unify.
for package in battery-module-firmware charger-firmware; do
    cargo build --release --locked --quiet -p "$package"
done

# node binary, its state symbol, flash goal, state goal (bytes)
NODES=(
    "battery_module BATTERY_MODULE_STATE 14336 1024"
    "charger CHARGER_STATE 16384 1536"
)

section() { # binary section -> size (0 when absent)
    "$SIZE" -A "$1" | awk -v s="$2" '$1 == s { print $2; found = 1 } END { if (!found) print 0 }'
}
budget() { # node column -> recorded figure
    [[ -f budget.txt ]] || return 0
    awk -v n="$1" -v c="$2" '$1 == n { print $c }' budget.txt
}

status=0
new_budget=$'# Footprint budget of examples/firmware (bytes), written by size.sh --record.\n# CI fails when a node is more than 10% over its figure.\n# node flash(text+rodata+data) state'
printf '%-15s %7s %7s %5s %5s %7s %7s %7s %7s\n' node .text .rodata .data .bss vectors flash state budget
for row in "${NODES[@]}"; do
    read -r node symbol flash_goal state_goal <<<"$row"
    elf="target/$TARGET/release/$node"
    text=$(section "$elf" .text)
    rodata=$(section "$elf" .rodata)
    data=$(section "$elf" .data)
    bss=$(section "$elf" .bss)
    vectors=$(section "$elf" .vector_table)
    flash=$((text + rodata + data))
    state_hex=$("$NM" --print-size "$elf" | awk -v s="$symbol" '$4 == s { print $2 }')
    [[ -n "$state_hex" ]] || { echo "$symbol not found in $elf" >&2; exit 1; }
    state=$((16#$state_hex))
    rec_flash=$(budget "$node" 2)
    rec_state=$(budget "$node" 3)
    printf '%-15s %7d %7d %5d %5d %7d %7d %7d %7s\n' "$node" "$text" "$rodata" "$data" "$bss" \
        "$vectors" "$flash" "$state" "${rec_flash:-?}/${rec_state:-?}"
    printf '  goal: flash %d (%s), state %d (%s)\n' "$flash_goal" \
        "$([[ $flash -le $flash_goal ]] && echo met || echo 'not met')" "$state_goal" \
        "$([[ $state -le $state_goal ]] && echo met || echo 'not met')"
    new_budget+=$'\n'"$node $flash $state"
    if [[ -z "$rec_flash" || -z "$rec_state" ]]; then
        echo "  no figures for $node in budget.txt" >&2
        status=1
    elif ((flash * 10 > rec_flash * 11 || state * 10 > rec_state * 11)); then
        echo "  $node is more than 10% over budget.txt ($rec_flash flash, $rec_state state)" >&2
        status=1
    fi
done
if [[ $RECORD == 1 ]]; then
    printf '%s\n' "$new_budget" >budget.txt
    echo "recorded in examples/firmware/budget.txt"
    status=0
fi
exit "$status"
