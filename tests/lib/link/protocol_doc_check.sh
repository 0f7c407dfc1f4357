#!/usr/bin/env bash
# docs/protocol/serial.md must list every message of pitvol_link.proto's
# Message oneof with its tag, and the frame limits the code uses.
# usage: protocol_doc_check.sh PROTO DOC GENERATED_PB_H
set -euo pipefail
proto=$1 doc=$2 pbh=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
# Lines "    Hello hello = 1;" inside "oneof body { ... }".
entries=$(awk '/oneof body/ {on=1; next} on && /}/ {on=0} on && /=/ {gsub(";", ""); print $1, $4}' "$proto")
[ -n "$entries" ] || fail "no oneof entries found in $proto"
n=0
while read -r name tag; do
  grep -q "^| $tag | \`$name\` |" "$doc" || fail "$doc lacks the row '| $tag | \`$name\` |'"
  n=$((n + 1))
done <<<"$entries"
size=$(sed -n 's/^#define pitvol_Message_size *\([0-9]*\)/\1/p' "$pbh")
grep -q "payload | 0 .. $size " "$doc" || fail "$doc: payload size is not $size"
raw=$((size + 9)); cobs=$((raw + raw / 254 + 1)); wire=$((cobs + 2))
grep -q "\*\*$wire\*\*" "$doc" || fail "$doc: largest wire frame is not $wire"
echo "PASS: $n messages, payload <= $size, frame <= $wire bytes"
