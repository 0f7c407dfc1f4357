#!/usr/bin/env bash
# Fails if a static library references the heap or exception machinery:
# the MCU core must run in its block alone (docs/targets.md).
# Usage: check_no_heap.sh NM LIBRARY.a
set -euo pipefail
nm_tool=$1 lib=$2
undefined=$("$nm_tool" -u --demangle "$lib" | awk '{print $NF}' | sort -u)
[ -n "$undefined" ] || { echo "no undefined symbols read from $lib: nm failed?" >&2; exit 1; }
bad=$(grep -E '^(malloc|calloc|realloc|free|aligned_alloc|posix_memalign|_malloc_r|_free_r|operator new|operator delete|__cxa_allocate_exception|__cxa_throw|__cxa_begin_catch|__gxx_personality_v0|std::__throw_)' <<<"$undefined" || true)
if [ -n "$bad" ]; then
  echo "FAIL: $lib references:" >&2
  echo "$bad" >&2
  exit 1
fi
echo "ok: $(wc -l <<<"$undefined") undefined symbols in $lib, none of the heap or exceptions"
