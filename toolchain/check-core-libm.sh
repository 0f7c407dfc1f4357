#!/usr/bin/env bash
# Fails if any core object calls a libm function whose rounding is not
# fixed by IEEE 754 (sin, cos, atan2, hypot, acos, ...): libm need not
# round them alike on x86-64, aarch64 and newlib, and every method must
# give the same bits on every target (docs/targets.md, "Same bits"). sqrt, floor, fabs,
# ldexp and frexp are exact or correctly rounded everywhere: allowed.
# Usage: check-core-libm.sh NM LIBRARY.a
set -euo pipefail
nm_tool=$1 lib=$2
# member:symbol for every undefined symbol of every member.
undefined=$("$nm_tool" -A -u "$lib" | sed -n 's/^[^:]*:\([^:]*\):.* U \(.*\)$/\1:\2/p')
[ -n "$undefined" ] || { echo "no undefined symbols read from $lib: nm failed?" >&2; exit 1; }
libm='(sin|cos|tan|sincos|asin|acos|atan|atan2|sinh|cosh|tanh|hypot|exp|exp2|expm1|log|log2|log10|log1p|pow|cbrt|erf|erfc|tgamma|lgamma)[fl]?(@.*)?'
calls=$(grep -E ":${libm}$" <<<"$undefined" || true)
if [ -n "$calls" ]; then
  echo "FAIL: libm calls in $lib (use common/angle.h):" >&2
  echo "$calls" >&2
  exit 1
fi
echo "ok: the core calls no libm function whose rounding may differ between targets"
